#include "tools/photometric_file.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "io/file_io.h"
#include "io/ies.h"
#include "io/ldt.h"

namespace gonio::cli {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

Result<PhotometricFile> read_ies_file(const std::string& path) {
  Result<io::IesFile> f = io::read_ies(path);
  if (!f.ok()) return f.error();
  return PhotometricFile{path, std::string("IES ") + io::to_string(f->version), std::move(f->distribution),
                         std::move(f->findings)};
}

Result<PhotometricFile> read_ldt_file(const std::string& path) {
  Result<io::LdtFile> f = io::read_ldt(path);
  if (!f.ok()) return f.error();
  return PhotometricFile{path, "EULUMDAT", std::move(f->distribution), std::move(f->findings)};
}

}  // namespace

Result<PhotometricFile> read_photometric_file(const std::string& path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  if (ext == ".ies") return read_ies_file(path);
  if (ext == ".ldt") return read_ldt_file(path);
  Result<std::string> bytes = io::read_file(path, io::kMaxIesFileBytes);
  if (!bytes.ok()) return bytes.error();
  const std::string head = lower(bytes->substr(0, 4096));
  if (head.rfind("iesna", 0) == 0 || head.rfind("ies:", 0) == 0 || head.find("tilt=") != std::string::npos)
    return read_ies_file(path);
  Error e;
  e.where.file = path;
  e.message = "not a photometric file Gonio knows: expected an IES LM-63 (.ies) or EULUMDAT (.ldt) file";
  return e;
}

}  // namespace gonio::cli
