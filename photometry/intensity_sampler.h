// Intensity of any distribution (Types A, B, C) at Type C angles, for the
// planning figures that look at a luminaire from points of a room: built
// once (the symmetry expansion), then queried per direction.
#pragma once

#include <vector>

#include "photometry/distribution.h"

namespace gonio::photometry {

class IntensitySampler {
 public:
  // Requires validate(d).ok().
  explicit IntensitySampler(const Distribution& d);
  // I [cd] toward (C, γ) of the photometric frame [deg]: interpolate() of
  // the expanded grid (Types A/B through their own angles), 0 where the file
  // holds no data.
  double cd(double c_deg, double gamma_deg) const;
  // cd() at every point of the tensor grid c_deg × gamma_deg, as
  // out[i * gamma_deg.size() + j] for (c_deg[i], gamma_deg[j]): the same
  // values, with one search per grid line for Type C (interpolate_grid).
  std::vector<double> grid(const std::vector<double>& c_deg, const std::vector<double>& gamma_deg) const;

 private:
  Distribution expanded_;
};

// View factor between two directly opposed parallel rectangles a × b [m]
// at distance c [m] (the classical closed form, Howell's catalogue C-11):
// the fraction of the diffuse flux leaving one that reaches the other.
double facing_rectangles_view_factor(double a, double b, double c);

}  // namespace gonio::photometry
