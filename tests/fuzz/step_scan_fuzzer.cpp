// libFuzzer harness: Gonio's own reading of a STEP file before OpenCASCADE
// sees it (io/model/step_references.h) — the header check, the one pass over
// the text that finds the instances and their references (strings, binaries,
// comments, complex instances, the line count) and the depth-first walk that
// refuses circles through shape entities and chains deeper than the limit.
// No file, no OpenCASCADE: thousands of executions a second, where the
// harness of the whole reader (step_fuzzer.cpp) makes a few.
//
// What it checks beyond crashes and sanitizer reports:
// - an error names the file and a line the text has (or none);
// - the statistics are consistent: at most as many entities as '=' and
//   references as '#' in the text, shape entities ascending and among the
//   entities, a depth of at least 1 where there are entities and never
//   over the limit, a first harmless circle described where one was counted;
// - the same text one line lower (a newline put in front) gives the same
//   verdict, the same statistics, and an error one line lower;
// - an accepted text whose chain is `depth` deep is refused, naming the
//   nesting, under the limit depth − 1.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/model/step_references.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

using gonio::Result;
using gonio::io::StepReferenceStats;

void check_error(const gonio::Error& e, std::size_t lines, const char* what) {
  if (e.where.file != "fuzz.step") gonio::fuzz::finding(std::string(what) + ": the error does not name the file");
  if (e.where.line < 0 || static_cast<std::size_t>(e.where.line) > lines)
    gonio::fuzz::finding(std::string(what) + ": the error names line " + std::to_string(e.where.line) +
                         " of a text of " + std::to_string(lines) + " lines");
  if (e.message.empty()) gonio::fuzz::finding(std::string(what) + ": an error without a message");
}

// The text's newlines, '=' and '#', in one pass left out of libFuzzer's
// coverage and comparison tracing: the harness's own bookkeeping, which
// would otherwise cost as much as a scan.
struct Counts {
  std::size_t lines = 1, equals = 0, hashes = 0;
};
__attribute__((no_sanitize("coverage"))) Counts count_bytes(std::string_view text) {
  Counts c;
  for (char ch : text) {
    c.lines += ch == '\n';
    c.equals += ch == '=';
    c.hashes += ch == '#';
  }
  return c;
}

bool same_stats(const StepReferenceStats& a, const StepReferenceStats& b) {
  return a.entities == b.entities && a.references == b.references && a.depth == b.depth &&
         a.harmless_cycles == b.harmless_cycles && a.shape_entities == b.shape_entities;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gonio;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const Counts counts = count_bytes(text);
  const std::size_t lines = counts.lines;

  // The header: leading white space does not change the verdict.
  const bool header = io::has_step_header(text);
  if (size < 200 && io::has_step_header(" " + std::string(text)) != header)
    fuzz::finding("has_step_header changed its verdict for a leading space");

  Result<StepReferenceStats> r = io::check_step_references(text, "fuzz.step");
  const std::string lower = "\n" + std::string(text);
  Result<StepReferenceStats> shifted = io::check_step_references(lower, "fuzz.step");
  if (r.ok() != shifted.ok()) fuzz::finding("a newline in front changed the verdict of check_step_references");

  if (!r.ok()) {
    check_error(r.error(), lines, "check_step_references");
    check_error(shifted.error(), lines + 1, "check_step_references, one line lower");
    const int expected = r.error().where.line > 0 ? r.error().where.line + 1 : 0;
    if (shifted.error().where.line != expected)
      fuzz::finding("one line lower, the error names line " + std::to_string(shifted.error().where.line) +
                    " instead of " + std::to_string(expected));
    return 0;
  }

  const StepReferenceStats& s = *r;
  if (s.entities > counts.equals) fuzz::finding("more entities than '=' in the text");
  if (s.references > counts.hashes)
    fuzz::finding("more references than '#' in the text");
  if (s.shape_entities.size() > s.entities) fuzz::finding("more shape entities than entities");
  if (!std::is_sorted(s.shape_entities.begin(), s.shape_entities.end()))
    fuzz::finding("the shape entities are not in ascending order");
  for (std::uint64_t id : s.shape_entities)
    if (!s.is_shape_entity(id)) fuzz::finding("is_shape_entity does not find a listed shape entity");
  if ((s.entities > 0) != (s.depth > 0)) fuzz::finding("a depth of 0 with entities, or more than 0 without");
  if (s.depth > io::kMaxStepReferenceDepth || s.depth > s.entities)
    fuzz::finding("a depth over the limit or over the number of entities");
  if ((s.harmless_cycles > 0) != !s.first_harmless_cycle.empty())
    fuzz::finding("harmless circles counted without the first described, or the reverse");
  if (!same_stats(s, *shifted)) fuzz::finding("a newline in front changed the statistics");

  if (s.depth > 0) {
    Result<StepReferenceStats> tight = io::check_step_references(text, "fuzz.step", s.depth - 1);
    if (tight.ok()) fuzz::finding("a text whose references nest " + std::to_string(s.depth) +
                                  " deep was accepted under the limit " + std::to_string(s.depth - 1));
    check_error(tight.error(), lines, "check_step_references under a tighter limit");
    if (tight.error().message.find(" nest ") == std::string::npos)
      fuzz::finding("under a tighter limit the error is not the nesting: " + tight.error().message);
  }
  return 0;
}
