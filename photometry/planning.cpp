#include "photometry/planning.h"

namespace gonio::photometry {

PlanningFigures planning_figures(const Distribution& d, double floor_reflectance, const UgrOptions& ugr) {
  PlanningFigures p;
  p.ugr = ugr_table(d, ugr);
  p.cu = cu_table(d, floor_reflectance);
  p.spacing = spacing_criterion(d);
  p.bug = bug_rating(d);
  p.luminance = luminance_table(d);
  return p;
}

std::vector<MethodLabel> method_labels(const PlanningFigures& p) {
  std::vector<MethodLabel> out;
  const bool cie190 = p.ugr.background == UgrBackground::Cie190;
  out.push_back(
      {"UGR", "ugr_table",
       std::string("CIE 190:2010 catalogue table (CIE 117:1995 tabular method): H = 2 m, spacing ") +
           (p.ugr.spacing_h == 0.25 ? "0.25H" : "other than 0.25H") +
           ", luminaires with T/R <= 3 and gamma <= 85 deg, Guth index from CIE 117 Table 4.1 (blanks left out), " +
           (cie190 ? "background luminance by CIE 190 eq. 7-12 with its Tables 4 and 5"
                   : "background luminance by Gonio's flux-transfer room model (--ugr-background "
                     "flux-transfer), not CIE 190's"),
       "crosswise: the luminaire straight ahead is seen in its C0 plane (its C90-C270 axis, an EULUMDAT "
       "luminaire's length, across the line of sight); endwise: in its C90 plane; at the file's flux",
       cie190 ? "the CIE 190:2010 example table (sample_11.ldt): largest difference 0.8, mean 0.23 (DIALux's "
                "table departs from it as far); Relux's table of that file: every cell within 0.1"
              : "none (CIE 190's example table is met by the default cie190 background only)"});
  out.push_back({"CU", "cu_table", "IES zonal cavity method (IES Lighting Handbook)",
                 "% of the rated lamp flux (relative photometry) or of the luminaire flux (absolute); "
                 "ceiling cavity / wall reflectances, effective floor cavity reflectance as given",
                 "Photometric Toolbox's CU table of a real roadway luminaire (198 of 198 cells round to the "
                 "printed percent); the Handbook's closed form and exact view factors"});
  out.push_back({"Spacing criterion", "spacing_criterion",
                 "IES spacing criterion (half-illuminance rule between luminaires)",
                 "S / mounting height above the work plane, in the C0-C180, C90-C270 and diagonal planes",
                 "closed forms for Lambertian and isotropic luminaires (Gonio's tests); no published value yet"});
  out.push_back({"BUG rating", "bug", "IES TM-15-11 Addendum A (backlight, uplight, glare zone lumens)",
                 "front = the C90 side (the street side of a Type C road luminaire); lumens at the file's flux; "
                 "glare of BH held to FH's limits for Types V/VS (downward lumens of all 8 octants within "
                 "10 % of their mean), to the backlight limits otherwise",
                 "10 of the 45 thresholds (U0-U3, G0's high-angle limit) against the IDA-IES Model Lighting "
                 "Ordinance's guide and Ashdown (LEUKOS); one real luminaire's published zone lumens and "
                 "rating (Selux Aya, Type V: B2-U0-G1); the other thresholds not yet (docs/methods.md)"});
  out.push_back({"Luminance", "luminance_table",
                 "average luminance I / A_p of the projected luminous opening (CIE 117 eq. 4.3: A_p = "
                 "A_bottom cos gamma + A_side(C) sin gamma, EULUMDAT side heights per face)",
                 "gamma 45-85 deg in the C0 and C90 planes; the opening's length along C0-C180 (LM-63), an "
                 "EULUMDAT length along C90-C270",
                 "the projected areas' closed forms (Gonio's tests) and the CIE 190 example through the UGR "
                 "table"});
  return out;
}

}  // namespace gonio::photometry
