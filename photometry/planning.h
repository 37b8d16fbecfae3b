// Every light-planning figure of a distribution in one call (what `gonio
// info` and the datasheet print): the UGR table, the CU table, the spacing
// criterion, the BUG rating and the luminance table. Each figure's method is
// in its own header.
#pragma once

#include "photometry/bug_rating.h"
#include "photometry/luminance.h"
#include "photometry/spacing_criterion.h"
#include "photometry/ugr.h"
#include "photometry/zonal_cavity.h"

namespace gonio::photometry {

struct PlanningFigures {
  UgrTable ugr;
  CuTable cu;
  SpacingCriterion spacing;
  BugRating bug;
  LuminanceTable luminance;
};

// Requires validate(d).ok(). `floor_reflectance` is the CU table's effective
// floor cavity reflectance [1].
PlanningFigures planning_figures(const Distribution& d, double floor_reflectance = 0.2);

}  // namespace gonio::photometry
