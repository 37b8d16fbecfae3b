#include "tools/run/ray_file_far_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "photometry/format.h"
#include "sim/detectors/far_field.h"

namespace gonio::app {

photometry::PhotometricFrame ray_file_frame() {
  return photometry::make_frame(Vec3{0.0, 0.0, -1.0}, Vec3{1.0, 0.0, 0.0});
}

Result<photometry::Distribution> ray_set_far_field(const io::Tm25RaySet& set, const std::string& path,
                                                   const sim::CGammaGrid& grid) {
  if (!set.has_luminous_flux())
    return make_error(path, "the rays carry radiant flux only and the header does not state both total fluxes: "
                            "their luminous flux, and so their far field, is unknown");
  if (Status valid = sim::validate(grid); !valid.ok()) return make_error(path, valid.error().message);
  const int face = sim::face_size_for(grid);
  sim::FarField field(face);
  const std::size_t n = set.ray_count();
  for (std::size_t i = 0; i < n; ++i) {
    const double flux = set.luminous_flux_lm(i);
    if (flux > 0.0) field.add(field.grid().texel_of(set.direction(i)), flux);
  }
  if (!(field.total_flux_lm() > 0.0)) return make_error(path, "the rays carry no luminous flux");
  const sim::Resampler resampler(face, ray_file_frame(), grid);
  photometry::Distribution d = sim::to_distribution(resampler.bin(field), photometry::Symmetry::None);
  d.absolute = true;
  // The emitter's extent in the photometric frame (x: C0, −y: C90, −z: up).
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = set.position_mm(i);
    const double v[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], v[k]);
      hi[k] = std::max(hi[k], v[k]);
    }
  }
  if (n > 0) {
    d.luminaire.length_m = (hi[0] - lo[0]) * 1e-3;
    d.luminaire.width_m = (hi[1] - lo[1]) * 1e-3;
    d.luminaire.height_m = (hi[2] - lo[2]) * 1e-3;
  }
  const io::Tm25Header& h = set.header;
  if (!h.manufacturer.empty()) d.set_keyword("MANUFAC", h.manufacturer);
  if (!h.light_source.empty()) d.set_keyword("LUMCAT", h.light_source);
  d.set_keyword("LUMINAIRE", h.light_source.empty() ? "TM-25 ray set" : h.light_source + " (TM-25 ray set)");
  d.set_keyword("TEST", std::string(h.creation_method == 1 ? "measured" : "simulated") + " ray set, " +
                            std::to_string(n) + " rays" + (h.created.empty() ? "" : ", " + h.created));
  if (!h.equipment.empty()) d.set_keyword("TESTLAB", h.equipment);
  const std::string grid_words = grid.uniform() ? "C every " + format_number(grid.c_step_deg) + " deg, gamma every " +
                                                      format_number(grid.gamma_step_deg) + " deg"
                                                : grid.describe();
  d.set_keyword("OTHER", "far field of the TM-25 ray file's directions binned by luminous flux (" + grid_words +
                             "; +z of the ray file is the nadir)");
  if (Status valid = photometry::validate(d); !valid.ok()) return make_error(path, valid.error().message);
  return d;
}

void enable_ray_files(io::PhotometricReadOptions& options) {
  options.ray_set_far_field = [](const io::Tm25RaySet& set, const std::string& path) {
    return ray_set_far_field(set, path);
  };
}

}  // namespace gonio::app
