#include "io/photometric/photometric_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/support/file_io.h"
#include "io/support/text.h"
#include "io/photometric/gldf.h"
#include "io/support/xml.h"
#include "photometry/format.h"
#include "photometry/flux.h"

namespace gonio::io {
namespace {

std::string lower_extension(std::string_view path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string describe_grid(const photometry::Distribution& c) {
  const auto& h = c.horizontal_deg;
  const auto& v = c.vertical_deg;
  const double c_step = h.size() > 1 ? h[1] - h[0] : 0.0;
  const double g_step = v.size() > 1 ? v[1] - v[0] : 0.0;
  std::string s = "C " + format_number(h.front()) + " to " + format_number(h.back());
  if (h.size() > 1) s += " every " + format_number(c_step);
  s += " deg (" + std::to_string(h.size()) + " planes, " + photometry::to_string(c.symmetry) +
       "), gamma " + format_number(v.front()) + " to " + format_number(v.back());
  if (v.size() > 1) s += " every " + format_number(g_step);
  s += " deg";
  return s;
}

}  // namespace

const char* to_string(PhotometricFormat format) {
  switch (format) {
    case PhotometricFormat::Ies: return "IES";
    case PhotometricFormat::Ldt: return "EULUMDAT";
    case PhotometricFormat::Tm33: return "TM-33";
    case PhotometricFormat::Gldf: return "GLDF";
    case PhotometricFormat::Tm25: return "TM-25";
  }
  return "?";
}

std::optional<PhotometricFormat> format_for_path(std::string_view path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ies") return PhotometricFormat::Ies;
  if (ext == ".ldt") return PhotometricFormat::Ldt;
  if (ext == ".xml") return PhotometricFormat::Tm33;
  if (ext == ".gldf") return PhotometricFormat::Gldf;
  if (ext == ".tm25ray") return PhotometricFormat::Tm25;
  return std::nullopt;
}

std::optional<PhotometricFormat> photometric_format_for_content(std::string_view bytes) {
  if (bytes.substr(0, 4) == std::string_view("PK\x03\x04", 4)) return PhotometricFormat::Gldf;
  if (looks_like_tm25(bytes)) return PhotometricFormat::Tm25;
  if (looks_like_tm33(bytes)) return PhotometricFormat::Tm33;
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);
  const std::vector<TextLine> lines = split_lines(bytes.substr(0, 8192));
  const std::size_t n = std::min<std::size_t>(lines.size(), 40);
  for (std::size_t i = 0; i < n; ++i) {
    std::string_view t = lines[i].text;
    while (!t.empty() && (t.front() == ' ' || t.front() == '\t')) t.remove_prefix(1);
    std::string head(t.substr(0, 5));
    for (char& c : head) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (head == "IESNA" || head.rfind("IES:", 0) == 0 || head == "TILT=")
      return PhotometricFormat::Ies;
  }
  // EULUMDAT: line 1 is free text, lines 2-6 are Ityp, Isym, Mc, Dc, Ng.
  if (lines.size() < 7) return std::nullopt;
  const auto integer_in = [&](std::size_t i, double lo, double hi) {
    const auto v = parse_number(trim(lines[i].text), true);
    return v && *v >= lo && *v <= hi && *v == std::floor(*v);
  };
  const auto dc = parse_number(trim(lines[4].text), true);
  if (integer_in(1, 0, 3) && integer_in(2, 0, 4) && integer_in(3, 0, kMaxLdtCPlanes) && dc &&
      *dc >= 0.0 && *dc <= 360.0 && integer_in(5, 0, kMaxLdtGammaAngles))
    return PhotometricFormat::Ldt;
  return std::nullopt;
}

namespace {

// The whole file and its format: by extension, then by content.
struct DetectedFile {
  PhotometricFormat format;
  std::string bytes;
};

std::size_t byte_limit(std::optional<PhotometricFormat> format) {
  if (format == PhotometricFormat::Ies) return kMaxIesFileBytes;
  if (format == PhotometricFormat::Ldt) return kMaxLdtBytes;
  if (format == PhotometricFormat::Tm33) return kMaxXmlBytes;
  if (format == PhotometricFormat::Gldf) return kMaxGldfBytes;
  if (format == PhotometricFormat::Tm25) return kMaxTm25Bytes;
  return std::max({kMaxIesFileBytes, kMaxLdtBytes, kMaxXmlBytes, kMaxGldfBytes});
}

Result<DetectedFile> read_and_detect(const std::string& path) {
  const auto by_extension = format_for_path(path);
  auto bytes = read_file(path, byte_limit(by_extension));
  if (!bytes.ok()) return bytes.error();
  if (by_extension) return DetectedFile{*by_extension, std::move(bytes).value()};
  if (const auto format = photometric_format_for_content(*bytes))
    return DetectedFile{*format, std::move(bytes).value()};
  const std::string ext = lower_extension(path);
  return make_error(path,
                    (ext.empty() ? std::string("no file extension") : "file extension '" + ext + "'") +
                        " and content name no photometric format Gonio knows; expected IES LM-63 "
                        "(.ies, or an IESNA/TILT= line), EULUMDAT (.ldt, or its numeric header), "
                        "IES TM-33 (.xml, or its root element), GLDF (.gldf, a ZIP archive) or an IES TM-25 ray "
                        "file (.tm25ray, or 'TM25' at its start)");
}

}  // namespace

Result<PhotometricFormat> detect_photometric_format(const std::string& path) {
  auto detected = read_and_detect(path);
  if (!detected.ok()) return detected.error();
  return detected->format;
}

std::string format_label(const PhotometricFile& file) {
  std::string label = to_string(file.format);
  if (file.ies_version) label += std::string(" ") + to_string(*file.ies_version);
  if (file.tm33_version) label = to_string(*file.tm33_version);
  if (!file.container.empty()) label = "GLDF (" + label + ")";
  return label;
}

namespace {

// One photometry from its bytes; `name` names it in findings and errors.
Result<PhotometricFile> parse_photometry(PhotometricFormat format, std::string_view bytes,
                                         const std::string& name, const std::string& tilt_dir,
                                         const PhotometricReadOptions& options) {
  PhotometricFile out;
  out.format = format;
  if (format == PhotometricFormat::Ies) {
    auto r = parse_ies(bytes, name, tilt_dir);
    if (!r.ok()) return r.error();
    out.ies_version = r->version;
    out.distribution = std::move(r->distribution);
    out.findings = std::move(r->findings);
  } else if (format == PhotometricFormat::Tm25) {
    auto r = parse_tm25(bytes, name);
    if (!r.ok()) return r.error();
    if (!options.ray_set_far_field)
      return make_error(name, "a TM-25 ray file: its far field is not computed here");
    auto far_field = options.ray_set_far_field(*r, name);
    if (!far_field.ok()) return far_field.error();
    out.distribution = std::move(far_field).value();
    out.findings = std::move(r->findings);
    out.findings.push_back({Severity::Info, "tm25-far-field",
                            "read as its far field: the " + std::to_string(r->ray_count()) +
                                " rays' directions binned by luminous flux (the OTHER keyword states the grid)",
                            {name, 0, 0}});
    out.ray_set = std::make_shared<const Tm25RaySet>(std::move(r).value());
  } else if (format == PhotometricFormat::Tm33) {
    auto r = parse_tm33(bytes, name);
    if (!r.ok()) return r.error();
    out.tm33_version = r->version;
    out.distribution = std::move(r->distribution);
    out.findings = std::move(r->findings);
  } else {
    auto r = parse_ldt(bytes, name, options.ldt);
    if (!r.ok()) return r.error();
    out.distribution = std::move(r->distribution);
    out.findings = std::move(r->findings);
  }
  // The readers promise a valid model; a broken promise is reported as the
  // file's error rather than passed on to code that relies on it.
  if (Status valid = photometry::validate(out.distribution); !valid.ok())
    return make_error(name, valid.error().message);
  return out;
}

}  // namespace

Result<std::vector<PhotometricFile>> read_photometric_files(const std::string& path,
                                                            const PhotometricReadOptions& options) {
  auto detected = read_and_detect(path);
  if (!detected.ok()) return detected.error();
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  std::vector<PhotometricFile> out;
  if (detected->format != PhotometricFormat::Gldf) {
    auto one = parse_photometry(detected->format, detected->bytes, path, dir.string(), options);
    if (!one.ok()) return one.error();
    out.push_back(std::move(one).value());
    return out;
  }
  auto gldf = parse_gldf(detected->bytes, path);
  if (!gldf.ok()) return gldf.error();
  if (!options.gldf_photometry.empty()) {
    std::vector<GldfPhotometry> chosen;
    std::string ids;
    for (const GldfPhotometry& p : gldf->photometries) {
      if (p.id == options.gldf_photometry || p.entry == options.gldf_photometry) chosen.push_back(p);
      ids += (ids.empty() ? "" : ", ") + p.id + " (" + p.entry + ")";
    }
    if (chosen.empty())
      return make_error(path, "no photometry '" + options.gldf_photometry + "' in the archive; it holds " + ids);
    gldf->photometries = std::move(chosen);
  }
  for (const GldfPhotometry& p : gldf->photometries) {
    const PhotometricFormat format = p.content_type == "ldc/ies"      ? PhotometricFormat::Ies
                                     : p.content_type == "ldc/iesxml" ? PhotometricFormat::Tm33
                                                                      : PhotometricFormat::Ldt;
    // TILT=<file> of an IES inside an archive is never looked up on disk.
    auto one = parse_photometry(format, p.bytes, path + ":" + p.entry, "/nonexistent-gldf-tilt-dir",
                                options);
    if (!one.ok()) return one.error();
    one->container = path;
    one->container_entry = p.entry;
    one->container_id = p.id;
    if (out.empty())
      for (const Finding& f : gldf->findings) one->findings.push_back(f);
    out.push_back(std::move(one).value());
  }
  return out;
}

Result<PhotometricFile> read_photometric_file(const std::string& path,
                                              const PhotometricReadOptions& options) {
  auto all = read_photometric_files(path, options);
  if (!all.ok()) return all.error();
  PhotometricFile first = std::move(all->front());
  if (all->size() > 1) {
    std::string others;
    for (std::size_t i = 1; i < all->size(); ++i) others += (i > 1 ? ", '" : "'") + (*all)[i].container_id + "'";
    first.findings.push_back({Severity::Info, "gldf-first-photometry",
                              "the archive holds " + std::to_string(all->size()) + " photometries; read '" +
                                  first.container_id + "' (" + first.container_entry + "), not " + others,
                              {path, 0, 0}});
  }
  return first;
}

Result<std::string> encode_photometric_file(const photometry::Distribution& d,
                                            PhotometricFormat format,
                                            const PhotometricWriteOptions& options,
                                            std::vector<Finding>* warnings) {
  if (Status valid = photometry::validate(d); !valid.ok())
    return make_error("cannot write an invalid distribution: " + valid.error().message);
  if (format == PhotometricFormat::Tm25)
    return make_error("a TM-25 ray file holds rays, not a far field: it is written by 'gonio simulate --format tm25'");
  const bool resample = format != PhotometricFormat::Gldf &&
                        (options.always_resample || (format == PhotometricFormat::Ldt &&
                                                     d.type != photometry::PhotometricType::C));
  photometry::Distribution resampled;
  const photometry::Distribution* source = &d;
  if (resample) {
    auto c = photometry::to_type_c(d, options.type_c_grid);
    if (!c.ok()) return make_error("cannot resample to Type C: " + c.error().message);
    resampled = std::move(c).value();
    source = &resampled;
    if (warnings) {
      const double before = photometry::total_flux_lm(d);
      const double after = photometry::total_flux_lm(resampled);
      std::string message =
          std::string("Type ") + photometry::to_string(d.type) +
          " photometry resampled onto a Type C grid: " + describe_grid(resampled) + "; flux " +
          format_number(before, 7) + " lm -> " + format_number(after, 7) + " lm";
      if (before > 0.0) message += " (" + format_number(100.0 * (after - before) / before, 3) + " %)";
      if (format == PhotometricFormat::Ldt && d.type != photometry::PhotometricType::C)
        message += "; EULUMDAT holds Type C only";
      warnings->push_back({Severity::Warning, "type-c-resampled", std::move(message), {}});
    }
  }
  if (format == PhotometricFormat::Gldf) {
    const PhotometricFormat inner =
        options.gldf_photometry == PhotometricFormat::Gldf || options.gldf_photometry == PhotometricFormat::Tm25
            ? PhotometricFormat::Ldt
            : options.gldf_photometry;
    auto bytes = encode_photometric_file(*source, inner, options, warnings);
    if (!bytes.ok()) return bytes.error();
    GldfProduct product;
    const auto keyword = [&](const char* key) {
      const photometry::Keyword* k = source->find_keyword(key);
      return k ? k->value : std::string();
    };
    product.name = keyword("LUMINAIRE");
    if (product.name.empty()) product.name = keyword("LUMCAT");
    const std::string stem = options.gldf_stem.empty() ? "luminaire" : options.gldf_stem;
    if (product.name.empty()) product.name = stem;
    product.manufacturer = keyword("MANUFAC");
    const char* ext = inner == PhotometricFormat::Ies ? ".ies" : inner == PhotometricFormat::Tm33 ? ".xml" : ".ldt";
    const char* type = inner == PhotometricFormat::Ies    ? "ldc/ies"
                       : inner == PhotometricFormat::Tm33 ? "ldc/iesxml"
                                                          : "ldc/eulumdat";
    product.photometries.push_back({stem + ext, type, std::move(bytes).value(), *source});
    product.created_unix =
        options.gldf_created_unix != 0 ? options.gldf_created_unix : now_unix();
    if (warnings)
      warnings->push_back({Severity::Info, "gldf-packaged",
                           std::string("packaged as ") + to_string(inner) + " (" + type +
                               ") with product.xml; no geometry (a simulation's GLDF carries its L3D model)",
                           {}});
    return write_gldf(product);
  }
  if (format == PhotometricFormat::Tm33) return write_tm33(*source, warnings);
  if (warnings && !source->spectra.empty())
    warnings->push_back({Severity::Warning, "spectrum-dropped",
                         std::to_string(source->spectra.size()) + " spectral distribution" +
                             (source->spectra.size() == 1 ? "" : "s") + " (TM-33) not written: " +
                             to_string(format) + " holds none",
                         {}});
  if (format == PhotometricFormat::Ies) return write_ies(*source, options.ies, warnings);
  return write_ldt(*source, options.ldt, warnings);
}

Status write_photometric_file(const std::string& path, const photometry::Distribution& d,
                              const PhotometricWriteOptions& options,
                              std::vector<Finding>* warnings) {
  const auto format = format_for_path(path);
  if (!format)
    return make_error(path, "cannot tell the output format: expected the extension .ies, .ldt, .xml or .gldf");
  PhotometricWriteOptions with_stem = options;
  if (*format == PhotometricFormat::Gldf && options.gldf_stem.empty())
    with_stem.gldf_stem = std::filesystem::path(path).stem().string();
  auto bytes = encode_photometric_file(d, *format, with_stem, warnings);
  if (!bytes.ok()) return make_error(path, bytes.error().message);
  return write_file_atomic(path, *bytes);
}

}  // namespace gonio::io
