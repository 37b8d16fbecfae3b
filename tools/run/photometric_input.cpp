#include "tools/run/photometric_input.h"

#include "tools/run/ray_file_far_field.h"

namespace gonio::cli {

photometry::UgrOptions ugr_options(const std::string& word) {
  photometry::UgrOptions o;
  o.background = photometry::parse_ugr_background(word).value_or(photometry::UgrBackground::Cie190);
  return o;
}

io::LdtIsym3Order isym3_order(const std::string& word) {
  return word == kIsym3QLumEdit ? io::LdtIsym3Order::C90_C180_C270 : io::LdtIsym3Order::C270_C0_C90;
}

io::PhotometricReadOptions read_options(const InputOptions& options) {
  io::PhotometricReadOptions r;
  r.ldt.isym3_order = isym3_order(options.ldt_isym3);
  r.gldf_photometry = options.gldf_photometry;
  enable_ray_files(r);
  return r;
}

Result<io::PhotometricFile> read_input(const std::string& path, const InputOptions& options,
                                       bool print_info) {
  auto file = io::read_photometric_file(path, read_options(options));
  if (!file.ok()) {
    print_error(file.error());
    return file.error();
  }
  for (const Finding& f : file->findings)
    if (print_info || f.severity != Severity::Info) print_finding(f);
  return file;
}

Result<std::vector<io::PhotometricFile>> read_inputs(const std::string& path, const InputOptions& options,
                                                     bool print_info) {
  auto files = io::read_photometric_files(path, read_options(options));
  if (!files.ok()) {
    print_error(files.error());
    return files.error();
  }
  for (const io::PhotometricFile& file : *files)
    for (const Finding& f : file.findings)
      if (print_info || f.severity != Severity::Info) print_finding(f);
  return files;
}

}  // namespace gonio::cli
