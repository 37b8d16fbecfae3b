// The colour-over-angle chart of a spectral run (issue 24), beside the
// intensity diagram: CCT over γ and Δu′v′ from the luminaire's mean
// chromaticity over γ, one curve per principal C-plane, on two line charts
// (io/outputs/plot.h renders them).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/outputs/plot.h"

namespace gonio::io {

struct ColourCurve {
  double c_deg = 0.0;
  std::vector<double> gamma_deg;
  std::vector<double> cct_k;     // NaN where undefined (a gap)
  std::vector<double> delta_uv;  // Δu′v′ from the mean; NaN where no light
};

// The curves from report.json's "colour_over_angle" (planes of gamma_deg,
// u_prime, v_prime, cct_k; mean_u_prime, mean_v_prime): Δu′v′ from the
// mean per γ, NaN for nulls; planes whose lists differ in length are left
// out.
std::vector<ColourCurve> colour_curves(const nlohmann::json& colour_over_angle);

// Errors: no curves, or a curve whose lists differ in length.
Result<Figure> colour_over_angle_chart(const std::vector<ColourCurve>& curves, const std::string& title,
                                       double delta_uv_max);

}  // namespace gonio::io
