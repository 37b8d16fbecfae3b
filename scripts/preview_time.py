#!/usr/bin/env python3
"""Issue 43's live-loop figure: the time from a model having been read to the
first filtered preview of `gonio watch` (state.json's read_to_preview_s), with
the glossy energy tables built in the run (cold: their cache entries removed
before it) and read from the cache folder (warm), interleaved in one run so
that both see the same load.

    python3 scripts/preview_time.py [ROUNDS] [--gonio PATH] [--model PATH]

Defaults: 8 rounds, build/tools/gonio, build/samples/bell/bell.gltf. The cache
folder is a fresh temporary one, filled once before the rounds (so a cold run
rebuilds only the energy tables; the model checks and the resampler are read).
Prints each run's figure and the medians.
"""
import argparse
import json
import pathlib
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

root = pathlib.Path(__file__).resolve().parents[1]
ap = argparse.ArgumentParser()
ap.add_argument("rounds", nargs="?", type=int, default=8)
ap.add_argument("--gonio", default=str(root / "build" / "tools" / "gonio"))
ap.add_argument("--model", default=str(root / "build" / "samples" / "bell" / "bell.gltf"))
args = ap.parse_args()


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def first_preview(cache, cold):
    if cold:
        for f in pathlib.Path(cache).glob("glossy-energy-*"):
            f.unlink()
    port = free_port()
    p = subprocess.Popen([args.gonio, "watch", args.model, "--port", str(port), "--cache", cache],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        deadline = time.time() + 60
        while time.time() < deadline:
            if p.poll() is not None:
                sys.exit(f"gonio watch ended early: {p.stderr.read().decode(errors='replace')}")
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/state.json", timeout=1) as r:
                    state = json.load(r)
                if state.get("iteration", 0) >= 1:
                    return state["read_to_preview_s"]
            except (OSError, ValueError):
                pass
            time.sleep(0.01)
        sys.exit("no preview within 60 s")
    finally:
        p.terminate()
        p.wait()


with tempfile.TemporaryDirectory() as cache:
    first_preview(cache, False)
    runs = {"cold": [], "warm": []}
    for _ in range(args.rounds):
        for kind in runs:
            runs[kind].append(first_preview(cache, kind == "cold"))
    for kind, v in runs.items():
        print(f"{kind}: " + ", ".join(f"{x:.3f}" for x in v) + f"  median {statistics.median(v):.3f} s")
