#include "tools/photometric_input.h"

#include "tools/ray_file_far_field.h"

namespace gonio::cli {

void add_input_options(ArgParser& parser, InputOptions* options) {
  parser.choice("ldt-isym3", &options->ldt_isym3, {kIsym3Standard, kIsym3QLumEdit},
                "Plane order of EULUMDAT input with Isym 3 (C90-C270 symmetry): 'standard' "
                "stores C270 ... C0 ... C90 as the standard defines; 'qlumedit' stores "
                "C90 ... C180 ... C270 as QLumEdit writes it (a half turn of the other). No "
                "field in the file tells them apart. Default: standard.");
  parser.option("photometry", &options->gldf_photometry, "ID",
                "Of a GLDF container, the photometry to read: its id in product.xml or its file "
                "(ldc/NAME). Default: every one where the command reports several (info, check), "
                "else the first.");
}

void add_ugr_background_option(ArgParser& parser, std::string* word) {
  parser.choice("ugr-background", word,
                {photometry::to_string(photometry::UgrBackground::Cie190),
                 photometry::to_string(photometry::UgrBackground::FluxTransfer)},
                "Background luminance of the UGR table: 'cie190' as CIE 190:2010 eq. 7-12 with its "
                "Tables 4 and 5 (what DIALux, Relux and the CIE's example use; default), or "
                "'flux-transfer', Gonio's own inter-reflection model of each room (README "
                "\"Light-planning figures\" says when they differ).");
}

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
