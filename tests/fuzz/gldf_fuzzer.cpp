// libFuzzer harness: the GLDF container reader (io::parse_gldf, the ZIP
// layer of io/support/zip.cpp and product.xml through io/support/xml.cpp) and, for what it
// accepts, every photometry inside read by its content type
// (io::read_photometric_files: EULUMDAT, IES or TM-33), its plausibility
// checks and flux, then packaged again as a GLDF (encode_photometric_file),
// which must read back to the same number of photometries. A crash, a
// sanitizer report or a broken round trip is a finding (scripts/fuzz.sh).
//
// Deflated entries make byte mutations of an archive useless past its
// headers, so a custom mutator unpacks a readable archive, mutates one
// entry's uncompressed bytes (product.xml, a photometry, ...) with
// libFuzzer's own mutator and packs it again (io::write_zip); one mutation
// in four, and every input that is not a readable archive, is mutated as
// raw bytes, which keeps the ZIP layer itself fuzzed.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "io/photometric/gldf.h"
#include "io/photometric/photometric_file.h"
#include "io/support/zip.h"
#include "photometry/distribution.h"
#include "photometry/flux.h"
#include "photometry/validation.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  using namespace gonio;
  std::minstd_rand random(seed);
  if (random() % 4 == 0) return LLVMFuzzerMutate(data, size, max_size);
  Result<std::vector<io::ZipEntry>> entries =
      io::read_zip(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.gldf");
  if (!entries.ok() || entries->empty()) return LLVMFuzzerMutate(data, size, max_size);
  std::string& bytes = (*entries)[random() % entries->size()].bytes;
  const std::size_t old_size = bytes.size();
  const std::size_t room = std::max(old_size, std::min<std::size_t>(max_size, 2 * old_size + 1024));
  bytes.resize(room);
  bytes.resize(LLVMFuzzerMutate(reinterpret_cast<std::uint8_t*>(bytes.data()), old_size, room));
  Result<std::string> packed = io::write_zip(*entries, 0);
  if (!packed.ok() || packed->size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, packed->data(), packed->size());
  return packed->size();
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  static const std::string dir = fuzz::scratch_dir("gldf");
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  Result<io::GldfFile> container = io::parse_gldf(bytes, "fuzz.gldf");
  if (!container.ok()) return 0;
  const std::string path = dir + "/fuzz.gldf";
  fuzz::write(path, bytes);
  Result<std::vector<io::PhotometricFile>> files = io::read_photometric_files(path);
  if (!files.ok()) return 0;  // a photometry inside that its reader refuses
  if (files->size() != container->photometries.size())
    fuzz::finding("read_photometric_files read " + std::to_string(files->size()) + " photometries of " +
                  std::to_string(container->photometries.size()));
  for (const io::PhotometricFile& f : *files) {
    const photometry::Distribution& d = f.distribution;
    if (!photometry::validate(d).ok()) fuzz::finding("a GLDF photometry read as an invalid distribution");
    (void)photometry::check(d);
    (void)photometry::total_flux_lm(d);
    io::PhotometricWriteOptions options;
    options.gldf_photometry = f.format;
    options.gldf_created_unix = 1;
    Result<std::string> packed = io::encode_photometric_file(d, io::PhotometricFormat::Gldf, options, nullptr);
    if (!packed.ok()) continue;  // e.g. relative photometry without lamp flux as EULUMDAT
    const std::string again = dir + "/again.gldf";
    fuzz::write(again, *packed);
    Result<std::vector<io::PhotometricFile>> back = io::read_photometric_files(again);
    if (!back.ok()) fuzz::finding("a GLDF written from a photometry reads back as: " + to_string(back.error()));
    if (back->size() != 1) fuzz::finding("a GLDF written with one photometry reads back with another count");
  }
  return 0;
}
