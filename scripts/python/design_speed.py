#!/usr/bin/env python3
"""Issue 40's speed figure: one evaluation of a designed reflector of about
10^4 triangles at 2*10^5 photons, setup included (gonio.Design.set, then
gonio.simulate of the Design in memory: tessellation, scene, checks, trace,
candela table), against gonio.simulate of the downlight sample (its glTF
file) with the same photons, interleaved in the same run so that both see
the same load.

    PYTHONPATH=build/tools/python /usr/bin/python3 scripts/python/design_speed.py [ROUNDS] [--no-cache]

Prints, per model, the best and the median wall time per call and the median
trace time (SimulationResult.trace_s), and the ratio of the medians. The
design's triangles are counted once by `gonio simulate` (report.json's cad
section) when build/tools/gonio exists.
"""
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import gonio

root = pathlib.Path(__file__).resolve().parents[2]
downlight = root / "build" / "samples" / "downlight" / "downlight.gltf"
rounds = int(sys.argv[1]) if len(sys.argv) > 1 and sys.argv[1].isdigit() else 10
RUN = dict(photons=200_000, iterations=1, seed=1, threads=0, gamma_step=2.5,
           cache="--no-cache" not in sys.argv)

# A paraboloid around an isotropic point source at its focus; at the default
# 2.5° grid (δ = 2°, rows every 0.5° of tangent turn, azimuth every 2°) its
# 6…12 mm aperture is about 10^4 triangles.
DESIGN = """length_unit = "mm"

[materials.mirror]
mirror = 0.92

[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000

[[reflectors]]
name = "dish"
material = "mirror"
profile = "conic"
radius = { value = 20, min = 10, max = 40, name = "R" }
conic = -1
vertex = 10
aperture = [6, 12]
"""


def main():
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "speed.design.toml"
        path.write_text(DESIGN)
        exe = root / "build" / "tools" / "gonio"
        if exe.exists():
            subprocess.run([str(exe), "simulate", str(path), "--photons", "200000", "--iterations", "1", "--out",
                            str(pathlib.Path(tmp) / "run"), "--format", "ies", "--no-cache"],
                           check=False, capture_output=True)
            report = json.loads((pathlib.Path(tmp) / "run" / "report.json").read_text())
            print("design triangles:", report["design_file"]["triangles_unique"])
        design = gonio.Design(path)
        gonio.simulate(design, **RUN)  # warm: the module, the resampler
        gonio.simulate(downlight, **RUN)
        wall = {"design": [], "downlight": []}
        trace = {"design": [], "downlight": []}
        for i in range(rounds):
            design.set("R", 20.0 + 0.01 * i)  # a new value each evaluation, as an optimiser sets
            t = time.perf_counter()
            r = gonio.simulate(design, **RUN)
            wall["design"].append(time.perf_counter() - t)
            trace["design"].append(r.trace_s)
            t = time.perf_counter()
            r = gonio.simulate(downlight, **RUN)
            wall["downlight"].append(time.perf_counter() - t)
            trace["downlight"].append(r.trace_s)
        for k in wall:
            print(f"{k}: best {min(wall[k]):.4f} s, median {statistics.median(wall[k]):.4f} s per call, "
                  f"median trace {statistics.median(trace[k]):.4f} s, beyond the trace "
                  f"{statistics.median(wall[k]) - statistics.median(trace[k]):.4f} s ({rounds} rounds)")
        print(f"ratio design/downlight (medians): {statistics.median(wall['design']) / statistics.median(wall['downlight']):.3f}")


if __name__ == "__main__":
    main()
