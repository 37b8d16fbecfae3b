// What several commands print as JSON in the same way: numbers that may be
// undefined, and the peak, beam and field figures of a photometry::Summary
// (gonio info --json, the live page's state.json). Templates over
// nlohmann's json types: info writes ordered_json, the live page json.
#pragma once

#include <cmath>

#include <nlohmann/json.hpp>

#include "photometry/summary.h"

namespace gonio::cli {

// v, or null where it is NaN or infinite (JSON has no NaN).
template <class Json = nlohmann::json>
Json json_number(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

// Sets, under gonio info --json's keys and in its order: max_cd, max_c_deg,
// max_gamma_deg, max_horizontal_deg, max_vertical_deg,
// beam_angle_c0_c180_deg, beam_angle_c90_c270_deg, field_angle_c0_c180_deg,
// field_angle_c90_c270_deg (photometry/summary.h, photometry/beam.h);
// without a summary, each null.
template <class Json>
void put_peak_and_spread(Json& j, const photometry::Summary* s) {
  using S = photometry::Summary;
  const auto value = [s](auto get) { return s ? json_number<Json>(get(*s)) : Json(nullptr); };
  j["max_cd"] = value([](const S& x) { return x.max_intensity_cd; });
  j["max_c_deg"] = value([](const S& x) { return x.max_c_deg; });
  j["max_gamma_deg"] = value([](const S& x) { return x.max_gamma_deg; });
  j["max_horizontal_deg"] = value([](const S& x) { return x.max_horizontal_deg; });
  j["max_vertical_deg"] = value([](const S& x) { return x.max_vertical_deg; });
  j["beam_angle_c0_c180_deg"] = value([](const S& x) { return x.beam_c0_c180.angle_deg; });
  j["beam_angle_c90_c270_deg"] = value([](const S& x) { return x.beam_c90_c270.angle_deg; });
  j["field_angle_c0_c180_deg"] = value([](const S& x) { return x.field_c0_c180.angle_deg; });
  j["field_angle_c90_c270_deg"] = value([](const S& x) { return x.field_c90_c270.angle_deg; });
}

}  // namespace gonio::cli
