// Every light-planning figure of a distribution in one call (what `gonio
// info` and the datasheet print): the UGR table, the CU table, the spacing
// criterion, the BUG rating and the luminance table. Each figure's method is
// in its own header.
#pragma once

#include <string>
#include <vector>

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

// Which method and convention a figure follows and which outside reference
// Gonio's tests hold it to (what `gonio info` and the datasheet print beside
// each figure).
struct MethodLabel {
  std::string figure;           // "UGR", "CU", "Spacing criterion", "BUG rating", "Luminance"
  std::string key;              // its JSON key: "ugr_table", "cu_table", …
  std::string method;           // the method and the publication that defines it
  std::string convention;       // orientation, planes, units: what a reader must know to compare
  std::string checked_against;  // the outside reference of the tests; "none" says so
};

// One label per figure, in the order of PlanningFigures; the UGR label
// follows the table's background (CIE 190 or flux transfer).
std::vector<MethodLabel> method_labels(const PlanningFigures& p);

// Requires validate(d).ok(). `floor_reflectance` is the CU table's effective
// floor cavity reflectance [1]; `ugr` the UGR table's background and spacing.
PlanningFigures planning_figures(const Distribution& d, double floor_reflectance = 0.2,
                                 const UgrOptions& ugr = {});

}  // namespace gonio::photometry
