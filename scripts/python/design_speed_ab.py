#!/usr/bin/env python3
"""Issue 40's speed figure for two builds in one run: the evaluation of
design_speed.py (Design.set of the paraboloid's radius, then gonio.simulate
of the 10 440-triangle design at 2*10^5 photons, setup included), with and
without `out` (formats="ies"), timed in worker processes that alternate
between the builds' Python modules, so that both see the same load.

    /usr/bin/python3 scripts/python/design_speed_ab.py BASE_MODULE_DIR BRANCH_MODULE_DIR [--rounds N] [--repeats K] [--threads T]

BASE_MODULE_DIR and BRANCH_MODULE_DIR are what PYTHONPATH would name
(build/tools/python of each build). Each of the K repeats runs, for each
build in turn, one worker that warms up and times N calls of each kind.
Prints per build and kind the median call, the median trace (trace_s) and
its share, the part beyond the trace, and the ratio branch/base of the
median calls.
"""
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent


def worker(rounds, threads):
    import gonio
    sys.path.insert(0, str(HERE))
    from design_speed import DESIGN
    run = dict(photons=200_000, iterations=1, seed=1, threads=threads, gamma_step=2.5)
    out = {"bare": [], "out": []}
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "speed.design.toml"
        path.write_text(DESIGN)
        design = gonio.Design(path)
        gonio.simulate(design, out=pathlib.Path(tmp) / "warm", formats="ies", **run)
        for i in range(rounds):
            for kind in ("bare", "out"):
                design.set("R", 20.0 + 0.01 * i)
                extra = dict(out=pathlib.Path(tmp) / f"{kind}{i}", formats="ies") if kind == "out" else {}
                t = time.perf_counter()
                r = gonio.simulate(design, **run, **extra)
                out[kind].append((time.perf_counter() - t, r.trace_s))
    print(json.dumps(out))


def main():
    args = sys.argv[1:]
    if args and args[0] == "--worker":
        worker(int(args[1]), int(args[2]))
        return

    def option(name, default):
        if name in args:
            i = args.index(name)
            value = args[i + 1]
            del args[i:i + 2]
            return int(value)
        return default

    rounds, repeats, threads = option("--rounds", 5), option("--repeats", 4), option("--threads", 0)
    if len(args) != 2:
        sys.exit(__doc__)
    builds = {"base": args[0], "branch": args[1]}
    calls = {(b, k): [] for b in builds for k in ("bare", "out")}
    for _ in range(repeats):
        for b, module_dir in builds.items():
            env = dict(os.environ, PYTHONPATH=module_dir, PYTHONDONTWRITEBYTECODE="1")
            text = subprocess.run([sys.executable, __file__, "--worker", str(rounds), str(threads)], env=env,
                                  check=True, capture_output=True, text=True).stdout
            for k, v in json.loads(text).items():
                calls[(b, k)].extend(v)
    print(f"threads={threads}, {repeats} x {rounds} calls per build and kind, alternating builds")
    for k in ("bare", "out"):
        med = {}
        for b in builds:
            wall = statistics.median(w for w, _ in calls[(b, k)])
            trace = statistics.median(t for _, t in calls[(b, k)])
            med[b] = wall
            print(f"{k:4s} {b:6s}: call {wall:.4f} s (best {min(w for w, _ in calls[(b, k)]):.4f}), "
                  f"trace {trace:.4f} s ({100 * trace / wall:.0f} %), beyond {wall - trace:.4f} s")
        print(f"{k:4s} ratio branch/base of the median calls: {med['branch'] / med['base']:.3f}")


if __name__ == "__main__":
    main()
