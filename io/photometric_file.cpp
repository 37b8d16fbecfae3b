#include "io/photometric_file.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/file_io.h"
#include "photometry/flux.h"

namespace gonio::io {
namespace {

std::string lower_extension(std::string_view path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::string num(double v, int digits = 6) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string describe_grid(const photometry::Distribution& c) {
  const auto& h = c.horizontal_deg;
  const auto& v = c.vertical_deg;
  const double c_step = h.size() > 1 ? h[1] - h[0] : 0.0;
  const double g_step = v.size() > 1 ? v[1] - v[0] : 0.0;
  std::string s = "C " + num(h.front()) + " to " + num(h.back());
  if (h.size() > 1) s += " every " + num(c_step);
  s += " deg (" + std::to_string(h.size()) + " planes, " + photometry::to_string(c.symmetry) +
       "), gamma " + num(v.front()) + " to " + num(v.back());
  if (v.size() > 1) s += " every " + num(g_step);
  s += " deg";
  return s;
}

Error failure(std::string message) {
  Error e;
  e.message = std::move(message);
  return e;
}

}  // namespace

const char* to_string(PhotometricFormat format) {
  return format == PhotometricFormat::Ies ? "IES" : "EULUMDAT";
}

std::optional<PhotometricFormat> format_for_path(std::string_view path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ies") return PhotometricFormat::Ies;
  if (ext == ".ldt") return PhotometricFormat::Ldt;
  return std::nullopt;
}

Result<PhotometricFile> read_photometric_file(const std::string& path,
                                              const PhotometricReadOptions& options) {
  const auto format = format_for_path(path);
  if (!format) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
      return Error{SourceLoc{path, 0, 0}, "is a directory, not a file"};
    const std::string ext = lower_extension(path);
    return Error{SourceLoc{path, 0, 0}, (ext.empty() ? std::string("no file extension")
                                                     : "unknown file extension '" + ext + "'") +
                                            "; expected .ies (IES LM-63) or .ldt (EULUMDAT)"};
  }
  PhotometricFile out;
  out.format = *format;
  if (*format == PhotometricFormat::Ies) {
    auto r = read_ies(path);
    if (!r.ok()) return r.error();
    out.ies_version = r->version;
    out.distribution = std::move(r->distribution);
    out.findings = std::move(r->findings);
  } else {
    auto r = read_ldt(path, options.ldt);
    if (!r.ok()) return r.error();
    out.distribution = std::move(r->distribution);
    out.findings = std::move(r->findings);
  }
  // The readers promise a valid model; a broken promise is reported as the
  // file's error rather than passed on to code that relies on it.
  if (Status valid = photometry::validate(out.distribution); !valid.ok())
    return Error{SourceLoc{path, 0, 0}, valid.error().message};
  return out;
}

Result<std::string> encode_photometric_file(const photometry::Distribution& d,
                                            PhotometricFormat format,
                                            const PhotometricWriteOptions& options,
                                            std::vector<Finding>* warnings) {
  if (Status valid = photometry::validate(d); !valid.ok())
    return failure("cannot write an invalid distribution: " + valid.error().message);
  const bool resample = options.always_resample || (format == PhotometricFormat::Ldt &&
                                                    d.type != photometry::PhotometricType::C);
  photometry::Distribution resampled;
  const photometry::Distribution* source = &d;
  if (resample) {
    auto c = photometry::to_type_c(d, options.type_c_grid);
    if (!c.ok()) return failure("cannot resample to Type C: " + c.error().message);
    resampled = std::move(c).value();
    source = &resampled;
    if (warnings) {
      const double before = photometry::total_flux_lm(d);
      const double after = photometry::total_flux_lm(resampled);
      std::string message =
          std::string("Type ") + photometry::to_string(d.type) +
          " photometry resampled onto a Type C grid: " + describe_grid(resampled) + "; flux " +
          num(before, 7) + " lm -> " + num(after, 7) + " lm";
      if (before > 0.0) message += " (" + num(100.0 * (after - before) / before, 3) + " %)";
      if (format == PhotometricFormat::Ldt && d.type != photometry::PhotometricType::C)
        message += "; EULUMDAT holds Type C only";
      warnings->push_back({Severity::Warning, "type-c-resampled", std::move(message), {}});
    }
  }
  if (format == PhotometricFormat::Ies) return write_ies(*source, options.ies, warnings);
  return write_ldt(*source, options.ldt, warnings);
}

Status write_photometric_file(const std::string& path, const photometry::Distribution& d,
                              const PhotometricWriteOptions& options,
                              std::vector<Finding>* warnings) {
  const auto format = format_for_path(path);
  if (!format)
    return Error{SourceLoc{path, 0, 0},
                 "cannot tell the output format: expected the extension .ies or .ldt"};
  auto bytes = encode_photometric_file(d, *format, options, warnings);
  if (!bytes.ok()) return Error{SourceLoc{path, 0, 0}, bytes.error().message};
  return write_file_atomic(path, *bytes);
}

}  // namespace gonio::io
