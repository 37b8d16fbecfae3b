#include "sim/samplers/alias_table.h"

#include <cmath>

#include "photometry/diagnostics.h"

namespace gonio::sim {

AliasTable::AliasTable(std::span<const double> weights)
    : probability_(weights.size()), alias_(weights.size()), weight_(weights.begin(), weights.end()) {
  GONIO_CHECK_MSG(!weights.empty() && weights.size() < (std::size_t{1} << 32),
                  "alias table size out of range");
  for (double w : weights) {
    GONIO_CHECK_MSG(std::isfinite(w) && w >= 0.0, "alias table weights must be finite and >= 0");
    total_ += w;
  }
  GONIO_CHECK_MSG(total_ > 0.0 && std::isfinite(total_), "alias table weights sum to zero");

  const std::size_t n = weights.size();
  std::vector<double> scaled(n);
  std::vector<std::uint32_t> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    scaled[i] = weights[i] * static_cast<double>(n) / total_;
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
  }
  while (!small.empty() && !large.empty()) {
    const std::uint32_t s = small.back(), l = large.back();
    small.pop_back();
    probability_[s] = scaled[s];
    alias_[s] = l;
    scaled[l] = (scaled[l] + scaled[s]) - 1.0;
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // Whatever is left is 1 up to rounding.
  for (std::uint32_t i : large) {
    probability_[i] = 1.0;
    alias_[i] = i;
  }
  for (std::uint32_t i : small) {
    probability_[i] = weights[i] > 0.0 ? 1.0 : 0.0;
    alias_[i] = i;
  }
  // A zero-weight index must never be drawn, even through rounding residue.
  std::uint32_t first_positive = 0;
  while (weights[first_positive] == 0.0) ++first_positive;
  for (std::size_t i = 0; i < n; ++i) {
    if (weights[i] == 0.0 && alias_[i] == i) {
      alias_[i] = first_positive;
      probability_[i] = 0.0;
    }
  }
}

}  // namespace gonio::sim
