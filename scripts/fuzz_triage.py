#!/usr/bin/env python3
"""Says where a fuzz finding happened: `scripts/fuzz_triage.py LOG`.

Reads a libFuzzer log (scripts/fuzz.sh) and prints one line: "opencascade
FRAME" when the code running at the crash, timeout or sanitizer report was
OpenCASCADE's (a frame in one of its libTK* libraries before any frame of
Gonio's), else "gonio FRAME" (a frame of Gonio's code or of the harness
first, a leak, a failed check of the harness, or no stack at all).

The runtime's own frames (libFuzzer, the sanitizers and their interceptors)
and those of the C and C++ runtime libraries say nothing about whose code
it was, and are passed over. Only the STEP harness runs OpenCASCADE in
process; gonio itself runs it in the helper process gonio-cad, where such a
fault is an error message (scripts/fuzz.sh then checks that it is).
"""
import re
import sys

FRAME = re.compile(r"^\s*#\d+ 0x[0-9a-f]+ in (?P<func>.*?) \((?P<module>[^()]*?)\+0x[0-9a-f]+\)")
RUNTIME_MODULES = ("libc.so", "libstdc++.so", "libm.so", "libgcc_s.so", "ld-linux", "libpthread.so")
RUNTIME_FUNCS = ("fuzzer::", "__sanitizer", "__asan", "__ubsan", "__lsan", "__interceptor", "__interception",
                 "___interceptor", "__cxa", "__cxxabiv1", "__dynamic_cast", "operator new", "operator delete")
# The sanitizers' interceptors of the C library carry its functions' plain
# names, in the harness binary.
INTERCEPTED = re.compile(r"^(str|mem|wcs|__str|__mem)[a-z_]*$|^(malloc|calloc|realloc|free|printf|sprintf|"
                         r"snprintf|vsnprintf|fopen|fread|fwrite|fclose|read|write|open|close|pthread_[a-z_]+)$")


def classify(lines):
    """('opencascade' | 'gonio', frame) for the first report's stack."""
    if any("fuzz finding" in line or "ERROR: LeakSanitizer" in line for line in lines):
        return "gonio", "a finding of the harness's own checks or a leak"
    started = False
    for line in lines:
        if not started:
            started = bool(re.search(r"==\d+==ERROR|ERROR: libFuzzer|runtime error|ALARM", line))
            continue
        m = FRAME.match(line)
        if not m:
            continue
        func, module = m.group("func"), m.group("module")
        if any(r in module for r in RUNTIME_MODULES):
            continue
        if func.startswith(RUNTIME_FUNCS) or INTERCEPTED.match(func):
            continue
        if "/libTK" in module:
            return "opencascade", f"{func} ({module.rsplit('/', 1)[-1]})"
        return "gonio", func
    return "gonio", "no stack in the log"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: fuzz_triage.py LOG")
    with open(sys.argv[1], encoding="utf-8", errors="replace") as f:
        who, frame = classify(f.read().splitlines())
    print(who, frame)


if __name__ == "__main__":
    main()
