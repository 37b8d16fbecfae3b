#!/usr/bin/env python3
"""The methods chart of gonio optimize (docs/design.md, "Methods compared").

The conic-recovery case of docs/design.md ("A conic constant recovered"): a
point source shining up (Lambertian toward the zenith, 1000 lm) under a conic
dish (R = 10 mm at the vertex, 5 mm above the source, rho 2..30 mm,
reflectance 0.9, a white Lambertian dish); the target is `gonio simulate` of the dish at kappa = -1.5
(10^6 photons, 2.5 deg gamma step); every run starts at kappa = -2.6 within
[-3, -1] with --gamma-step 5. Each method (BOBYQA, COBYLA, Nelder-Mead,
CMA-ES) runs with common random numbers and smooth binning, with neither,
and with each alone. Writes into OUT: the runs' folders, methods.json (one
row a run), methods.md (the table) and methods.svg (merit against
evaluations and against wall time, drawn by gnuplot as the project's charts
are).

  python3 scripts/optimize_methods.py [--gonio build/tools/gonio] [--out DIR]
      [--max-evals N] [--final-photons N] [--methods bobyqa,cobyla,...] [--seeds S]

Each configuration runs with seeds 1..S (--seed of gonio optimize: other
photons for the stages, another sampling for CMA-ES); the table gives the
median and worst distance of the kappa found from -1.5, the mean
evaluations and wall time, and the median final RMS of gonio compare
(--normalize, 5 deg grid) of the best design's final trace against the
target, the same measure for every run. The chart draws seed 1's runs.
"""
import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import time

DESIGN = """length_unit = "mm"
[materials.mirror]
reflectance = 0.9
[[emitters]]
name = "LED"
position = [0, 0, 0]
profile = "up.ies"
[[reflectors]]
name = "dish"
material = "mirror"
profile = "conic"
radius = 10
conic = {conic}
vertex = 5
aperture = [2, 30]
"""


def write_emitter(path):
    gammas = [2.5 * i for i in range(73)]
    cd = [0.0 if g <= 90.0 else -318.31 * math.cos(math.radians(g)) for g in gammas]
    lines = ["IESNA:LM-63-2002", "[TEST] point source shining up, 1000 lm", "TILT=NONE",
             "1 -1 1 %d 1 1 2 0 0 0" % len(gammas), "1 1 0",
             " ".join("%g" % g for g in gammas), "0", " ".join("%.6g" % c for c in cd)]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def run(cmd):
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    # 3: gonio optimize wrote every file but could not improve the design
    # (docs/commands/optimize.md "Exit codes"): a result to chart, not a failure.
    if p.returncode not in (0, 3):
        sys.exit("failed: %s\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    return time.time() - t, p.stdout


VARIANTS = [("crn+smooth", []), ("crn", ["--no-smooth"]), ("smooth", ["--no-common-random"]),
            ("neither", ["--no-smooth", "--no-common-random"])]


def with_kappa(stage):
    """(index, best, time, |kappa - (-1.5)| of the best so far) per evaluation."""
    out, kappa = [], float("nan")
    for e in stage:
        if e["merit"] is not None and e["best"] is not None and e["merit"] == e["best"]:
            kappa = e["values"]["reflectors[0].conic"]
        out.append((e["index"], e["best"], e["time_s"], abs(kappa + 1.5)))
    return out


def gnuplot_chart(rows, path):
    """Three panels: the best merit so far against evaluations and against
    wall time, and how far the best so far's kappa is from the target's."""
    data = path + ".dat"
    with open(data, "w") as f:
        for r in rows:
            f.write("# %s %s\n" % (r["method"], r["variant"]))
            for e in r["history"]:
                f.write("%d %.6g %.6g %.6g\n" % e)
            f.write("\n\n")
    colours = {"bobyqa": "#1f77b4", "cobyla": "#d62728", "neldermead": "#2ca02c", "cmaes": "#9467bd"}
    dashes = {"crn+smooth": 1, "crn": 2, "smooth": 3, "neither": 4}
    plots_e, plots_t, plots_k = [], [], []
    for i, r in enumerate(rows):
        style = "lc rgb '%s' dt %d lw 1.5" % (colours.get(r["method"], "black"), dashes[r["variant"]])
        title = "%s, %s" % (r["method"], r["variant"])
        plots_e.append("'%s' index %d using 1:2 with steps %s title '%s'" % (data, i, style, title))
        plots_t.append("'%s' index %d using 3:2 with steps %s notitle" % (data, i, style))
        plots_k.append("'%s' index %d using 1:4 with steps %s notitle" % (data, i, style))
    script = "\n".join([
        "set terminal svg size 1800,700 font 'DejaVu Sans,11' background '#ffffff'",
        "set output '%s'" % path,
        "set multiplot layout 1,3 title 'gonio optimize: the conic dish from kappa = -2.6 toward the target at -1.5 (best merit so far)'",
        "set logscale y", "set grid", "set key outside bottom center horizontal maxrows 4 font ',9'",
        "set xlabel 'evaluation'", "set ylabel 'best merit (candela RMS, % of the peak)'",
        "plot " + ", ".join(plots_e),
        "set xlabel 'wall time [s] (2 loaded cores)'", "unset key",
        "plot " + ", ".join(plots_t),
        "set xlabel 'evaluation'", "set ylabel '|kappa - (-1.5)| of the best so far'",
        "plot " + ", ".join(plots_k),
        "unset multiplot", ""])
    subprocess.run([os.environ.get("GONIO_GNUPLOT", "gnuplot")], input=script, text=True, check=True)
    os.remove(data)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gonio", default="build/tools/gonio")
    ap.add_argument("--out", default="build/optimize-methods")
    ap.add_argument("--max-evals", type=int, default=120)
    ap.add_argument("--final-photons", type=int, default=100000)
    ap.add_argument("--methods", default="bobyqa,cobyla,neldermead,cmaes")
    ap.add_argument("--variants", default=",".join(v for v, _ in VARIANTS))
    ap.add_argument("--seeds", type=int, default=1)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    write_emitter(os.path.join(a.out, "up.ies"))
    with open(os.path.join(a.out, "truth.design.toml"), "w") as f:
        f.write(DESIGN.format(conic="-1.5"))
    with open(os.path.join(a.out, "start.design.toml"), "w") as f:
        f.write(DESIGN.format(conic="{ value = -2.6, min = -3, max = -1 }"))
    target = os.path.join(a.out, "truth", "truth.ies")
    if not os.path.exists(target):
        run([a.gonio, "simulate", os.path.join(a.out, "truth.design.toml"), "--out", os.path.join(a.out, "truth"),
             "--photons", "1000000", "--iterations", "1", "--gamma-step", "2.5", "--format", "ies", "--no-cache"])
    rows = []
    wanted = a.variants.split(",")
    for method in a.methods.split(","):
        for variant, flags in VARIANTS:
            if variant not in wanted:
                continue
            for seed in range(1, a.seeds + 1):
                out = os.path.join(a.out, "%s-%s-%d" % (method, variant, seed))
                cmd = [a.gonio, "optimize", os.path.join(a.out, "start.design.toml"), "--target", target, "--out",
                       out, "--method", method, "--gamma-step", "5", "--max-evals", str(a.max_evals),
                       "--final-photons", str(a.final_photons), "--no-step", "--seed", str(seed)] + flags
                wall, _ = run(cmd)
                o = json.load(open(os.path.join(out, "report.json")))["optimize"]
                h = json.load(open(os.path.join(out, "history.json")))
                stage = [e for e in h if e["stage"] != "noise"]
                rows.append({
                    "method": method, "variant": variant, "seed": seed, "command": " ".join(cmd[1:]),
                    "kappa": o["variables"][0]["best"], "evaluations": o["evaluations"],
                    "stopped_by": o["stopped_by"], "best_merit": o["best_merit"],
                    "independent_merit": o["independent_merit"], "noise_floor": o["noise_floor"],
                    "final_merit_rms_pct": o["final"]["candela_rms_pct"],
                    "compare_rms_pct": 100.0 * o["compare"]["rms_relative"], "wall_s": wall,
                    "history": with_kappa(stage)})
                r = rows[-1]
                print("%-10s %-11s seed %d: kappa %.4f  %3d evals  compare RMS %.2f %%  %.1f s" % (
                    method, variant, seed, r["kappa"], r["evaluations"], r["compare_rms_pct"], wall), flush=True)
    json.dump({"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "machine": platform.node(),
               "cpus": os.cpu_count(), "load": os.getloadavg(), "runs": rows},
              open(os.path.join(a.out, "methods.json"), "w"), indent=1)
    with open(os.path.join(a.out, "methods.md"), "w") as f:
        f.write("| method | CRN | smooth | median \\|κ + 1.5\\| | worst | evaluations (mean) | "
                "final RMS vs target [% of peak] (median) | wall (mean) |\n")
        f.write("|---|---|---|---|---|---|---|---|\n")
        for method in a.methods.split(","):
            for variant, _ in VARIANTS:
                runs = [r for r in rows if r["method"] == method and r["variant"] == variant]
                if not runs:
                    continue
                err = [abs(r["kappa"] + 1.5) for r in runs]
                f.write("| %s | %s | %s | %.4f | %.4f | %.0f | %.2f | %.1f s |\n" % (
                    method, "yes" if "crn" in variant else "no", "yes" if "smooth" in variant else "no",
                    statistics.median(err), max(err), statistics.mean(r["evaluations"] for r in runs),
                    statistics.median(r["compare_rms_pct"] for r in runs),
                    statistics.mean(r["wall_s"] for r in runs)))
    gnuplot_chart([r for r in rows if r["seed"] == 1], os.path.join(a.out, "methods.svg"))
    print("wrote", os.path.join(a.out, "methods.md"), os.path.join(a.out, "methods.svg"))


if __name__ == "__main__":
    main()
