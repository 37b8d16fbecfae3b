#!/usr/bin/env python3
"""Where one evaluation's time goes (issue 40's speed figure, see
design_speed.py): the design of design_speed.py, set to a new radius each
round, simulated with `out` (report.json's "setup" section: load, model
checks, shading, BVH, emission tables; its "trace_s"; `formats="ies"`) and
the wall time of the call around it; the rest is the loop's own (the
resampler, the candela table, writing the file).

    PYTHONPATH=build/tools/python /usr/bin/python3 scripts/python/design_speed_breakdown.py [ROUNDS]

Prints the median of each part over the rounds, in seconds and as a share of
the call.
"""
import pathlib
import statistics
import sys
import tempfile
import time

import gonio

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from design_speed import DESIGN  # noqa: E402

rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 10
RUN = dict(photons=200_000, iterations=1, seed=1, threads=0, gamma_step=2.5, formats="ies")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "speed.design.toml"
        path.write_text(DESIGN)
        design = gonio.Design(path)
        gonio.simulate(design, out=pathlib.Path(tmp) / "warm", **RUN)
        parts = {}
        for i in range(rounds):
            design.set("R", 20.0 + 0.01 * i)
            t = time.perf_counter()
            r = gonio.simulate(design, out=pathlib.Path(tmp) / f"run{i}", **RUN)
            wall = time.perf_counter() - t
            setup = r.report["setup"]
            row = {"call": wall, "trace": r.report["trace_s"], "tessellate": r.report["design_file"]["tessellate_s"]}
            for k in ("load_s", "check_s", "shading_s", "bvh_s", "emission_tables_s", "validate_s"):
                row[k[:-2]] = setup.get(k, 0.0)
            row["load (beyond tessellation)"] = row["load"] - row["tessellate"]
            # Simulation::create's whole time: shading, BVH, emission tables, and the next-event pilot.
            row["simulation setup"] = r.report.get("setup_s", 0.0)
            row["setup beyond its parts (pilot)"] = row["simulation setup"] - sum(
                setup.get(k, 0.0) for k in ("shading_s", "bvh_s", "emission_tables_s", "validate_s"))
            row["rest"] = wall - row["trace"] - row["simulation setup"] - row["load"] - row["check"]
            for k, v in row.items():
                parts.setdefault(k, []).append(v)
        # The same calls without `out`: no files, no report.json.
        bare = []
        for i in range(rounds):
            design.set("R", 20.0 + 0.01 * i)
            t = time.perf_counter()
            b = gonio.simulate(design, **{k: v for k, v in RUN.items() if k != "formats"})
            bare.append((time.perf_counter() - t, b.trace_s))
        parts["call without out"] = [w for w, _ in bare]
        parts["trace without out"] = [t for _, t in bare]
        call = statistics.median(parts["call"])
        for k, v in parts.items():
            m = statistics.median(v)
            print(f"{k:28s} {m:.4f} s  {100 * m / call:5.1f} %")
        print(f"({rounds} rounds, triangles {r.report['design_file']['triangles_unique']})")


if __name__ == "__main__":
    main()
