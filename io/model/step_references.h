// The instance references of a STEP file (an ISO 10303-21 exchange
// structure), checked before OpenCASCADE reads it.
//
// OpenCASCADE's translators follow references by recursion
// (StepToGeom::MakeCurve calls itself for a SEAM_CURVE's or TRIMMED_CURVE's
// basis curve, and so on), without a guard: a file in which an entity
// refers, directly or through others, to itself makes it recurse until the
// stack runs out, and so does a long enough chain. Conforming files hold
// neither: the application protocols forbid cycles in their where-rules
// (ISO 10303-42's acyclic_curve_replica and acyclic_surface_replica,
// ISO 10303-43's acyclic_mapped_representation, ISO 10303-41's
// acyclic_product_definition_relationship), and their reference chains are
// short (docs/cad.md gives the depths of the files we test with). So a
// cycle through an entity of a type shapes are made of (geometry, topology,
// mapped items, the assembly structure, units) or a chain
// deeper than the limit is an error naming the entities and their lines,
// found by one pass over the text and one depth-first walk of the
// references, both linear in the file's size; gonio-cad then never hands
// such a file to OpenCASCADE. Exporters do write other cycles (a CAx-IF
// test file's density REPRESENTATION lists itself among its items):
// OpenCASCADE reads those, and they are reported, not refused.
//
// What is read: every `#N = …;` instance in the file (HEADER entities have
// no instance name and are passed over), the `#M` references in its
// parameters, with strings ('…', '' inside), binaries ("…") and comments
// (/* … */) skipped. References to entities the file does not hold are
// left to OpenCASCADE, which reports them by name.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

// The deepest chain of references accepted: #1 → #2 → … → #N counts N.
inline constexpr std::size_t kMaxStepReferenceDepth = 1000;

struct StepReferenceStats {
  std::size_t entities = 0;     // instances `#N = …;`
  std::size_t references = 0;   // `#M` inside them, to entities the file holds
  std::size_t depth = 0;        // the longest chain of references, in entities
  // Cycles among entities of types OpenCASCADE does not follow by
  // recursion (a property's representation that lists itself among its
  // items): passed over, and the first described for a warning.
  std::size_t harmless_cycles = 0;
  std::string first_harmless_cycle;
  // The numbers of the entities of the types shapes are made of (geometry,
  // topology, mapped items, the assembly structure, units and contexts),
  // ascending: damage OpenCASCADE finds in one of these loses or misplaces
  // a shape; damage elsewhere (a property, a style, a text) does not.
  std::vector<std::uint64_t> shape_entities;
  bool is_shape_entity(std::uint64_t id) const;
};

// Whether `text`, a file's content, begins (after white space, within its
// first 256 bytes) with STEP's ISO-10303-21 header; gonio-cad reads a file
// without it as IGES where its name ends .igs or .iges, else refuses it.
bool has_step_header(std::string_view text);

// Checks `text`, the content of `file` (named in errors, with the line of
// the entity concerned).
Result<StepReferenceStats> check_step_references(std::string_view text, const std::string& file,
                                                 std::size_t max_depth = kMaxStepReferenceDepth);

}  // namespace gonio::io
