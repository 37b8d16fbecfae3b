#!/usr/bin/env python3
"""Where the tracer's instructions go: callgrind's self costs summed by group.

    scripts/callgrind_groups.py [--top N] CALLGRIND_OUT...

Groups (docs/validation.md, "Where the time goes"): Embree (libembree3 and
the EmbreeScene wrappers), sampling and scattering (emission, lobes, BSDF
evaluation, next-event directions, the phase function, random numbers),
booking (texel lookup, rounding to units, the tallies' own functions), and
the tracer loop with the rest (follow, trace_photons, connect_from, with
what the compiler inlined into them, booking's increments among it). Run
callgrind with --toggle-collect='gonio::sim::Tracer::trace_photons*' so that
only tracing counts. --top N also lists each group's N costliest functions.
"""
import re
import subprocess
import sys

GROUPS = [
    ("Embree", re.compile(r"libembree|EmbreeScene::|rtc[A-Z]|embree::")),
    ("booking", re.compile(r"texel_of|Tally::|book_|Ledger|add_connection|CubeMap|ImageTally|LuminanceImage"
                           r"|record_rays|llround|lround")),
    ("sampling+scattering", re.compile(
        r"sample|Sample|scatter|weight_at|unpack_unit|connection_direction|draw|f_cos|pdf|fresnel|Fresnel|bsdf"
        r"|Bsdf|BSDF|abg|Abg|volume|Volume|slab|Slab|Sobol|sobol|PhotonRandom|random|Random|lobe|Lobe"
        r"|Polarization|polariz|interface_event|tabulated|Emission|emit|spectr|Wavelength|owen|Owen|hash"
        r"|refract|reflect|frame|Frame|henyey|exp|log|sin|cos|sqrt|atan|acos|pow|erf|Incidence|Vertex"
        r"|mixture|glossy|beckmann|lambert|half_vector")),
]
REST = "tracer loop+rest"
# callgrind_annotate lists these wrappers with the whole run as their cost.
WRAPPERS = re.compile(r"libc-start|below main|ld-linux-x86-64")


def groups(path):
    out = subprocess.run(["callgrind_annotate", "--threshold=100", "--inclusive=no", path],
                         capture_output=True, text=True, check=True).stdout
    sums = {g: 0 for g, _ in GROUPS}
    sums[REST] = 0
    detail = {g: [] for g in sums}
    total = 0
    for line in out.splitlines():
        m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$", line)
        if not m or "PROGRAM TOTALS" in line or WRAPPERS.search(line):
            continue
        ir = int(m.group(1).replace(",", ""))
        name = m.group(2)
        # The function's own name (the signature's types would match other groups).
        plain = re.sub(r"^[^:]*:", "", name.replace("(anonymous namespace)", "anon"), count=1)
        fn = plain.split("(")[0] + (" " + name.split("[")[-1] if "[" in name else "")
        total += ir
        group = next((g for g, rx in GROUPS if rx.search(fn)), REST)
        sums[group] += ir
        detail[group].append((ir, name))
    return total, sums, detail


def main(argv):
    top = 0
    if len(argv) > 2 and argv[1] == "--top":
        top = int(argv[2])
        argv = argv[2:]
    for path in argv[1:]:
        total, sums, detail = groups(path)
        print(f"{path}: {total:,} Ir; " + ", ".join(f"{g} {v / max(total, 1) * 100:.1f} %" for g, v in sums.items()))
        for g, rows in detail.items():
            for ir, name in sorted(rows, reverse=True)[:top]:
                print(f"  {g:20s} {ir:>14,}  {name[:120]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
