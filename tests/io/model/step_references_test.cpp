// The check of a STEP file's references before OpenCASCADE reads it
// (io/model/step_references.h): cycles and deep chains are errors naming
// the entities and their lines; strings, binaries and comments hold no
// references.
#include "io/model/step_references.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

const std::string kHead =
    "ISO-10303-21;\n"
    "HEADER;\n"
    "FILE_DESCRIPTION(('#1 in a string; not a reference'),'2;1');\n"
    "FILE_NAME('x','2026',('#2'),(''),'','','');\n"
    "FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\n"
    "ENDSEC;\n"
    "DATA;\n";  // the DATA section starts on line 8
const std::string kTail = "ENDSEC;\nEND-ISO-10303-21;\n";

TEST(StepReferences, CountsEntitiesReferencesAndTheLongestChain) {
  const std::string text = kHead +
                           "#1 = CARTESIAN_POINT('',(0.,0.,0.));\n"
                           "#2 = DIRECTION('',(0.,0.,1.));\n"
                           "#3 = AXIS2_PLACEMENT_3D('',#1,#2,$);\n"
                           "#4 = CIRCLE('',#3,5.);\n"
                           "#5 = TRIMMED_CURVE('',#4,(#1),(#1),.T.,.CARTESIAN.);\n" + kTail;
  Result<StepReferenceStats> r = check_step_references(text, "a.step");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->entities, 5u);
  EXPECT_EQ(r->references, 6u);  // #3: 2, #4: 1, #5: 3
  EXPECT_EQ(r->depth, 4u);       // #5 → #4 → #3 → #1
  EXPECT_EQ(r->shape_entities, (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
}

TEST(StepReferences, AnEntityThatRefersToItselfIsNamedWithItsLine) {
  // What the fuzzer made of a FreeCAD file: OpenCASCADE's
  // StepToGeom::MakeCurve recursed on it until the stack ran out.
  const std::string text = kHead +
                           "#1 = CARTESIAN_POINT('',(0.,0.,0.));\n"
                           "#26 = SEAM_CURVE('',#26,(#1),\n  .PCURVE_S1.);\n" + kTail;
  Result<StepReferenceStats> r = check_step_references(text, "seam.step");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.file, "seam.step");
  EXPECT_EQ(r.error().where.line, 9);
  EXPECT_NE(r.error().message.find("#26 (line 9) refers to itself"), std::string::npos) << r.error().message;
}

TEST(StepReferences, ACircleThroughSeveralEntitiesIsNamedInOrder) {
  const std::string text = kHead +
                           "#1 = TRIMMED_CURVE('',#2,(),(),.T.,.UNSPECIFIED.);\n"
                           "/* a comment #1 with a reference-like word */\n"
                           "#2 = SURFACE_CURVE('',#3,(),.CURVE_3D.);\n"
                           "#3 = OFFSET_CURVE_3D('',#1,1.,.F.,#4);\n"
                           "#4 = DIRECTION('',(0.,0.,1.));\n" + kTail;
  Result<StepReferenceStats> r = check_step_references(text, "c.step");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.line, 8);
  EXPECT_NE(r.error().message.find("#1 (line 8) → #2 (line 10) → #3 (line 11) → #1"), std::string::npos)
      << r.error().message;
}

TEST(StepReferences, ACircleThroughAComplexInstancesCurveTypeIsRefused) {
  const std::string text = kHead +
                           "#1 = ( BOUNDED_CURVE() B_SPLINE_CURVE(1,(#2,#2),.UNSPECIFIED.,.F.,.F.)\n"
                           "  CURVE() GEOMETRIC_REPRESENTATION_ITEM() REPRESENTATION_ITEM('') );\n"
                           "#2 = POINT_ON_CURVE('',#1,0.5);\n" + kTail;
  Result<StepReferenceStats> r = check_step_references(text, "x.step");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("#1 (line 8) → #2 (line 10) → #1"), std::string::npos) << r.error().message;
}

TEST(StepReferences, ACircleAmongPropertiesIsPassedOverAndDescribed) {
  // As in the CAx-IF file dm1-oc-214.stp, which OpenCASCADE reads: a
  // material's density REPRESENTATION lists itself among its items.
  const std::string text = kHead +
                           "#1 = ( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n"
                           "#2 = REPRESENTATION_CONTEXT('','');\n"
                           "#3 = REPRESENTATION('density',(#3),#2);\n"
                           "#4 = PROPERTY_DEFINITION_REPRESENTATION(#5,#3);\n"
                           "#5 = PROPERTY_DEFINITION('material property','',#4);\n" + kTail;
  Result<StepReferenceStats> r = check_step_references(text, "p.step");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->harmless_cycles, 2u);
  EXPECT_EQ(r->first_harmless_cycle, "entity #3 (line 10) refers to itself");
  EXPECT_EQ(r->entities, 5u);
  // The unit and the context scale shapes; the property's entities do not.
  EXPECT_EQ(r->shape_entities, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_TRUE(r->is_shape_entity(2));
  EXPECT_FALSE(r->is_shape_entity(3));
}

TEST(StepReferences, ChainsUpToTheLimitPassAndOneLongerIsRefused) {
  auto chain = [](std::size_t n) {
    std::string t = kHead;
    for (std::size_t k = 1; k < n; ++k)
      t += "#" + std::to_string(k) + "=TRIMMED_CURVE('',#" + std::to_string(k + 1) + ",(),(),.T.,.UNSPECIFIED.);\n";
    t += "#" + std::to_string(n) + "=DIRECTION('',(0.,0.,1.));\n";
    return t + kTail;
  };
  Result<StepReferenceStats> ok = check_step_references(chain(kMaxStepReferenceDepth), "ok.step");
  ASSERT_TRUE(ok.ok()) << to_string(ok.error());
  EXPECT_EQ(ok->depth, kMaxStepReferenceDepth);
  Result<StepReferenceStats> deep = check_step_references(chain(kMaxStepReferenceDepth + 1), "deep.step");
  ASSERT_FALSE(deep.ok());
  EXPECT_NE(deep.error().message.find("nest 1001 entities deep"), std::string::npos) << deep.error().message;
  // A chain a hundred times longer costs no stack of ours.
  EXPECT_FALSE(check_step_references(chain(100 * kMaxStepReferenceDepth), "deeper.step").ok());
}

TEST(StepReferences, StringsBinariesAndCommentsHoldNoReferences) {
  const std::string text = kHead +
                           "#1 = PRODUCT('it''s #1; really','#1',\n'line two #1',(#2));\n"
                           "#2 = PRODUCT_CONTEXT('',#3,'mechanical /* not a comment #2 */');\n"
                           "#3 = APPLICATION_CONTEXT(\"0FF\");\n"
                           "#4 = DUMMY(/* #4 */ #1);\n" + kTail;
  Result<StepReferenceStats> r = check_step_references(text, "s.step");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->entities, 4u);
  EXPECT_EQ(r->references, 3u);  // #1 → #2 → #3, #4 → #1
  EXPECT_EQ(r->depth, 4u);
}

TEST(StepReferences, MissingTargetsAreLeftToTheReaderAndBrokenTextIsNamed) {
  Result<StepReferenceStats> missing = check_step_references(kHead + "#1 = A(#999);\n" + kTail, "m.step");
  ASSERT_TRUE(missing.ok());
  EXPECT_EQ(missing->references, 0u);
  struct Case {
    std::string text;
    int line;
    const char* says;
  };
  const Case cases[] = {
      {kHead + "#1 = A('open\n\n", 8, "string (') that is never closed"},
      {kHead + "#1 = A(1);\n/* open\n", 9, "comment (/*) that is never closed"},
      {kHead + "#1 = A(\"0F\n", 8, "binary value"},
      {kHead + "#1234567890123456789 = A();\n", 8, "more than 18 digits"},
  };
  for (const Case& c : cases) {
    test::offer_fuzz_seed("step", c.text);
    Result<StepReferenceStats> r = check_step_references(c.text, "b.step");
    ASSERT_FALSE(r.ok()) << c.says;
    EXPECT_EQ(r.error().where.line, c.line) << c.says;
    EXPECT_NE(r.error().message.find(c.says), std::string::npos) << r.error().message;
  }
}

TEST(StepReferences, TheHeaderIsLookedForAfterWhiteSpaceInTheFirst256Bytes) {
  // gonio-cad reads a file without it as IGES (by its name) or refuses it.
  EXPECT_TRUE(has_step_header(kHead));
  EXPECT_TRUE(has_step_header(" \t\r\n\v\f" + kHead));
  EXPECT_TRUE(has_step_header("ISO-10303-21;"));
  EXPECT_FALSE(has_step_header("ISO-10303-21"));            // cut short
  EXPECT_FALSE(has_step_header("iso-10303-21;\nHEADER;"));  // the keyword is upper case
  EXPECT_FALSE(has_step_header("/* */ISO-10303-21;"));     // a comment is not white space here
  EXPECT_FALSE(has_step_header(""));
  EXPECT_TRUE(has_step_header(std::string(243, ' ') + "ISO-10303-21;"));  // ends at byte 256
  EXPECT_FALSE(has_step_header(std::string(244, ' ') + "ISO-10303-21;"));
}

}  // namespace
}  // namespace gonio::io
