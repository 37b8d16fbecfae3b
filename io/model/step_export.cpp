#include "io/model/step_export.h"

#include <cmath>
#include <sstream>

#include "photometry/format.h"

namespace gonio::io {
namespace {

constexpr const char* kHeader = "gonio-step-export 1";

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace

std::string serialize_step_export(const StepExport& request) {
  std::string out = std::string(kHeader) + "\n";
  out += "product " + one_line(request.product) + "\n";
  out += "tolerance " + format_number(request.tolerance_mm, 17) + "\n";
  out += "parts " + std::to_string(request.parts.size()) + "\n";
  for (const StepRevolvedPart& p : request.parts) {
    out += "part " + one_line(p.name) + "\n";
    if (!p.curves.empty()) {
      out += "curves " + std::to_string(p.curves.size());
      for (std::size_t c : p.curves) out += " " + std::to_string(c);
      out += "\n";
    }
    if (p.extrude_mm > 0.0) out += "extrude " + format_number(p.extrude_mm, 17) + "\n";
    if (!p.cover.empty())
      out += "cover " + one_line(p.cover) + " " + format_number(p.cover_a, 17) + " " + format_number(p.cover_b, 17) + " " +
             format_number(p.cover_t, 17) + " " + format_number(p.cover_z, 17) + "\n";
    if (!p.faces.empty()) {
      out += "faces " + std::to_string(p.faces.size()) + "\n";
      std::size_t k = 0;
      for (std::size_t n : p.faces) {
        out += std::to_string(n);
        for (std::size_t c = 0; c < 3 * n && k < p.corners.size(); ++c, ++k) out += " " + format_number(p.corners[k], 17);
        out += "\n";
      }
    }
    if (!p.patches.empty()) {
      out += "patches " + std::to_string(p.patches.size() / 2) + "\n";
      std::size_t k = 0;
      for (std::size_t q = 0; q + 1 < p.patches.size(); q += 2) {
        out += std::to_string(p.patches[q]) + " " + std::to_string(p.patches[q + 1]);
        for (std::size_t c = 0; c < 3 * p.patches[q] * p.patches[q + 1] && k < p.patch_points.size(); ++c, ++k)
          out += " " + format_number(p.patch_points[k], 17);
        out += "\n";
      }
    }
    if (!p.file.empty()) out += "file " + one_line(p.file) + "\n";
    if (!p.place.empty()) {
      out += "place";
      for (double v : p.place) out += " " + format_number(v, 17);
      out += "\n";
    }
    out += "points " + std::to_string(p.rho.size()) + "\n";
    for (std::size_t i = 0; i < p.rho.size() && i < p.z.size(); ++i)
      out += format_number(p.rho[i], 17) + " " + format_number(p.z[i], 17) + "\n";
  }
  return out;
}

Result<StepExport> parse_step_export(std::string_view text, const std::string& name) {
  std::istringstream in{std::string(text)};
  std::string line;
  int number = 0;
  auto next = [&](std::string& l) -> bool {
    if (!std::getline(in, l)) return false;
    ++number;
    return true;
  };
  auto bad = [&](const std::string& why) { return make_error(name, "line " + std::to_string(number) + ": " + why); };
  auto keyed = [&](const std::string& key, std::string& value) -> bool {
    if (!next(line) || line.rfind(key + " ", 0) != 0) return false;
    value = line.substr(key.size() + 1);
    return true;
  };
  if (!next(line) || line != kHeader) return bad("not a STEP export request");
  StepExport r;
  std::string value;
  if (!keyed("product", r.product)) return bad("expected 'product NAME'");
  if (!keyed("tolerance", value)) return bad("expected 'tolerance MM'");
  char* end = nullptr;
  r.tolerance_mm = std::strtod(value.c_str(), &end);
  if (*end != '\0' || !(r.tolerance_mm > 0.0) || !std::isfinite(r.tolerance_mm)) return bad("bad tolerance");
  if (!keyed("parts", value)) return bad("expected 'parts N'");
  const long parts = std::strtol(value.c_str(), &end, 10);
  if (*end != '\0' || parts < 1 || parts > 100000) return bad("bad part count");
  for (long k = 0; k < parts; ++k) {
    StepRevolvedPart p;
    if (!keyed("part", p.name)) return bad("expected 'part NAME'");
    if (!next(line)) return bad("expected 'points N'");
    if (line.rfind("curves ", 0) == 0) {
      std::istringstream cs(line.substr(7));
      long count = 0;
      if (!(cs >> count) || count < 1 || count > 1000) return bad("bad curve count");
      for (long c = 0; c < count; ++c) {
        long start = -1;
        if (!(cs >> start) || start < 0 || (c == 0 && start != 0) ||
            (c > 0 && start <= static_cast<long>(p.curves.back())))
          return bad("curve starts must be 0 and then increase");
        p.curves.push_back(static_cast<std::size_t>(start));
      }
      std::string rest;
      if (cs >> rest) return bad("text after the curve starts");
      if (!next(line)) return bad("expected 'points N'");
    }
    if (line.rfind("extrude ", 0) == 0) {
      p.extrude_mm = std::strtod(line.c_str() + 8, &end);
      if (*end != '\0' || !(p.extrude_mm > 0.0) || !std::isfinite(p.extrude_mm)) return bad("bad extrusion length");
      if (!next(line)) return bad("expected 'points N'");
    }
    if (line.rfind("cover ", 0) == 0) {
      std::istringstream c(line.substr(6));
      std::string rest;
      if (!(c >> p.cover >> p.cover_a >> p.cover_b >> p.cover_t >> p.cover_z) || (c >> rest) ||
          (p.cover != "box" && p.cover != "disc" && p.cover != "dome") || !(p.cover_a > 0.0) || !(p.cover_t >= 0.0) ||
          !std::isfinite(p.cover_a) || !std::isfinite(p.cover_b) || !std::isfinite(p.cover_t) || !std::isfinite(p.cover_z))
        return bad("bad cover (box, disc or dome; then four finite numbers)");
      if (!next(line)) return bad("expected 'points N'");
    }
    if (line.rfind("faces ", 0) == 0) {
      const long count = std::strtol(line.c_str() + 6, &end, 10);
      if (*end != '\0' || count < 1 || count > 1'000'000) return bad("bad face count");
      for (long f = 0; f < count; ++f) {
        if (!next(line)) return bad("the faces end early");
        std::istringstream fs(line);
        long corners = 0;
        if (!(fs >> corners) || corners < 3 || corners > 100'000) return bad("a face needs 3 to 100000 corners");
        for (long c = 0; c < 3 * corners; ++c) {
          double v = 0.0;
          if (!(fs >> v) || !std::isfinite(v)) return bad("expected " + std::to_string(3 * corners) + " finite numbers x y z");
          p.corners.push_back(v);
        }
        std::string rest;
        if (fs >> rest) return bad("text after the face's corners");
        p.faces.push_back(static_cast<std::size_t>(corners));
      }
      if (!p.cover.empty() || p.extrude_mm > 0.0 || !p.curves.empty()) return bad("planar faces are a part of their own");
      if (!next(line)) return bad("expected 'points N'");
    }
    if (line.rfind("patches ", 0) == 0) {
      const long count = std::strtol(line.c_str() + 8, &end, 10);
      if (*end != '\0' || count < 1 || count > 1'000'000) return bad("bad patch count");
      for (long f = 0; f < count; ++f) {
        if (!next(line)) return bad("the patches end early");
        std::istringstream ps(line);
        long nu = 0, nv = 0;
        if (!(ps >> nu >> nv) || nu < 2 || nv < 2 || nu > 10'000 || nv > 10'000 || nu * nv > 1'000'000)
          return bad("a patch needs 2 … 10000 points each way (at most 10⁶)");
        for (long c = 0; c < 3 * nu * nv; ++c) {
          double v = 0.0;
          if (!(ps >> v) || !std::isfinite(v)) return bad("expected " + std::to_string(3 * nu * nv) + " finite numbers x y z");
          p.patch_points.push_back(v);
        }
        std::string rest;
        if (ps >> rest) return bad("text after the patch's points");
        p.patches.push_back(static_cast<std::size_t>(nu));
        p.patches.push_back(static_cast<std::size_t>(nv));
      }
      if (!p.cover.empty() || p.extrude_mm > 0.0 || !p.curves.empty()) return bad("patches are a part of their own");
      if (!next(line)) return bad("expected 'points N'");
    }
    if (line.rfind("file ", 0) == 0) {
      p.file = line.substr(5);
      if (p.file.empty()) return bad("an empty file name");
      if (!next(line) || line.rfind("place ", 0) != 0) return bad("expected 'place' and 12 numbers");
    }
    if (line.rfind("place ", 0) == 0) {
      std::istringstream ps(line.substr(6));
      double v = 0.0;
      while (ps >> v) {
        if (!std::isfinite(v)) return bad("the placement's numbers must be finite");
        p.place.push_back(v);
      }
      if (p.place.size() != 12 || !ps.eof()) return bad("expected 'place' and 12 numbers");
      if (!p.file.empty() &&
          (!p.cover.empty() || p.extrude_mm > 0.0 || !p.curves.empty() || !p.faces.empty() || !p.patches.empty()))
        return bad("a placed file is a part of its own");
      if (p.file.empty() && p.curves.empty()) return bad("only a file or a solid (curves) is placed");
      if (!next(line)) return bad("expected 'points N'");
    }
    if (line.rfind("points ", 0) != 0) return bad("expected 'points N'");
    value = line.substr(7);
    const long n = std::strtol(value.c_str(), &end, 10);
    const bool pointless = !p.cover.empty() || !p.faces.empty() || !p.patches.empty() || !p.file.empty();
    if (*end != '\0' || (pointless ? n != 0 : n < 2) || n > 10'000'000)
      return bad(!pointless ? "bad point count (at least 2)"
                 : p.cover.empty() ? "planar faces and patches have no points"
                                   : "a cover has no points");
    if (!p.curves.empty() && static_cast<long>(p.curves.back()) + 1 >= n)
      return bad("a curve starts at or after the last point");
    for (long i = 0; i < n; ++i) {
      if (!next(line)) return bad("the points end early");
      std::istringstream pt(line);
      double rho = 0.0, z = 0.0;
      std::string rest;
      if (!(pt >> rho >> z) || (pt >> rest) || !std::isfinite(rho) || !std::isfinite(z) ||
          (rho < 0.0 && p.extrude_mm == 0.0))
        return bad(p.extrude_mm > 0.0 ? "expected two finite numbers x, z" : "expected two finite numbers ρ ≥ 0, z");
      p.rho.push_back(rho);
      p.z.push_back(z);
    }
    r.parts.push_back(std::move(p));
  }
  while (next(line))
    if (!line.empty()) return bad("unexpected text after the last part");
  return r;
}

}  // namespace gonio::io
