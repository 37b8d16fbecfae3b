"""scripts/fuzz_triage.py: whose code ran at a fuzz finding.

The logs are shaped as libFuzzer and the sanitizers print them (the STEP
harness's stack overflow in OpenCASCADE of 2026-12-05 among them, cut to
its first frames); the verdict decides whether CI fails (Gonio's code) or
checks that gonio contains the fault (OpenCASCADE's).
"""
import importlib.util
import os
import pathlib

SCRIPT = pathlib.Path(os.environ.get("GONIO_SOURCE_DIR", pathlib.Path(__file__).parents[2])) / "scripts" / "fuzz_triage.py"
spec = importlib.util.spec_from_file_location("fuzz_triage", SCRIPT)
triage = importlib.util.module_from_spec(spec)
spec.loader.exec_module(triage)

BIN = "/check/build-fuzz/tests/fuzz/gonio_fuzz_step"


def frame(n, func, module):
    return f"    #{n} 0x7ffff6e6eaba in {func} ({module}+0x26eaba) (BuildId: 77286485)"


def test_a_stack_overflow_inside_opencascade_is_opencascades():
    log = [
        "INFO: Seed: 194243959",
        "==14707==ERROR: AddressSanitizer: stack-overflow on address 0x7fffff7fef40",
        frame(0, "fuzzer::TracePC::AddValueForMemcmp(void*, void const*, void const*, unsigned long, bool)", BIN),
        frame(1, "strcmp", BIN),
        frame(2, "__cxxabiv1::__si_class_type_info::__do_dyncast(long) const", "/lib/x86_64-linux-gnu/libstdc++.so.6"),
        frame(3, "__dynamic_cast", "/lib/x86_64-linux-gnu/libstdc++.so.6"),
        frame(4, "StepToGeom::MakeCurve(opencascade::handle<StepGeom_Curve> const&)", "/lib/x86_64-linux-gnu/libTKSTEP.so.7"),
        frame(5, "StepToGeom::MakeCurve(opencascade::handle<StepGeom_Curve> const&)", "/lib/x86_64-linux-gnu/libTKSTEP.so.7"),
    ]
    who, where = triage.classify(log)
    assert who == "opencascade"
    assert "StepToGeom::MakeCurve" in where and "libTKSTEP" in where


def test_a_fault_in_gonios_code_called_from_opencascade_callbacks_is_gonios():
    log = [
        "==1==ERROR: AddressSanitizer: heap-buffer-overflow on address 0x602000000010",
        frame(0, "__asan_memcpy", BIN),
        frame(1, "gonio::io::(anonymous namespace)::CadReader::collect(TopoDS_Shape const&)", BIN),
        frame(2, "BRepMesh_IncrementalMesh::Perform()", "/lib/x86_64-linux-gnu/libTKMesh.so.7"),
    ]
    assert triage.classify(log)[0] == "gonio"


def test_harness_checks_leaks_undefined_behaviour_and_bare_logs_are_gonios():
    assert triage.classify(["fuzz finding: read_cad_file returned a non-finite vertex"])[0] == "gonio"
    assert triage.classify(["==1==ERROR: LeakSanitizer: detected memory leaks",
                            frame(0, "malloc", BIN),
                            frame(1, "NCollection_BaseAllocator::Allocate(unsigned long)",
                                  "/lib/x86_64-linux-gnu/libTKernel.so.7")])[0] == "gonio"
    assert triage.classify(["==1==ERROR: libFuzzer: out-of-memory (used: 4097Mb; exceeds: 4096Mb)"]) == \
        ("gonio", "no stack in the log")
    ub = ["io/model/step.cpp:420:7: runtime error: signed integer overflow",
          frame(0, "gonio::io::read_cad_file(std::string const&)", BIN)]
    assert triage.classify(ub)[0] == "gonio"


def test_a_timeout_inside_opencascade_is_opencascades():
    log = [
        "ALARM: working on the last Unit for 26 seconds",
        "==1== ERROR: libFuzzer: timeout after 26 seconds",
        frame(0, "__sanitizer_print_stack_trace", BIN),
        frame(1, "fuzzer::PrintStackTrace()", BIN),
        frame(2, "BRepMesh_Delaun::Perform(IMeshData::VectorOfInteger&)", "/lib/x86_64-linux-gnu/libTKMesh.so.7"),
        frame(3, "gonio::io::read_cad_file(std::string const&)", BIN),
    ]
    assert triage.classify(log)[0] == "opencascade"
