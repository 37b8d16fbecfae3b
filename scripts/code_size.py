#!/usr/bin/env python3
"""Line counts per folder and the longest functions of a source tree.

    scripts/code_size.py [--top N] [--repo DIR] [--rev REV] [FOLDER...]   (default FOLDER: tools)

Lines per folder: every file git tracks under FOLDER (C++ sources and headers
apart from the rest: CMake, web files), one row per folder holding files.
Longest functions: every function and method defined in a .cpp or .h, from
its first line to its closing brace, as universal-ctags finds them
(`ctags --fields=+ne`, Debian's universal-ctags, in scripts/setup.sh); lambdas count in the
function that holds them. With --rev the files are read as they are at that
commit (git show), so the same command measures before and after a change:

    scripts/code_size.py --rev c46d261 tools
    scripts/code_size.py tools
"""
import argparse
import collections
import json
import os
import pathlib
import subprocess
import sys
import tempfile

CXX = ('.cpp', '.h')


def tracked(repo, rev, folders):
    cmd = ['git', '-C', repo, 'ls-tree', '-r', '--name-only', rev or 'HEAD', '--'] if rev else \
          ['git', '-C', repo, 'ls-files', '--']
    return [f for f in subprocess.run(cmd + folders, check=True, capture_output=True,
                                       text=True).stdout.splitlines() if f]


def read(repo, rev, path):
    if rev:
        return subprocess.run(['git', '-C', repo, 'show', f'{rev}:{path}'], check=True,
                              capture_output=True).stdout
    return (pathlib.Path(repo) / path).read_bytes()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('folders', nargs='*', default=['tools'])
    ap.add_argument('--top', type=int, default=10, help='longest functions to list (default 10)')
    ap.add_argument('--repo', default=str(pathlib.Path(__file__).resolve().parent.parent))
    ap.add_argument('--rev', help='measure the files at this commit instead of the working tree')
    a = ap.parse_args()

    files = tracked(a.repo, a.rev, a.folders)
    per_folder = collections.defaultdict(lambda: [0, 0, 0])  # C++ lines, other lines, files
    with tempfile.TemporaryDirectory() as tmp:
        for f in files:
            data = read(a.repo, a.rev, f)
            lines = data.count(b'\n')
            row = per_folder[os.path.dirname(f)]
            row[0 if f.endswith(CXX) else 1] += lines
            row[2] += 1
            if f.endswith(CXX):
                out = pathlib.Path(tmp) / f
                out.parent.mkdir(parents=True, exist_ok=True)
                out.write_bytes(data)
        sources = [f for f in files if f.endswith(CXX)]
        tags = subprocess.run(['ctags', '--output-format=json', '--fields=+ne', '--kinds-C++=f',
                               '--language-force=C++', '-o', '-'] + sources, cwd=tmp, check=True,
                              capture_output=True, text=True).stdout

    functions = []
    for line in tags.splitlines():
        t = json.loads(line)
        if t.get('_type') != 'tag' or t['name'].startswith('__anon') or 'end' not in t:
            continue
        scope = t.get('scope', '')
        if '__anon' in scope and t.get('scopeKind') == 'function':
            continue  # a lambda's or local class's function: counted in its enclosing one
        name = (scope.split('::__anon')[0] + '::' if scope and t.get('scopeKind') != 'namespace' else '') + t['name']
        functions.append((t['end'] - t['line'] + 1, name, f"{t['path']}:{t['line']}"))
    functions.sort(key=lambda x: (-x[0], x[2]))

    print(f"Lines per folder ({a.rev or 'working tree'}):")
    print(f"  {'folder':<24} {'files':>5} {'C++':>7} {'other':>7}")
    total = [0, 0, 0]
    for folder in sorted(per_folder):
        cxx, other, n = per_folder[folder]
        total = [total[0] + cxx, total[1] + other, total[2] + n]
        print(f"  {folder + '/':<24} {n:>5} {cxx:>7} {other:>7}")
    print(f"  {'all':<24} {total[2]:>5} {total[0]:>7} {total[1]:>7}")
    print(f"\nLongest functions ({len(functions)} in all):")
    for n, name, where in functions[:a.top]:
        print(f"  {n:>5}  {name}  ({where})")
    return 0


if __name__ == '__main__':
    sys.exit(main())
