// What the libFuzzer harnesses share: a scratch folder per harness and
// process, file writes, and findings that are not crashes.
#pragma once

#include <string>
#include <string_view>

namespace gonio::fuzz {

// A fresh folder for one harness in this process (under /dev/shm where it
// exists, else $TMPDIR or /tmp), holding the fixed side files a harness's
// inputs may name: tilt.dat (a valid IES TILT file), profile.ies and
// profile.ldt (valid profiles). Removed at exit.
std::string scratch_dir(const std::string& harness);

// Writes `bytes` to `path` whole; aborts when it cannot (the harness's own
// failure, not a finding in the code under test).
void write(const std::string& path, std::string_view bytes);

// Reports a broken property (not a crash) and aborts, so that libFuzzer
// keeps the input as a crash artifact.
[[noreturn]] void finding(const std::string& what);

}  // namespace gonio::fuzz
