// Walker's alias method: draws index i with probability w_i / Σw in O(1)
// from one uniform number (Vose's construction, deterministic).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace gonio::sim {

class AliasTable {
 public:
  AliasTable() = default;
  // Weights must be finite and ≥ 0 with a positive sum (GONIO_CHECK).
  explicit AliasTable(std::span<const double> weights);

  std::size_t size() const { return probability_.size(); }
  double total_weight() const { return total_; }

  // Index for a uniform u in [0, 1).
  std::uint32_t sample(double u) const {
    const double x = u * static_cast<double>(probability_.size());
    std::size_t i = static_cast<std::size_t>(x);
    if (i >= probability_.size()) i = probability_.size() - 1;
    return (x - static_cast<double>(i)) < probability_[i] ? static_cast<std::uint32_t>(i)
                                                          : alias_[i];
  }
  // Probability of drawing index i: w_i / Σw.
  double pmf(std::size_t i) const { return weight_[i] / total_; }

 private:
  std::vector<double> probability_;   // chance of keeping bucket i
  std::vector<std::uint32_t> alias_;  // the other index in bucket i
  std::vector<double> weight_;
  double total_ = 0.0;
};

}  // namespace gonio::sim
