// The IES spacing criterion (SC): the largest ratio of luminaire spacing to
// mounting height above the work plane at which the work plane stays evenly
// lit, by the IES rule of the "half illuminance" between luminaires.
//
// With the luminaire at height h above the work plane and E₁(C, x) the
// horizontal illuminance one luminaire gives at horizontal distance x in the
// plane C, E₁ = I(C, γ) cos³γ / h², tan γ = x / h:
// - C0–C180: two luminaires S apart along C0; SC is the smallest S/h at which
//   the illuminance midway between them from both, E₁(C0, S/2) + E₁(C180, S/2),
//   has fallen to the illuminance directly below one from that one, E₁(nadir);
//   for a symmetric luminaire, E₁(S/2) = 0.5 E₁(nadir).
// - C90–C270: the same along C90.
// - Diagonal: four luminaires on a square of side S; the centre, S/√2 from
//   each along C45, C135, C225, C315, gets E₁(nadir) from the four
//   (E₁ = 0.25 E₁(nadir) each for a symmetric luminaire). Reported as the
//   square's side S/h.
// Not applicable (null, with the reason): no light straight down (indirect
// or asymmetric luminaires such as wall washers), or the illuminance does
// not fall to the criterion within 4 mounting heights.
#pragma once

#include <optional>
#include <string>

#include "photometry/distribution.h"

namespace gonio::photometry {

struct SpacingValue {
  std::optional<double> ratio;  // S / h [1]
  std::string why_undefined;    // empty when ratio is set
};

struct SpacingCriterion {
  SpacingValue c0_c180;
  SpacingValue c90_c270;
  SpacingValue diagonal;
};

// Requires validate(d).ok().
SpacingCriterion spacing_criterion(const Distribution& d);

}  // namespace gonio::photometry
