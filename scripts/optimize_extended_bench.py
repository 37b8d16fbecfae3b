#!/usr/bin/env python3
"""Issue 41's speed case, measured: from the direct design for an extended
emitter to <= 2 % RMS of the target's peak, within 5 minutes on 2 cores
(docs/design.md, "From a direct design to an extended emitter").

1. `gonio design reflector` designs a reflector for a point source shining up
   (Lambertian toward the zenith, 1000 lm) and the target cos^30 within 25 deg
   (`--target cos:30,25 --cone 90,180 --nodes 9`: 9 polar radii, each a
   variable within 0.8 ... 1.25 of its value).
2. The emitter is replaced by an extended one: 7 dies of 1000/7 lm each, one
   at the centre and six on a circle of radius R (default 5 mm) about it,
   against the reflector's 20 mm at the zenith: the point-source design
   misses.
3. `gonio optimize` the 9 radii toward the target (BOBYQA, the defaults,
   `--gamma-step 2.5 --max-time 300 --final-photons 1000000`; at 5 deg the
   final trace of this narrow beam can fail its energy check).

Printed and written to OUT/bench.json: the design's RMS with the extended
emitter before and after, both as `gonio compare --normalize` gives it (the
target's peak; solid-angle weighted over the sphere) and as the merit's
candela RMS (unweighted over its 5 deg gamma nodes, so the beam counts
more), and the wall time of the optimisation.

  python3 scripts/optimize_extended_bench.py [--gonio build/tools/gonio] [--out DIR] [--radius MM]
      [--method bobyqa|cobyla|neldermead|cmaes] [--max-evals N] [--max-time S]
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time


def run(cmd):
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    # 3: gonio optimize wrote every file but could not improve the design
    # (docs/commands/optimize.md "Exit codes"): a result to chart, not a failure.
    if p.returncode not in (0, 3):
        sys.exit("failed: %s\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    return time.time() - t, p.stdout


def write_emitter(path):
    gammas = [2.5 * i for i in range(73)]
    cd = [0.0 if g <= 90.0 else -318.31 * math.cos(math.radians(g)) for g in gammas]
    with open(path, "w") as f:
        f.write("\n".join(["IESNA:LM-63-2002", "[TEST] point source shining up, 1000 lm", "TILT=NONE",
                           "1 -1 1 %d 1 1 2 0 0 0" % len(gammas), "1 1 0", " ".join("%g" % g for g in gammas), "0",
                           " ".join("%.6g" % c for c in cd)]) + "\n")


def compare_rms(gonio, target, traced):
    _, out = run([gonio, "compare", target, traced, "--json", "--normalize"])
    return 100.0 * json.loads(out)["rms_relative"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gonio", default="build/tools/gonio")
    ap.add_argument("--out", default="build/optimize-extended")
    ap.add_argument("--radius", type=float, default=5.0)
    ap.add_argument("--max-time", default="300")
    ap.add_argument("--method", default="bobyqa")
    ap.add_argument("--max-evals", default="400")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    up = os.path.join(a.out, "up.ies")
    write_emitter(up)
    d = os.path.join(a.out, "design")
    run([a.gonio, "design", "reflector", "--emitter", up, "--target", "cos:30,25", "--cone", "90,180", "--nodes", "9",
         "--out", d, "--gamma-step", "2.5", "--photons", "200000"])
    text = open(os.path.join(d, "reflector.design.toml")).read()
    point = '[[emitters]]\nname = "emitter"\nposition = [0.0, 0.0, 0.0]\nprofile = "emitter.ies"\n'
    if point not in text:
        sys.exit("the designed file's emitter is not as expected")
    dies = [(0.0, 0.0)] + [(a.radius * math.cos(math.pi * k / 3), a.radius * math.sin(math.pi * k / 3))
                           for k in range(6)]
    emitters = "\n".join('[[emitters]]\nname = "die%d"\nposition = [%.6f, %.6f, 0.0]\nprofile = "emitter.ies"\n'
                         'flux_lm = %.9g\n' % (i, x, y, 1000.0 / 7.0) for i, (x, y) in enumerate(dies))
    extended = os.path.join(d, "extended.design.toml")
    open(extended, "w").write(text.replace(point, emitters))
    target = os.path.join(d, "target.ies")
    before = os.path.join(a.out, "before")
    run([a.gonio, "simulate", extended, "--out", before, "--photons", "1000000", "--iterations", "1",
         "--gamma-step", "2.5", "--format", "ies", "--no-cache"])
    rms_before = compare_rms(a.gonio, target, os.path.join(before, "extended.ies"))
    out = os.path.join(a.out, "optimized")
    cmd = [a.gonio, "optimize", extended, "--target", target, "--out", out, "--max-time", a.max_time,
           "--max-evals", a.max_evals, "--method", a.method, "--gamma-step", "2.5", "--final-photons", "1000000", "--no-step"]
    wall, _ = run(cmd)
    o = json.load(open(os.path.join(out, "report.json")))["optimize"]
    history = [e for e in json.load(open(os.path.join(out, "history.json"))) if e["stage"] != "noise"]
    rms_after = 100.0 * o["compare"]["rms_relative"]
    result = {
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "load": os.getloadavg(), "cpus": os.cpu_count(),
        "command": " ".join(cmd[1:]), "radius_mm": a.radius,
        "compare_rms_pct_before": rms_before, "compare_rms_pct_after": rms_after,
        "merit_start": o["start_merit"], "merit_best": o["best_merit"],
        "merit_candela_rms_pct_final": o["final"]["candela_rms_pct"], "evaluations": o["evaluations"],
        "stopped_by": o["stopped_by"], "search_s": history[-1]["time_s"], "wall_s": wall,
        "reached_2pct": rms_after <= 2.0}
    json.dump(result, open(os.path.join(a.out, "bench.json"), "w"), indent=1)
    print("extended emitter (7 dies within %.3g mm): gonio compare RMS %.2f %% -> %.2f %% of the target's peak; "
          "merit candela RMS %.2f -> final %.2f %%; %d evaluations (%s), search %.1f s, wall %.1f s%s" % (
              a.radius, rms_before, rms_after, o["start_merit"], o["final"]["candela_rms_pct"], o["evaluations"],
              o["stopped_by"], result["search_s"], wall, "" if result["reached_2pct"] else "  (NOT within 2 %)"))


if __name__ == "__main__":
    main()
