// gonio_make_samples DIR — writes the sample luminaires to DIR/<name>/
// (see samples/luminaires.h). The build runs it into build/samples.
#include <cstdio>
#include <string>

#include "samples/luminaires.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: gonio_make_samples DIR\n");
    return 2;
  }
  const gonio::Status written = gonio::samples::write_samples(argv[1]);
  if (!written.ok()) {
    std::fprintf(stderr, "gonio_make_samples: %s\n", gonio::to_string(written.error()).c_str());
    return 1;
  }
  return 0;
}
