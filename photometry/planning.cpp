#include "photometry/planning.h"

namespace gonio::photometry {

PlanningFigures planning_figures(const Distribution& d, double floor_reflectance) {
  PlanningFigures p;
  p.ugr = ugr_table(d);
  p.cu = cu_table(d, floor_reflectance);
  p.spacing = spacing_criterion(d);
  p.bug = bug_rating(d);
  p.luminance = luminance_table(d);
  return p;
}

}  // namespace gonio::photometry
