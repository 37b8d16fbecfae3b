#!/usr/bin/env python3
"""Checks the manual: figures moved, not lost, and links that lead somewhere.

    python3 scripts/docs_check.py [--base COMMIT]

1. Numbers: every number of README.md at COMMIT (default c46d261, the last
   README before it became a front page plus docs/) must appear in README.md
   and docs/**/*.md now at least as often as it did then (so a paragraph
   that goes takes its figures' counts down with it, even where the same
   number is written elsewhere). Numbers are runs of digits with their
   decimal points, thousands separators and superscripts ("0.163", "2²⁰",
   "10⁶", "2,090"). Those dropped on purpose are listed in DROPPED below,
   each with why; a number listed there that is no longer missing is an
   error too, so the list stays true.
2. Links: every relative link of README.md, DEVELOPERS.md and docs/**/*.md
   names a file that exists, and an anchor (#…) a heading of that file.
   Pages other branches add (PENDING) are reported, not failed, until they
   exist.

Exit status: 0 all good, 1 a number lost or a link broken.
"""
import argparse
import collections
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent

# Numbers of the old README left out on purpose: number -> (how many, why).
DROPPED = {
}

# Pages that land from other branches during the split (issue 30 step 3):
# a link to one of them is reported until the page exists.
PENDING = {
    "docs/cad.md", "docs/materials.md", "docs/luminance-and-glare.md",
    "docs/test-audit.md", "docs/python.md", "docs/slurm.md",
}

NUMBER = re.compile(r"[0-9⁰¹²³⁴⁵⁶⁷⁸⁹](?:[0-9⁰¹²³⁴⁵⁶⁷⁸⁹]|[.,](?=[0-9]))*")


def numbers(text):
    return collections.Counter(NUMBER.findall(text))


def manual_files():
    files = [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))
    return [f for f in files if f.is_file()]


def check_numbers(base):
    old = subprocess.run(["git", "show", f"{base}:README.md"], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout
    now = collections.Counter()
    for f in manual_files():
        now += numbers(f.read_text(encoding="utf-8"))
    problems = []
    lost = {}
    for n, count in numbers(old).items():
        if now[n] < count:
            lost[n] = count - now[n]
    for n, k in sorted(lost.items()):
        if n in DROPPED and DROPPED[n][0] >= k:
            continue
        problems.append(f"number {n}: {k} of its {numbers(old)[n]} occurrence(s) in "
                        f"{base}:README.md are not in README.md or docs/")
    for n, (k, why) in DROPPED.items():
        if lost.get(n, 0) == 0:
            problems.append(f"number {n} is listed as dropped ({why}) but is no longer missing: "
                            "take it out of DROPPED")
    return problems, lost


def anchors(path):
    """GitHub's heading anchors of a Markdown file."""
    result = set()
    seen = collections.Counter()
    in_code = False
    for line in path.read_text(encoding="utf-8").split("\n"):
        if line.startswith("```"):
            in_code = not in_code
        if in_code or not line.startswith("#"):
            continue
        title = line.lstrip("#").strip().lower()
        slug = re.sub(r"[^\w\- ]", "", title, flags=re.UNICODE).replace(" ", "-")
        anchor = slug if seen[slug] == 0 else f"{slug}-{seen[slug]}"
        seen[slug] += 1
        result.add(anchor)
    return result


LINK = re.compile(r"\]\(([^)\s]+)\)")


def check_links():
    problems, pending = [], set()
    files = manual_files() + [ROOT / "DEVELOPERS.md"]
    for f in files:
        in_code = False
        for number, line in enumerate(f.read_text(encoding="utf-8").split("\n"), 1):
            if line.startswith("```"):
                in_code = not in_code
            if in_code:
                continue
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target):
                    continue  # http:, mailto:
                path_part, _, anchor = target.partition("#")
                dest = (f.parent / path_part).resolve() if path_part else f
                rel = dest.relative_to(ROOT).as_posix() if dest.is_relative_to(ROOT) else str(dest)
                where = f"{f.relative_to(ROOT)}:{number}"
                if not dest.exists():
                    if rel in PENDING:
                        pending.add(rel)
                    else:
                        problems.append(f"{where}: link to {target}: no such file")
                    continue
                if anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    problems.append(f"{where}: link to {target}: no heading #{anchor} in {rel}")
    return problems, pending


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--base", default="c46d261",
                        help="commit whose README.md held every figure (default c46d261)")
    args = parser.parse_args()
    problems, lost = check_numbers(args.base)
    link_problems, pending = check_links()
    problems += link_problems
    for n, (k, why) in sorted(DROPPED.items()):
        print(f"dropped on purpose: {n} (x{k}): {why}")
    for p in sorted(pending):
        print(f"pending: {p} (lands from another branch)")
    for p in problems:
        print(f"docs_check: {p}", file=sys.stderr)
    print(f"docs_check: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
