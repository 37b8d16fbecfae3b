#!/usr/bin/env python3
"""Time to the same candela error on the peer's LED-in-a-tube scene.

    scripts/peer_tube_bench.py --gonio BUILD/tools/gonio [--gonio NAME=BIN]...
        [--make-samples BUILD/samples/gonio_make_samples] [--peer PEER_BIN]
        [--photons-log2 16,17,...] [--reference-log2 25] [--target-photons 1e7]
        [--modes default,none,on] [--rounds 1] [--threads 1] [--work DIR]

The scene is eulumdat-goniosim's led_with_housing(1000 lm, 120 deg) rebuilt in
Gonio (samples/peer_scenes.h; `gonio_make_samples --peer DIR` writes it).
docs/validation.md "The peer's led_with_housing (issue 43)" gives the figures.

Each tool's table is a 5 x 2.5 deg C-gamma grid (C 0..355, gamma 0..180, 72 x
73 points) in cd for 1000 lm emitted. Its error is the RMS over every grid
point of (table - reference) / peak of the reference, in percent, against
the SAME tool's converged reference: 2^R photons with another seed (Gonio:
pseudo-random, seed 1000, --symmetry none), averaged over C (the scene is
rotationally symmetric, so the C-average is the reference with 72x the
photons). Costs are whole-run CPU seconds (user + sys of the child process).

Gonio's series: `gonio simulate MODEL --photons N --iterations 1 --threads T
--format ies --cache DIR` (the cache warm from the reference run, as in any
run after the first; --no-cache: cold every time) with its defaults (mode "default": --symmetry auto,
--next-event auto, Sobol'), "none" (--symmetry none: the estimator the peer
has, no averaging over C) and "on" (--symmetry none --next-event on). Gonio
runs with several --gonio binaries (NAME=BIN, e.g. a base commit's) are
interleaved with the peer's, so ratios come from one run on a shared machine.

The peer's side needs a driver binary (not part of Gonio; see the docs) that
takes PHOTONS SEED C_STEP G_STEP OUT and writes "num_c num_g c g photons"
then num_c rows of num_g raw bin energies (each photon carries 1; C bins
[c, c + step), gamma bins centred on multiples of the step).

The target error is the peer's own error at --target-photons (default 10^7,
the issue's run); each series' time to it is interpolated log-log between
the photon counts around it (as gonio_next_event_study does).
"""
import argparse
import math
import os
import re
import resource
import subprocess
import sys
import tempfile

C_STEP, G_STEP = 5.0, 2.5
NC, NG = 72, 73
FLUX = 1000.0


def cpu_of(cmd):
    """Runs cmd; returns (user + sys CPU seconds of the child, stdout + stderr)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stdout))
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), p.stdout


def read_ies(path):
    """The IES file's candela as table[c][g] on the 72 x 73 grid (C planes
    repeated where the file keeps fewer by symmetry)."""
    text = open(path, encoding="latin-1").read()
    nums = [float(x) for x in re.split(r"[\s,]+", text[text.index("TILT="):].split("\n", 1)[1]) if x]
    mult, nv, nh = nums[2], int(nums[3]), int(nums[4])
    k = 13
    vert = nums[k:k + nv]
    hor = nums[k + nv:k + nv + nh]
    vals = nums[k + nv + nh:k + nv + nh + nv * nh]
    assert len(vert) == NG and abs(vert[-1] - 180.0) < 1e-9, "expected gamma 0..180 by 2.5"
    planes = {}
    for j, h in enumerate(hor):
        planes[round(h, 6)] = [mult * v for v in vals[j * nv:(j + 1) * nv]]
    table = []
    for i in range(NC):
        c = i * C_STEP
        if nh == 1:
            table.append(planes[round(hor[0], 6)])
        elif round(c, 6) in planes:
            table.append(planes[round(c, 6)])
        else:
            # Bilateral symmetries: mirror about the planes the file keeps.
            for m in (360.0 - c, 180.0 - c, c - 180.0, 540.0 - c):
                if round(m % 360.0, 6) in planes:
                    table.append(planes[round(m % 360.0, 6)])
                    break
            else:
                sys.exit("%s: no C plane for %g" % (path, c))
    return table


def read_peer(path):
    with open(path) as f:
        nc, ng, c_res, g_res, photons = f.readline().split()
        assert int(nc) == NC and int(ng) == NG
        bins = [[float(x) for x in f.readline().split()] for _ in range(NC)]
    photons = float(photons)
    dc = math.radians(C_STEP)
    table = []
    for i in range(NC):
        row = []
        for j in range(NG):
            g = math.radians(j * G_STEP)
            lo, hi = max(0.0, g - math.radians(G_STEP) / 2), min(math.pi, g + math.radians(G_STEP) / 2)
            omega = dc * abs(math.cos(lo) - math.cos(hi))
            row.append(bins[i][j] / photons * FLUX / omega)
        table.append(row)
    return table


def c_average(table):
    avg = [sum(table[i][j] for i in range(NC)) / NC for j in range(NG)]
    return [avg[:] for _ in range(NC)]


def rms_pct(table, ref, poles=True):
    """RMS over the grid, relative to the reference's peak [%]; without the
    poles' rows (gamma 0 and 180, where a C-gamma grid's points are slivers)
    when poles is False."""
    rows = range(NG) if poles else range(1, NG - 1)
    peak = max(max(r) for r in ref)
    s = sum((table[i][j] - ref[i][j]) ** 2 for i in range(NC) for j in rows)
    return 100.0 * math.sqrt(s / (NC * len(rows))) / peak


METRICS = (("whole grid", True), ("poles left out", False))


def to_target(points, target):
    """points: [(photons, cpu, err)] ascending; log-log interpolation."""
    for a, b in zip(points, points[1:]):
        if a[2] > target >= b[2]:
            t = math.log(a[2] / target) / math.log(a[2] / b[2])
            return (math.exp(math.log(a[0]) + t * math.log(b[0] / a[0])),
                    math.exp(math.log(a[1]) + t * math.log(b[1] / a[1])))
    return (float("nan"), float("nan"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gonio", action="append", required=True, help="BIN or NAME=BIN (repeatable)")
    ap.add_argument("--make-samples", help="gonio_make_samples (default: beside the first gonio's build)")
    ap.add_argument("--peer", help="the peer's driver binary (optional)")
    ap.add_argument("--photons-log2", default="16,17,18,19,20,21,22")
    ap.add_argument("--reference-log2", type=int, default=25)
    ap.add_argument("--target-photons", type=float, default=1e7)
    ap.add_argument("--modes", default="default,none,on")
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--work", default=None)
    ap.add_argument("--no-cache", action="store_true",
                    help="every gonio run with --no-cache (checks the model and builds the overlaps each time)")
    ap.add_argument("--tables", help="write the C-averaged references' gamma profiles here (CSV)")
    a = ap.parse_args()

    work = a.work or tempfile.mkdtemp(prefix="peer_tube_")
    gonios = []
    for g in a.gonio:
        name, _, binary = g.rpartition("=")
        gonios.append((name or "gonio", os.path.abspath(binary)))
    make = a.make_samples or os.path.join(os.path.dirname(os.path.dirname(gonios[0][1])), "samples",
                                          "gonio_make_samples")
    subprocess.run([make, "--peer", work], check=True)
    model = os.path.join(work, "led-housing", "led-housing.gltf")
    with open("/proc/loadavg") as f:
        print("load:", f.read().strip())

    def gonio_run(binary, photons, mode, seed="1", sampler="sobol", tag="run"):
        out = os.path.join(work, "%s-%s-%d" % (tag, mode, photons))
        cmd = [binary, "simulate", model, "--out", out, "--photons", str(int(photons)), "--iterations", "1",
               "--threads", str(a.threads), "--format", "ies", "--seed", seed, "--sampler", sampler]
        # Warm: the model check and the grid's overlaps come from the cache
        # after the reference run (each binary its own), as in a user's second run.
        cmd += ["--no-cache"] if a.no_cache else ["--cache", os.path.join(work, "cache-" + os.path.basename(binary))]
        if mode in ("none", "on", "reference"):
            cmd += ["--symmetry", "none"]
        if mode == "on":
            cmd += ["--next-event", "on"]
        cpu, log = cpu_of(cmd)
        ne = re.search(r"next-event estimation ([^\n]*)", log)
        return cpu, read_ies(os.path.join(out, "led-housing.ies")), ne.group(1) if ne else ""

    def peer_run(photons, seed):
        out = os.path.join(work, "peer-%d-%d.txt" % (photons, seed))
        cpu, _ = cpu_of([a.peer, str(int(photons)), str(seed), str(C_STEP), str(G_STEP), out])
        return cpu, read_peer(out)

    refs = {}
    big = 1 << a.reference_log2
    for name, binary in gonios:
        cpu, table, _ = gonio_run(binary, big, "reference", seed="1000", sampler="random", tag="ref-" + name)
        refs[name] = c_average(table)
        print("reference %s: 2^%d photons, %.2f CPU s" % (name, a.reference_log2, cpu))
    if a.peer:
        cpu, table = peer_run(big, 1000)
        refs["peer"] = c_average(table)
        print("reference peer: 2^%d photons, %.2f CPU s" % (a.reference_log2, cpu))
    if a.tables:
        with open(a.tables, "w") as f:
            f.write("gamma," + ",".join(refs) + "\n")
            for j in range(NG):
                f.write("%g,%s\n" % (j * G_STEP, ",".join("%.6g" % refs[k][0][j] for k in refs)))
    names = list(refs)
    for x in names:
        for y in names:
            if x < y:
                print("references %s vs %s: RMS %.3f %% of %s's peak; peaks %.2f and %.2f cd" %
                      (x, y, rms_pct(refs[x], refs[y]), y, max(refs[x][0]), max(refs[y][0])))

    counts = [1 << int(k) for k in a.photons_log2.split(",")]
    modes = a.modes.split(",")
    series = {}
    for r in range(a.rounds):
        for n in counts:
            if a.peer:
                cpu, table = peer_run(n, 1 + r)
                series.setdefault(("peer", ""), []).append(
                    (r, n, cpu, rms_pct(table, refs["peer"]), rms_pct(table, refs["peer"], False)))
            for name, binary in gonios:
                for mode in modes:
                    cpu, table, ne = gonio_run(binary, n, mode, seed=str(1 + r))
                    series.setdefault((name, mode), []).append(
                        (r, n, cpu, rms_pct(table, refs[name]), rms_pct(table, refs[name], False)))
                    series.setdefault((name, mode, "ne"), []).append(ne)
    print("\nseries (round, photons, whole-run CPU s, RMS % of peak against the tool's own reference):")
    for key, pts in series.items():
        if len(key) == 3:
            print("%s %s: next-event %s" % (key[0], key[1], pts[-1]))
            continue
        for p in pts:
            print("%-8s %-8s round %d photons %9d cpu %8.3f err %7.4f, poles left out %7.4f" %
                  (key[0], key[1] or "-", p[0], p[1], p[2], p[3], p[4]))
    if not a.peer:
        return
    peer_pts = series[("peer", "")]
    for metric, (label, _) in enumerate(METRICS):
        e = 3 + metric
        # The peer's error at the target photons, from its series: err ~ k / sqrt(N).
        ks = [p[e] * math.sqrt(p[1]) for p in peer_pts]
        target = sum(ks) / len(ks) / math.sqrt(a.target_photons)
        print("\n[%s] target: the peer's error at %.3g photons = %.4f %% (k = err * sqrt(N) = %.3f, spread %.3f..%.3f)"
              % (label, a.target_photons, target, sum(ks) / len(ks), min(ks), max(ks)))
        print("time to the target per round, CPU s (and photons), and the ratio to the peer's in the same round:")
        for r in range(a.rounds):
            peer = sorted((p[1], p[2], p[e]) for p in peer_pts if p[0] == r)
            # The peer's cost is linear in photons (no setup): its CPU per photon of its two largest runs.
            per_photon = sum(p[1] for p in peer[-2:]) / sum(p[0] for p in peer[-2:])
            t_peer = a.target_photons * per_photon
            print("round %d peer: %.3g photons, %.3f CPU s (CPU per 10^6 photons %.3f)" %
                  (r, a.target_photons, t_peer, per_photon * 1e6))
            for key, pts in series.items():
                if len(key) == 3 or key[0] == "peer":
                    continue
                mine = sorted((p[1], p[2], p[e]) for p in pts if p[0] == r)
                n, t = to_target(mine, target)
                how = "interpolated"
                if math.isnan(t):
                    # Beyond the series: err ~ k / sqrt(N) from the nearest end, CPU linear in photons past it.
                    end = mine[-1] if mine[-1][2] > target else mine[0]
                    k = end[2] * math.sqrt(end[0])
                    n = (k / target) ** 2
                    t = end[1] * n / end[0] if end is mine[-1] else end[1]
                    how = "extrapolated" if end is mine[-1] else "below the smallest run: its CPU"
                print("round %d %s %s: %.3g photons, %.3f CPU s, ratio %.3f (%s)" %
                      (r, key[0], key[1], n, t, t / t_peer, how))

if __name__ == "__main__":
    main()
