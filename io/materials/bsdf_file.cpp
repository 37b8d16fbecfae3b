#include "io/materials/bsdf_file.h"

#include <utility>

#include "io/support/file_io.h"
#include "photometry/format.h"

namespace gonio::io {

Status finish_bsdf(sim::TabulatedBsdf& t, const std::string& name, std::vector<Finding>& findings) {
  std::vector<Finding> energy;
  if (Status f = t.finish(energy); !f.ok()) return make_error(name, f.error().message);
  for (Finding& f : energy) {
    f.where.file = name;
    findings.push_back(std::move(f));
  }
  for (bool transmission : {false, true}) {
    const double e = t.reciprocity_error(transmission);
    if (e >= 0.0)
      findings.push_back({Severity::Info, "bsdf-reciprocity",
                          name + ": " + (transmission ? "transmission front against back" : "front reflection") +
                              " departs from reciprocity by " + format_number(100.0 * e, 3) +
                              " % (mean over pairs of patches, weighted by the light they carry)",
                          {name}});
  }
  return Ok{};
}

Result<std::shared_ptr<const sim::TabulatedBsdf>> read_bsdf_file(const std::string& path,
                                                                 std::vector<Finding>& findings) {
  Result<std::string> bytes = read_file(path, kMaxBsdfFileBytes);
  if (!bytes.ok()) return bytes.error();
  std::string_view b = *bytes;
  if (b.substr(0, 3) == "\xEF\xBB\xBF") b.remove_prefix(3);
  const auto first = b.find_first_not_of(" \t\r\n");
  const bool xml = first != std::string_view::npos && b[first] == '<';
  Result<sim::TabulatedBsdf> t = xml ? read_bsdf_xml(b, path, findings) : read_bsdf_csv(b, path, findings);
  if (!t.ok()) return t.error();
  return std::shared_ptr<const sim::TabulatedBsdf>(std::make_shared<sim::TabulatedBsdf>(std::move(*t)));
}

}  // namespace gonio::io
