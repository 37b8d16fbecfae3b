// Measured BSDFs from files into sim::TabulatedBsdf (sim/bsdfs/tabulated_bsdf.h):
//
// Radiance/WINDOW BSDF XML (LBNL's "WindowElement" schema, as WINDOW 6/7,
// genBSDF and Radiance's bsdf2klems/bsdf2ttree write it), with
//   Klems matrices  IncidentDataStructure "Columns" (each line of the data
//                   one outgoing patch, incidence along it: WINDOW's layout)
//                   or "Rows" (each line one incidence); angle bases from
//                   the file's AngleBasis blocks, or LBNL's built-in Klems
//                   Full/Half/Quarter by name;
//   tensor trees    "TensorTree3" (isotropic) and "TensorTree4" (read along
//                   the incidence azimuth 0, with an Info finding), angle
//                   basis "LBNL/Shirley-Chiu", rasterised at the tree's
//                   finest level (at most 2⁷ cells per side).
// Only the photopic data (<Wavelength>Visible</Wavelength>) is read;
// solar, CIE-X/Z and CIE-u/v blocks are reported (Info) and skipped: the
// tabulated lobe is grey. WINDOW's "Front" data is for light arriving on
// the Gonio surface's front face (the side its normal points to); Radiance
// turns its own surfaces the other way round (BSDFdirections.txt). A Klems
// matrix is read along the incidence azimuth 0 of each ring (the isotropic
// reading); where the patches of a ring scatter more than 5 % differently,
// an Info finding says the data is anisotropic.
//
// CSV goniometer tables: a header naming the columns theta_in, theta_out,
// phi_out and bsdf (units [deg], [deg], [deg], [1/sr]; "_deg"/"_per_sr"
// suffixes and brdf/btdf accepted) and optionally side (front or back;
// default front); separators comma, semicolon, tab or spaces; '#' starts a
// comment. theta_out < 90 is reflection, > 90 transmission (180: straight
// through); phi_out = 0 is the plane of incidence on the far side of the
// normal from the source (where the specular and straight-through
// directions lie). Where every phi_out lies within 0..180 the table is
// taken as mirror-symmetric about the plane of incidence. Each hemisphere
// must be a full grid (every theta_out × phi_out at every theta_in);
// patches reach halfway to the neighbouring measured angles.
//
// Every reader checks counts before it allocates, refuses non-finite or
// negative values (with the line), and finishes the table: per incidence
// the hemispherical reflectance plus transmittance must not exceed 1 (else
// a Warning finding and the row is scaled down), and the reciprocity of the
// front reflection (and of transmission, where both sides are given) is
// reported as an Info finding.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/bsdfs/tabulated_bsdf.h"

namespace gonio::io {

// Documents larger than this are refused (a Klems Full file is ~0.5 MB, a
// fine tensor tree a few MB).
inline constexpr std::size_t kMaxBsdfFileBytes = std::size_t{64} << 20;

Result<sim::TabulatedBsdf> read_bsdf_xml(std::string_view bytes, const std::string& name,
                                         std::vector<Finding>& findings);
Result<sim::TabulatedBsdf> read_bsdf_csv(std::string_view bytes, const std::string& name,
                                         std::vector<Finding>& findings);
// For the readers: finishes a table read from `name` (the energy check of
// sim::TabulatedBsdf::finish, its findings placed in the file) and reports
// its reciprocity (Info, "bsdf-reciprocity").
Status finish_bsdf(sim::TabulatedBsdf& table, const std::string& name, std::vector<Finding>& findings);

// A file by its content: XML (starts with '<' after white space and a BOM)
// or CSV.
Result<std::shared_ptr<const sim::TabulatedBsdf>> read_bsdf_file(const std::string& path,
                                                                 std::vector<Finding>& findings);

}  // namespace gonio::io
