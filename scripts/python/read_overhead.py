#!/usr/bin/env python3
"""The cost of gonio.read on a small file, for docs/python.md: per call,
against reading the same bytes with open() and against the command
(`gonio info --json` as a process, what a script had before the module).

    PYTHONPATH=build/tools/python python3 scripts/python/read_overhead.py [FILE] [CALLS]

Default FILE samples/curves/downlight.ies (37 gamma angles, one plane),
CALLS 2000. Prints wall and CPU (process_time) microseconds per call, the
best of 5 rounds for each way, interleaved.
"""
import os
import pathlib
import subprocess
import sys
import time

import gonio

root = pathlib.Path(__file__).resolve().parents[2]
path = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else root / "samples" / "curves" / "downlight.ies"
calls = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
exe = os.environ.get("GONIO_EXECUTABLE", str(root / "build" / "tools" / "gonio"))


def per_call(fn, n):
    w0, c0 = time.perf_counter(), time.process_time()
    for _ in range(n):
        fn()
    return (time.perf_counter() - w0) / n * 1e6, (time.process_time() - c0) / n * 1e6


def open_read():
    with open(path, "rb") as f:
        f.read()


ways = {
    "open(path).read() (the bytes alone)": (open_read, calls),
    "gonio.read(path)": (lambda: gonio.read(path), calls),
    "gonio.read(path).summary()": (lambda: gonio.read(path).summary(), calls),
    "gonio.read(path).info() (every figure)": (lambda: gonio.read(path).info(), calls // 10),
    "gonio info --json PATH (a process)": (
        lambda: subprocess.run([exe, "info", "--json", str(path)], capture_output=True, check=True),
        max(calls // 100, 5),
    ),
}
best = {k: (float("inf"), float("inf")) for k in ways}
for _ in range(5):
    for name, (fn, n) in ways.items():
        wall, cpu = per_call(fn, n)
        best[name] = (min(best[name][0], wall), min(best[name][1], cpu))
print(f"{path.name} ({path.stat().st_size} bytes), best of 5 rounds; load average {os.getloadavg()}")
print("| call | wall µs per call | CPU µs per call (this process) |")
print("|---|---|---|")
for name, (wall, cpu) in best.items():
    print(f"| {name} | {wall:.1f} | {cpu:.1f} |")
