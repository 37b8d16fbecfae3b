#!/usr/bin/env python3
"""The worked example of docs/python.md: a sweep of one reflector parameter
through gonio.simulate, plotted with matplotlib.

The downlight sample (an LED at the focus of an aluminium paraboloid) is
simulated with its reflector's roughness (glTF roughnessFactor: the width of
the Beckmann lobe the glossy reflection draws from) set to each value of
ROUGHNESS; for each run the C0-C180 intensity curve and the beam angle come
from the result's candela table (result.photometry, the table the IES file
holds; gamma every 1 degree, C every 5). Writes docs/python/reflector-sweep.svg and prints the table
docs/python.md shows.

    PYTHONPATH=build/tools/python python3 scripts/python/reflector_sweep.py [PHOTONS]

(the build's samples in build/samples; PHOTONS per run, default 2000000, in
4 iterations, seed 1).
"""
import json
import pathlib
import shutil
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import gonio  # noqa: E402

ROUGHNESS = [0.05, 0.1, 0.2, 0.3, 0.45, 0.6]

root = pathlib.Path(__file__).resolve().parents[2]
sample = root / "build" / "samples" / "downlight"
figure = root / "docs" / "python" / "reflector-sweep.svg"
photons = int(float(sys.argv[1])) if len(sys.argv) > 1 else 2_000_000


def with_roughness(folder: pathlib.Path, roughness: float) -> pathlib.Path:
    """A copy of the downlight whose reflector material has this roughness."""
    model = json.loads((sample / "downlight.gltf").read_text())
    reflector = next(m for m in model["materials"] if "aluminium" in m["name"])
    reflector["pbrMetallicRoughness"]["roughnessFactor"] = roughness
    for f in sample.iterdir():
        if f.name != "downlight.gltf":
            shutil.copy(f, folder / f.name)
    path = folder / f"downlight-r{roughness:g}.gltf"
    path.write_text(json.dumps(model))
    return path


rows = []
fig, (curves, beams) = plt.subplots(1, 2, figsize=(10, 4.2), gridspec_kw={"width_ratios": [3, 2]})
with tempfile.TemporaryDirectory() as tmp:
    for r in ROUGHNESS:
        model = with_roughness(pathlib.Path(tmp), r)
        result = gonio.simulate(model, photons=photons // 4, iterations=4, seed=1, gamma_step=1.0)
        table = result.photometry
        s = table.summary()
        # C0 and C180 planes, gamma 0..90: one curve across the beam.
        c = table.horizontal_deg
        g = table.vertical_deg
        i0 = table.candela[int(np.argmin(np.abs(c - 0.0)))]
        i180 = table.candela[int(np.argmin(np.abs(c - 180.0)))] if c[-1] >= 180.0 else i0
        down = g <= 90.0
        angle = np.concatenate([-g[down][::-1], g[down][1:]])
        intensity = np.concatenate([i180[down][::-1], i0[down][1:]])
        curves.semilogy(angle, np.maximum(intensity, 1e-3), label=f"roughness {r:g}")
        rows.append((r, s["max_cd"], s["beam"]["c0_c180"]["angle_deg"], s["field"]["c0_c180"]["angle_deg"],
                     s["flux_lm"], result.estimated_rms_error_pct))
curves.set_xlabel("angle from nadir in C0-C180 [deg]")
curves.set_ylabel("intensity [cd]")
curves.set_xlim(-90, 90)
curves.set_ylim(1, None)
curves.grid(alpha=0.3)
curves.legend(fontsize=8)
curves.set_title("downlight, C0-C180")
beams.plot([r[0] for r in rows], [r[2] for r in rows], "o-", label="beam (50 %)")
beams.plot([r[0] for r in rows], [r[3] for r in rows], "s-", label="field (10 %)")
beams.set_xlabel("reflector roughness (glTF roughnessFactor)")
beams.set_ylabel("angle [deg]")
beams.grid(alpha=0.3)
beams.legend(fontsize=8)
beams.set_title(f"{photons:,} photons per run")
fig.tight_layout()
figure.parent.mkdir(parents=True, exist_ok=True)
plt.rcParams["svg.hashsalt"] = "gonio"  # the same file for the same figures
fig.savefig(figure, metadata={"Date": None})
print(f"wrote {figure.relative_to(root)}")
print("| roughness | peak [cd] | beam C0-C180 [deg] | field C0-C180 [deg] | flux [lm] | estimated RMS error [%] |")
print("|---|---|---|---|---|---|")
for r, peak, beam, field, flux, err in rows:
    print(f"| {r:g} | {peak:.0f} | {beam:.1f} | {field:.1f} | {flux:.1f} | {err:.2g} |")
