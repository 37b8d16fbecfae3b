// Reading a STEP (AP203, AP214, AP242) or IGES file with OpenCASCADE and
// tessellating its parts (io/model/cad_model.h). The only file that
// includes OpenCASCADE's headers is step.cpp, and only the helper program
// gonio-cad (io/model/cad_helper.cpp) and the fuzz harness link it: gonio
// reads CAD files through io/model/cad.h, which runs the helper as a child
// process with a time limit, so that what OpenCASCADE does on hostile bytes
// (a crash, a hang, unbounded memory) cannot take gonio down, and so that
// its ~60 shared libraries are not loaded at every start of gonio.
//
// - XCAF (STEPCAFControl_Reader, IGESCAFControl_Reader) keeps the product
//   names, the colours (surface colour, else generic colour; of the part,
//   its faces and its components), the layers and the assembly tree. Each
//   shape label that is not an assembly is one CadPart, tessellated once;
//   each of its occurrences in the tree one CadPlacement with the product
//   of the components' locations.
// - Units: OpenCASCADE converts the file's length unit to millimetres; the
//   parts are stored in metres, and the file's own unit is reported
//   (CadModel::file_unit).
// - Tessellation: BRepMesh_IncrementalMesh per part with the angular and
//   chordal deflections of CadTessellation; with exact_normals, every
//   vertex's normal is the surface's at the vertex's (u, v)
//   (GeomLib::NormEstim, which also handles poles), the average of the
//   adjacent facets' where the surface has none. Faces of REVERSED
//   orientation have their triangles and normals turned.
// - Errors name the file and the STEP entity (#123) where OpenCASCADE says
//   which, or the part (its assembly path): unreadable or empty files,
//   parse failures, references to missing entities, files without any
//   shape, faces whose meshing failed, non-finite coordinates. A shell that
//   does not close (free edges) is a warning naming the part: it matters
//   only for refractive parts, which the model checks then refuse.
#pragma once

#include <string>

#include "io/model/cad_model.h"
#include "photometry/diagnostics.h"

namespace gonio::io {

// Reads and tessellates `path` (STEP by its ISO-10303-21 header, else IGES
// by its extension .igs/.iges), in this process. `parallel`: BRepMesh may
// mesh faces on several threads (the same triangles either way).
Result<CadModel> read_cad_file(const std::string& path, const CadTessellation& tessellation,
                               bool parallel = true);

}  // namespace gonio::io

#include "io/model/step_export.h"

namespace gonio::io {

// Writes `request` as a STEP AP214 file at `path` (millimetres), in this
// process: each part's profile points approximated by a B-spline curve
// (GeomAPI_PointsToBSpline, degree 3…8, C2, within request.tolerance_mm of
// every point) in the XZ plane, turned about the Z axis
// (BRepPrimAPI_MakeRevol: a face on a surface of revolution whose meridian
// is that B-spline), each a shape named by its part name (XCAF, STEP product
// names), the components of one assembly named request.product. `max_deviation_mm`: the
// largest distance of a point from its part's curve.
Status write_step_file(const StepExport& request, const std::string& path, double* max_deviation_mm = nullptr);

}  // namespace gonio::io
