#include "sim/convergence.h"

#include <algorithm>
#include <limits>
#include <string>

namespace gonio::sim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean(std::span<const double> v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

// A map as a far field of flux = intensity × texel solid angle.
FarField as_far_field(int face_size, std::span<const double> intensity_cd) {
  FarField f(face_size);
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    f.add(t, intensity_cd[t] * f.grid().texel_solid_angle(t), 0);
  return f;
}

}  // namespace

std::vector<double> texel_intensities(const FarField& field) {
  std::vector<double> out(field.texel_count());
  for (std::size_t t = 0; t < out.size(); ++t) out[t] = field.intensity_cd(t);
  return out;
}

Result<ConvergenceReference> ConvergenceReference::create(const FarField& reference,
                                                          std::shared_ptr<const Resampler> resampler) {
  GONIO_CHECK(resampler && resampler->face_size() == reference.face_size());
  if (!(reference.total_flux_lm() > 0.0))
    return make_error("the reference run has no escaped flux: there is no far field to compare");
  return ConvergenceReference(reference, std::move(resampler));
}

ConvergenceReference::ConvergenceReference(FarField reference, std::shared_ptr<const Resampler> resampler)
    : reference_(std::move(reference)), resampler_(std::move(resampler)) {
  scaled_ = texel_intensities(reference_);
  const double r_mean = mean(scaled_);
  for (std::size_t t = 0; t < scaled_.size(); ++t) {
    const double r = scaled_[t] /= r_mean;
    peak_sq_ = std::max(peak_sq_, r * r);
    mean_sq_ += r * r;
    if (reference_.photons(t) > 0) noise_nu_ += r * r / static_cast<double>(reference_.photons(t));
  }
  mean_sq_ /= static_cast<double>(scaled_.size());
  noise_nu_ /= static_cast<double>(scaled_.size());

  table_ = resampler_->bin(reference_);
  for (std::size_t b = 0; b < table_.flux_lm.size(); ++b) {
    const double omega = table_.solid_angle_sr[b];
    if (!(omega > 0.0)) continue;
    peak_cd_ = std::max(peak_cd_, table_.intensity_cd(b));
    table_noise_ += table_.variance_lm2[b] / omega;  // Ω · v_b, v_b = variance / Ω²
    table_solid_angle_ += omega;
  }
}

double ConvergenceReference::table_noise_pct() const {
  return 100.0 * std::sqrt(table_noise_ / table_solid_angle_) / peak_cd_;
}

CubeMapError ConvergenceReference::cube_map_error(std::span<const double> intensity_cd) const {
  GONIO_CHECK(intensity_cd.size() == scaled_.size());
  const double x_mean = mean(intensity_cd);
  double sum = 0.0;
  for (std::size_t t = 0; t < scaled_.size(); ++t) {
    // Divided as the reference was, so that the reference scores exactly 0.
    const double d = (x_mean > 0.0 ? intensity_cd[t] / x_mean : 0.0) - scaled_[t];
    sum += d * d;
  }
  CubeMapError e;
  e.raw_mse = sum / static_cast<double>(scaled_.size());
  const double mse = e.raw_mse - noise_nu_;
  if (!(mse > 0.0)) {
    e.rmse = e.psnr_db = e.snr_db = kNaN;
    return e;
  }
  e.rmse = std::sqrt(mse);
  e.psnr_db = 10.0 * std::log10(peak_sq_ / mse);
  e.snr_db = 10.0 * std::log10(mean_sq_ / mse);
  return e;
}

TableError ConvergenceReference::table_error(std::span<const double> intensity_cd) const {
  GONIO_CHECK(intensity_cd.size() == scaled_.size());
  const BinnedField table = resampler_->bin(as_far_field(reference_.face_size(), intensity_cd));
  double sum = 0.0, worst = 0.0;
  for (std::size_t b = 0; b < table.flux_lm.size(); ++b) {
    const double omega = table_.solid_angle_sr[b];
    if (!(omega > 0.0)) continue;
    const double d = table.intensity_cd(b) - table_.intensity_cd(b);
    sum += omega * d * d;
    worst = std::max(worst, std::abs(d));
  }
  TableError e;
  const double ms = (sum - table_noise_) / table_solid_angle_;
  e.rms_pct = ms > 0.0 ? 100.0 * std::sqrt(ms) / peak_cd_ : kNaN;
  e.raw_rms_pct = 100.0 * std::sqrt(sum / table_solid_angle_) / peak_cd_;
  e.max_pct = 100.0 * worst / peak_cd_;
  const double flux_ref = table_.total_flux_lm();
  e.flux_pct = 100.0 * (table.total_flux_lm() - flux_ref) / flux_ref;
  return e;
}

double log_log_slope(std::span<const double> x, std::span<const double> y) {
  GONIO_CHECK(x.size() == y.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(std::isfinite(x[i]) && std::isfinite(y[i]) && x[i] > 0.0 && y[i] > 0.0)) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++n;
  }
  if (n < 2) return kNaN;
  const double var = sxx - sx * sx / n;
  if (!(var > 0.0)) return kNaN;
  return (sxy - sx * sy / n) / var;
}

double crossing(std::span<const double> x, std::span<const double> y, double level) {
  GONIO_CHECK(x.size() == y.size());
  if (x.empty()) return kNaN;
  auto above = [&](std::size_t i) { return !std::isnan(y[i]) && y[i] > level; };
  if (above(x.size() - 1)) return kNaN;
  std::size_t last = x.size();  // last index above the level
  for (std::size_t i = 0; i < x.size(); ++i)
    if (above(i)) last = i;
  if (last == x.size()) return x[0];
  const std::size_t next = last + 1;
  if (std::isnan(y[next]) || !(y[next] > 0.0)) return x[next];
  // Log-log interpolation between (x[last], y[last]) and (x[next], y[next]).
  const double t = std::log(level / y[last]) / std::log(y[next] / y[last]);
  return std::exp(std::log(x[last]) + t * std::log(x[next] / x[last]));
}

}  // namespace gonio::sim
