// The only file that includes OpenCASCADE's headers (io/model/step.h).
#include "io/model/step.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <gp_Trsf.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <gp_Pln.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <GeomAPI_PointsToBSpline.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Precision.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <Geom_BSplineCurve.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <gp_Ax1.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GeomLib.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESCAFControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <Poly_Triangulation.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <StepData_StepModel.hxx>
#include <TCollection_AsciiString.hxx>
#include <TCollection_ExtendedString.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TDF_ChildIterator.hxx>
#include <TDF_Label.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDF_Tool.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Vertex.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_LayerTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <gp_Trsf.hxx>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include "io/model/step_references.h"
#include "photometry/format.h"

namespace gonio::io {
namespace {

// OpenCASCADE's messages: never on the console; the failures and alarms of
// the current read are kept for the error text.
class CollectingPrinter : public Message_Printer {
 public:
  mutable std::vector<std::string> messages;

 protected:
  void send(const TCollection_AsciiString& text, const Message_Gravity gravity) const override {
    if (gravity >= Message_Alarm && messages.size() < 20) messages.emplace_back(text.ToCString());
  }
};

Handle(CollectingPrinter) quiet_messenger() {
  static Handle(CollectingPrinter) printer;
  static std::once_flag once;
  std::call_once(once, [] {
    const Handle(Message_Messenger)& m = Message::DefaultMessenger();
    m->RemovePrinters(STANDARD_TYPE(Message_Printer));
    while (m->Printers().Size() > 0) m->RemovePrinter(m->Printers().First());
    printer = new CollectingPrinter();
    m->AddPrinter(printer);
  });
  printer->messages.clear();
  return printer;
}

std::string utf8(const TCollection_ExtendedString& s) {
  return TCollection_AsciiString(s, '\0').ToCString();
}

std::string trimmed(std::string s, bool asterisks = false) {
  auto junk = [&](char c) { return std::isspace(static_cast<unsigned char>(c)) || (asterisks && c == '*'); };
  while (!s.empty() && junk(s.back())) s.pop_back();
  std::size_t i = 0;
  while (i < s.size() && junk(s[i])) ++i;
  return s.substr(i);
}

// A message of OpenCASCADE's on one line, without the asterisks its STEP
// parser frames them with ("**** ERR StepFile : … ****").
std::string message_text(const std::string& s) {
  std::string out = trimmed(s, true);
  for (char& c : out)
    if (c == '\n' || c == '\r') c = ' ';
  return out;
}

bool is_iges_path(const std::string& path) {
  std::string ext;
  const std::size_t dot = path.rfind('.');
  if (dot != std::string::npos)
    for (char c : path.substr(dot)) ext += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".igs" || ext == ".iges";
}

sim::Affine to_affine(const gp_Trsf& t, double unit_m) {
  sim::Affine a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a.m[r][c] = t.Value(r + 1, c + 1);
  a.offset = Vec3{t.Value(1, 4), t.Value(2, 4), t.Value(3, 4)} * unit_m;
  return a;
}

constexpr double kCoveredArea = 0.99;

struct ColourKey {
  bool has = false;
  float r = 0, g = 0, b = 0;
  bool operator<(const ColourKey& o) const {
    return std::tie(has, r, g, b) < std::tie(o.has, o.r, o.g, o.b);
  }
};

class CadReader {
 public:
  CadReader(std::string path, const CadTessellation& t, bool parallel, Handle(CollectingPrinter) printer)
      : path_(std::move(path)), tess_(t), parallel_(parallel), printer_(std::move(printer)) {}

  Result<CadModel> read();
  // The file's free shapes (its top-level products) with their names, as
  // read() names them, untessellated [mm]: what the STEP export places
  // (StepRevolvedPart::file).
  Result<std::vector<std::pair<std::string, TopoDS_Shape>>> free_shapes();

 private:
  Error fail(std::string message) const { return make_error(path_, std::move(message)); }
  void warn(const char* code, std::string message) {
    model_.findings.push_back({Severity::Warning, code, std::move(message), {path_}});
  }
  // "#123" of the file's entity that became `shape`, or empty.
  std::string entity_of(const TopoDS_Shape& shape) const;
  std::string entity_label(const Handle(Standard_Transient)& ent) const;
  // The fails (and, unless fails_only, warnings) of a check list, each with
  // its entity, of the entities `take` accepts (by their "#12"; all where
  // empty).
  std::string checks_text(const Interface_CheckIterator& checks, bool fails_only,
                          const std::function<bool(const std::string&)>& take = {}) const;
  std::string name_of(const TDF_Label& label) const;
  // The free shapes' names: each label's name, else its STEP entity, else
  // partN; a repeated name gets [2], [3], ….
  std::vector<std::string> root_names(const TDF_LabelSequence& roots) const;
  std::optional<sim::Vec3f> colour_of(const TDF_Label& label) const;
  std::vector<std::string> layers_of(const TDF_Label& label) const;

  Status read_step();
  Status read_iges();
  Status walk(const TDF_Label& label, const TopLoc_Location& location, const std::string& path,
              const std::optional<sim::Vec3f>& colour, const std::vector<std::string>& layers, int depth);
  // The part of a shape label, tessellated at its first occurrence; none
  // where the shape has no faces (wires, points, or nothing: the product of
  // an external reference), which is left out with a warning, once.
  Result<std::optional<std::uint32_t>> part(const TDF_Label& label, const std::string& path);
  Status tessellate(const TopoDS_Shape& shape, CadPart& part, const std::string& what,
                    const TDF_Label& label);
  Result<double> collect(const TopoDS_Shape& shape, CadPart& part, const std::string& what,
                         const std::map<const void*, sim::Vec3f>& face_colours,
                         std::map<ColourKey, std::size_t>& surface_of) const;

  std::string path_;
  CadTessellation tess_;
  bool parallel_;
  Handle(CollectingPrinter) printer_;
  Handle(TDocStd_Document) doc_;
  Handle(XCAFDoc_ShapeTool) shapes_;
  Handle(XCAFDoc_ColorTool) colours_;
  Handle(XCAFDoc_LayerTool) layers_;
  Handle(XSControl_WorkSession) session_;
  Handle(Interface_InterfaceModel) file_model_;
  StepReferenceStats references_;  // of a STEP file, read before OpenCASCADE reads it
  double unit_m_ = 0.001;  // metres per unit of the shapes (OpenCASCADE's millimetres)
  CadModel model_;
  std::map<std::string, std::optional<std::uint32_t>> parts_;  // shape label entry → part (none: left out)
  std::string first_left_out_;                                 // why the first part left out was
};

std::string CadReader::entity_label(const Handle(Standard_Transient)& ent) const {
  if (ent.IsNull() || file_model_.IsNull()) return {};
  Handle(TCollection_HAsciiString) label = file_model_->StringLabel(ent);
  if (label.IsNull()) return {};
  return label->ToCString();
}

std::string CadReader::entity_of(const TopoDS_Shape& shape) const {
  if (session_.IsNull() || session_->TransferReader().IsNull()) return {};
  try {
    return entity_label(session_->TransferReader()->EntityFromShapeResult(shape, 1));
  } catch (const Standard_Failure&) {
    return {};
  }
}

// "#12: message; #40: message", at most eight.
std::string CadReader::checks_text(const Interface_CheckIterator& checks, bool fails_only,
                                   const std::function<bool(const std::string&)>& take) const {
  std::string out;
  int shown = 0, more = 0;
  for (checks.Start(); checks.More(); checks.Next()) {
    const Handle(Interface_Check)& c = checks.Value();
    if (c.IsNull()) continue;
    std::string where = entity_label(c->Entity());
    if (where.empty() && !file_model_.IsNull() && checks.Number() > 0 &&
        checks.Number() <= file_model_->NbEntities())
      where = entity_label(file_model_->Value(checks.Number()));
    if (take && !take(where)) continue;
    auto add = [&](const char* text) {
      if (shown >= 8) {
        ++more;
        return;
      }
      out += (out.empty() ? "" : "; ") + (where.empty() ? std::string() : "entity " + where + ": ") +
             message_text(text ? text : "");
      ++shown;
    };
    for (int i = 1; i <= c->NbFails(); ++i) add(c->CFail(i));
    if (!fails_only)
      for (int i = 1; i <= c->NbWarnings(); ++i) add(c->CWarning(i));
  }
  if (more > 0) out += "; and " + std::to_string(more) + " more";
  return out;
}

std::string CadReader::name_of(const TDF_Label& label) const {
  Handle(TDataStd_Name) name;
  if (!label.FindAttribute(TDataStd_Name::GetID(), name)) return {};
  return trimmed(utf8(name->Get()));
}

std::optional<sim::Vec3f> CadReader::colour_of(const TDF_Label& label) const {
  Quantity_Color c;
  if (!colours_->GetColor(label, XCAFDoc_ColorSurf, c) && !colours_->GetColor(label, XCAFDoc_ColorGen, c))
    return std::nullopt;
  double r = 0, g = 0, b = 0;
  c.Values(r, g, b, Quantity_TOC_sRGB);
  return sim::Vec3f{static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)};
}

std::vector<std::string> CadReader::layers_of(const TDF_Label& label) const {
  std::vector<std::string> out;
  Handle(TColStd_HSequenceOfExtendedString) names;
  if (layers_.IsNull()) return out;
  names = layers_->GetLayers(label);
  if (names.IsNull()) return out;
  for (int i = 1; i <= names->Length(); ++i) out.push_back(trimmed(utf8(names->Value(i))));
  return out;
}

Status CadReader::read_step() {
  // The header, then the references: a cycle or a deep chain of them would
  // make OpenCASCADE's translators recurse until the stack runs out
  // (io/model/step_references.h). Both are Gonio's own code, which the
  // in-process harness tests/fuzz/step_scan_fuzzer.cpp fuzzes apart from
  // OpenCASCADE.
  {
    std::ifstream in(path_, std::ios::binary);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (!in.good() && !in.eof()) return fail("cannot read the file");
    if (!has_step_header(text)) return fail("not a STEP file: it does not begin with the ISO-10303-21 header");
    Result<StepReferenceStats> refs = check_step_references(text, path_);
    if (!refs.ok()) return refs.error();
    references_ = std::move(*refs);
    if (references_.harmless_cycles > 0)
      warn("step-reference-cycle",
           references_.first_harmless_cycle +
               (references_.harmless_cycles > 1
                    ? " (and " + std::to_string(references_.harmless_cycles - 1) + " more circles)"
                    : std::string()) +
               ": the file is damaged there, in entities no shape is made of");
  }
  STEPCAFControl_Reader reader;
  reader.SetColorMode(true);
  reader.SetNameMode(true);
  reader.SetLayerMode(true);
  const IFSelect_ReturnStatus status = reader.ReadFile(path_.c_str());
  STEPControl_Reader& step = reader.ChangeReader();
  session_ = step.WS();
  file_model_ = step.Model();
  if (!file_model_.IsNull() && file_model_->NbEntities() == 0)
    return fail("the STEP file holds no entities (its DATA section is empty or unreadable)");
  if (status != IFSelect_RetDone) {
    std::string why;
    for (const std::string& m : printer_->messages) why += (why.empty() ? "" : "; ") + message_text(m);
    if (why.empty() && !session_.IsNull()) why = checks_text(session_->ModelCheckList(), true);
    return fail("not a readable STEP file" + (why.empty() ? std::string() : ": " + why));
  }
  if (file_model_.IsNull() || file_model_->NbEntities() == 0) return fail("the STEP file holds no entities");
  // Parse errors the reader got past (a reference to a missing entity, a
  // wrong parameter) are errors: the part they hit would be missing.
  // Damage in an entity no shape is made of (a property, a style, a text;
  // io/model/step_references.h) loses only that: a warning.
  auto shape_entity = [this](const std::string& where) {
    if (where.size() < 2 || where[0] != '#') return true;
    char* end = nullptr;
    const unsigned long long id = std::strtoull(where.c_str() + 1, &end, 10);
    return *end != '\0' || references_.is_shape_entity(id);
  };
  const std::string fails = checks_text(session_->ModelCheckList(), true, shape_entity);
  if (!fails.empty()) return fail("the STEP file is damaged: " + fails);
  const std::string other =
      checks_text(session_->ModelCheckList(), true, [&](const std::string& where) { return !shape_entity(where); });
  if (!other.empty())
    warn("step-damaged-entity", "the STEP file is damaged in entities no shape is made of, read without them: " + other);

  TColStd_SequenceOfAsciiString lengths, angles, solid_angles;
  step.FileUnits(lengths, angles, solid_angles);
  if (lengths.Length() > 0) model_.file_unit = lengths.Value(1).ToCString();
  model_.format = "STEP";

  if (!reader.Transfer(doc_)) {
    const std::string why = checks_text(session_->TransferReader()->TransientProcess()->CheckList(false), true);
    return fail("OpenCASCADE could not turn the STEP file's entities into shapes" +
                (why.empty() ? std::string() : ": " + why));
  }
  const std::string transfer_fails =
      checks_text(session_->TransferReader()->TransientProcess()->CheckList(false), true);
  if (!transfer_fails.empty())
    warn("cad-transfer", "OpenCASCADE reported while making shapes: " + transfer_fails);
  return Ok{};
}

Status CadReader::read_iges() {
  IGESCAFControl_Reader reader;
  reader.SetColorMode(true);
  reader.SetNameMode(true);
  reader.SetLayerMode(true);
  const IFSelect_ReturnStatus status = reader.ReadFile(path_.c_str());
  session_ = reader.WS();
  file_model_ = reader.Model();
  if (status != IFSelect_RetDone) {
    std::string why = session_.IsNull() ? std::string() : checks_text(session_->ModelCheckList(), true);
    return fail("not a readable IGES file" + (why.empty() ? std::string() : ": " + why));
  }
  if (file_model_.IsNull() || file_model_->NbEntities() == 0) return fail("the IGES file holds no entities");
  model_.format = "IGES";
  if (Handle(IGESData_IGESModel) im = Handle(IGESData_IGESModel)::DownCast(file_model_); !im.IsNull()) {
    const IGESData_GlobalSection& g = im->GlobalSection();
    if (!g.UnitName().IsNull()) model_.file_unit = g.UnitName()->ToCString();
  }
  if (!reader.Transfer(doc_)) {
    const std::string why = checks_text(session_->TransferReader()->TransientProcess()->CheckList(false), true);
    return fail("OpenCASCADE could not turn the IGES file's entities into shapes" +
                (why.empty() ? std::string() : ": " + why));
  }
  return Ok{};
}

Status CadReader::tessellate(const TopoDS_Shape& shape, CadPart& part, const std::string& what,
                             const TDF_Label& label) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box);
  if (box.IsVoid()) return fail(what + ": the part has no extent");
  const double size = std::sqrt(box.SquareExtent());  // [file units after conversion: mm]
  if (!std::isfinite(size)) return fail(what + ": the part's coordinates are not finite");
  part.size_m = size * unit_m_;
  double chordal_m =
      tess_.chordal_m > 0.0 ? tess_.chordal_m : std::max(tess_.chordal_relative * part.size_m, tess_.chordal_min_m);
  const double target = tess_.angular_deflection_deg * M_PI / 180.0;

  // Colours of sub-shapes (faces, or shells and solids holding faces).
  std::map<const void*, sim::Vec3f> face_colours;
  for (TDF_ChildIterator it(label, false); it.More(); it.Next()) {
    const TopoDS_Shape sub = shapes_->GetShape(it.Value());
    if (sub.IsNull()) continue;
    const std::optional<sim::Vec3f> c = colour_of(it.Value());
    if (!c) continue;
    for (TopExp_Explorer f(sub, TopAbs_FACE); f.More(); f.Next())
      face_colours[f.Current().TShape().get()] = *c;
  }

  std::map<ColourKey, std::size_t> surface_of;
  for (TopExp_Explorer s(shape, TopAbs_SOLID); s.More(); s.Next()) ++part.solids;
  // Shells with free edges (an edge of one face only).
  std::size_t open_shells = 0;
  for (TopExp_Explorer s(shape, TopAbs_SHELL); s.More(); s.Next()) {
    TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
    TopExp::MapShapesAndAncestors(s.Current(), TopAbs_EDGE, TopAbs_FACE, edge_faces);
    for (int i = 1; i <= edge_faces.Extent(); ++i) {
      const TopoDS_Edge& e = TopoDS::Edge(edge_faces.FindKey(i));
      if (edge_faces(i).Extent() == 1 && !BRep_Tool::Degenerated(e)) {
        ++open_shells;
        break;
      }
    }
  }
  // A sheet (a reflector) need not close; a refractive part must, which
  // the model checks enforce on its mesh (open-volume).
  if (open_shells > 0)
    model_.findings.push_back({Severity::Info, "cad-open-shell",
                               what + ": " + std::to_string(open_shells) +
                                   " shell(s) do not close (edges of one face only): the part bounds no volume",
                               {path_}});

  // BRepMesh bounds the chordal deflection everywhere but the angle only
  // along edges (its interior meshers of spheres and tori, for one, follow
  // the deflection alone), so the angle is made good here: the part is
  // meshed again with a smaller deflection until no facet's normal is more
  // than the angular deflection off the surface's at its vertices (the
  // sagitta goes with the square of the angle a facet spans).
  double worst = 0.0;
  for (int round = 0;; ++round) {
    BRepTools::Clean(shape);
    BRepMesh_IncrementalMesh mesher(shape, chordal_m / unit_m_, false, std::min(target, 0.5), parallel_);
    (void)mesher;
    part.surfaces.clear();
    part.faces = 0;
    surface_of.clear();
    Result<double> w = collect(shape, part, what, face_colours, surface_of);
    if (!w.ok()) return w.error();
    worst = *w;
    part.chordal_m = chordal_m;
    if (worst <= target || tess_.chordal_m > 0.0 || chordal_m <= tess_.chordal_min_m || round == 4) break;
    chordal_m = std::max(tess_.chordal_min_m, chordal_m * std::clamp(0.9 * (target / worst) * (target / worst), 0.02, 0.8));
  }
  if (worst > target * 1.0001 && tess_.chordal_m <= 0.0)
    warn("cad-angular-deflection",
         what + ": facets stay up to " + format_number(worst * 180.0 / M_PI, 3) + "° off the surface (asked " +
             format_number(tess_.angular_deflection_deg, 3) + "°) after four refinements, at a chordal deflection of " +
             format_number(chordal_m * 1e3, 3) + " mm");
  return Ok{};
}

// The part's faces as meshed, into its surfaces; the angle δ between a
// facet's normal and the surface's at its vertices (the largest of the
// three) that kCoveredArea of the part's area keeps within [rad].
Result<double> CadReader::collect(const TopoDS_Shape& shape, CadPart& part, const std::string& what,
                                  const std::map<const void*, sim::Vec3f>& face_colours,
                                  std::map<ColourKey, std::size_t>& surface_of) const {
  const double size = part.size_m / unit_m_;  // [the shapes' unit]
  std::vector<std::pair<double, double>> deviations;  // per facet: δ [rad], area
  for (TopExp_Explorer it(shape, TopAbs_FACE); it.More(); it.Next()) {
    const TopoDS_Face& face = TopoDS::Face(it.Current());
    ++part.faces;
    TopLoc_Location location;
    const Handle(Poly_Triangulation)& tri = BRep_Tool::Triangulation(face, location);
    if (tri.IsNull() || tri->NbTriangles() == 0) {
      const std::string entity = entity_of(face);
      return fail(what + ": face " + std::to_string(part.faces) +
                  (entity.empty() ? std::string() : " (entity " + entity + ")") +
                  " could not be meshed (OpenCASCADE's BRepMesh gave no triangles)");
    }
    const gp_Trsf trsf = location.Transformation();
    const bool reversed = face.Orientation() == TopAbs_REVERSED;

    ColourKey key;
    std::optional<sim::Vec3f> fc;
    if (auto f = face_colours.find(face.TShape().get()); f != face_colours.end()) fc = f->second;
    if (fc) key = {true, fc->x, fc->y, fc->z};
    auto [sit, added] = surface_of.try_emplace(key, part.surfaces.size());
    if (added) {
      part.surfaces.emplace_back();
      part.surfaces.back().colour = fc;
    }
    CadSurface& surface = part.surfaces[sit->second];
    const std::size_t base = surface.positions.size();
    if (base + static_cast<std::size_t>(tri->NbNodes()) > 0xffffffffu)
      return fail(what + ": more than 2³² vertices in one part");

    for (int i = 1; i <= tri->NbNodes(); ++i) {
      const gp_Pnt p = tri->Node(i).Transformed(trsf);
      if (!(std::isfinite(p.X()) && std::isfinite(p.Y()) && std::isfinite(p.Z())))
        return fail(what + ": face " + std::to_string(part.faces) + " has non-finite mesh coordinates");
      surface.positions.push_back(sim::to_float(Vec3{p.X(), p.Y(), p.Z()} * unit_m_));
    }
    const int triangles = tri->NbTriangles();
    std::vector<std::uint32_t> local;
    local.reserve(static_cast<std::size_t>(triangles) * 3);
    for (int i = 1; i <= triangles; ++i) {
      int a = 0, b = 0, c = 0;
      tri->Triangle(i).Get(a, b, c);
      if (reversed) std::swap(b, c);
      if (a < 1 || b < 1 || c < 1 || a > tri->NbNodes() || b > tri->NbNodes() || c > tri->NbNodes())
        return fail(what + ": face " + std::to_string(part.faces) + ": a triangle names a node out of range");
      local.push_back(static_cast<std::uint32_t>(a - 1));
      local.push_back(static_cast<std::uint32_t>(b - 1));
      local.push_back(static_cast<std::uint32_t>(c - 1));
    }
    {
      // Facet normals summed per vertex (area-weighted), for the vertices
      // where the surface gives none.
      std::vector<Vec3> facet(static_cast<std::size_t>(tri->NbNodes()));
      std::vector<Vec3> exact_normals(static_cast<std::size_t>(tri->NbNodes()));
      std::vector<char> has_exact(static_cast<std::size_t>(tri->NbNodes()), 0);
      for (std::size_t t = 0; t < local.size(); t += 3) {
        const Vec3 p0 = sim::to_double(surface.positions[base + local[t]]);
        const Vec3 n = cross(sim::to_double(surface.positions[base + local[t + 1]]) - p0,
                             sim::to_double(surface.positions[base + local[t + 2]]) - p0);
        for (int k = 0; k < 3; ++k) facet[local[t + static_cast<std::size_t>(k)]] += n;
      }
      TopoDS_Face bare = TopoDS::Face(face.Located(TopLoc_Location()));
      Handle(Geom_Surface) surf = BRep_Tool::Surface(bare);
      Handle(ShapeAnalysis_Surface) analysis = surf.IsNull() ? nullptr : new ShapeAnalysis_Surface(surf);
      for (int i = 1; i <= tri->NbNodes(); ++i) {
        Vec3 n = facet[static_cast<std::size_t>(i - 1)];
        if (!surf.IsNull() && tri->HasUVNodes()) {
          // BRepMesh's (u, v) of a node need not be where its point is (it
          // places some nodes in 3D): 0.015 mm off on a FreeCAD paraboloid,
          // turning the normal by 3e-4 rad. Where they differ, the point is
          // projected back onto the surface from there.
          gp_Pnt2d uv = tri->UVNode(i);
          const gp_Pnt node = tri->Node(i);
          if (surf->Value(uv.X(), uv.Y()).SquareDistance(node) > 1e-18 * size * size)
            uv = analysis->NextValueOfUV(uv, node, 1e-9 * size, 1e-3 * size);
          gp_Dir d;
          if (GeomLib::NormEstim(surf, uv, 1e-7, d) <= 1) {
            const gp_Dir w = d.Transformed(trsf);
            Vec3 exact{w.X(), w.Y(), w.Z()};
            if (reversed) exact = exact * -1.0;
            // A surface normal against the facets' is a seam of the
            // parametrisation gone wrong: keep the facets'.
            if (dot(exact, n) >= 0.0 || length(n) == 0.0) {
              n = exact;
              exact_normals[static_cast<std::size_t>(i - 1)] = exact;
              has_exact[static_cast<std::size_t>(i - 1)] = 1;
            }
          }
        }
        const double len = length(n);
        if (tess_.exact_normals) surface.normals.push_back(len > 0.0 ? sim::to_float(n / len) : sim::Vec3f{0, 0, 1});
      }
      // δ: each facet's normal against the surface's at its vertices.
      for (std::size_t t = 0; t < local.size(); t += 3) {
        const Vec3 p0 = sim::to_double(surface.positions[base + local[t]]);
        const Vec3 n = cross(sim::to_double(surface.positions[base + local[t + 1]]) - p0,
                             sim::to_double(surface.positions[base + local[t + 2]]) - p0);
        const double len = length(n);
        if (!(len > 0.0)) continue;
        double delta = 0.0;
        for (int k = 0; k < 3; ++k) {
          const std::size_t v = local[t + static_cast<std::size_t>(k)];
          if (!has_exact[v]) continue;
          const double c = std::clamp(dot(n / len, exact_normals[v]), -1.0, 1.0);
          delta = std::max(delta, std::acos(c));
        }
        deviations.emplace_back(delta, len);
      }
    }
    for (std::uint32_t v : local) surface.indices.push_back(static_cast<std::uint32_t>(base) + v);
  }
  // The deviation that 99 % of the part's area keeps within: slivers along
  // seams and at poles, which BRepMesh leaves at any deflection, tilt by
  // degrees but catch almost no light.
  std::sort(deviations.begin(), deviations.end());
  double total = 0.0;
  for (const auto& d : deviations) total += d.second;
  double covered = 0.0;
  for (const auto& d : deviations) {
    covered += d.second;
    if (covered >= kCoveredArea * total) return d.first;
  }
  return deviations.empty() ? 0.0 : deviations.back().first;
}

Result<std::optional<std::uint32_t>> CadReader::part(const TDF_Label& label, const std::string& path) {
  TCollection_AsciiString entry;
  TDF_Tool::Entry(label, entry);
  if (auto it = parts_.find(entry.ToCString()); it != parts_.end()) return it->second;
  const TopoDS_Shape shape = shapes_->GetShape(label);
  CadPart p;
  p.name = name_of(label);
  p.colour = colour_of(label);
  p.layers = layers_of(label);
  const std::string entity = entity_of(shape);
  const std::string what = "part '" + path + "'" + (entity.empty() ? std::string() : " (entity " + entity + ")");
  if (shape.IsNull() || !TopExp_Explorer(shape, TopAbs_FACE).More()) {
    // Construction geometry beside the solids, or an assembly's component
    // kept in another file: nothing light could meet.
    const bool empty = shape.IsNull() || !TopExp_Explorer(shape, TopAbs_VERTEX).More();
    const std::string why = what + (empty ? ": holds no geometry (a product whose shape is in another file?)"
                                          : ": holds no faces, only wires, edges or points");
    if (first_left_out_.empty()) first_left_out_ = why;
    warn("cad-part-left-out", why + "; left out");
    parts_[entry.ToCString()] = std::nullopt;
    return std::optional<std::uint32_t>();
  }
  if (Status s = tessellate(shape, p, what, label); !s.ok()) return s.error();
  const auto id = static_cast<std::uint32_t>(model_.parts.size());
  model_.parts.push_back(std::move(p));
  parts_[entry.ToCString()] = id;
  return std::optional<std::uint32_t>(id);
}

Status CadReader::walk(const TDF_Label& label, const TopLoc_Location& location, const std::string& path,
                       const std::optional<sim::Vec3f>& colour, const std::vector<std::string>& layers,
                       int depth) {
  if (depth > 64) return fail("'" + path + "': the assembly is nested more than 64 deep (a cycle?)");
  if (shapes_->IsAssembly(label)) {
    TDF_LabelSequence components;
    shapes_->GetComponents(label, components, false);
    std::map<std::string, int> seen;
    for (int i = 1; i <= components.Length(); ++i) {
      const TDF_Label& component = components.Value(i);
      TDF_Label referred;
      if (!shapes_->GetReferredShape(component, referred)) continue;
      // OpenCASCADE's writer names components "=>[0:1:1:3]" (its label):
      // no name a person gave, so the product's name is used instead.
      std::string name = name_of(component);
      if (name.empty() || name.rfind("=>", 0) == 0) name = name_of(referred);
      if (name.empty()) {
        const std::string entity = entity_of(shapes_->GetShape(referred));
        name = entity.empty() ? "part" + std::to_string(i) : entity;
      }
      if (const int n = ++seen[name]; n > 1) name += "[" + std::to_string(n) + "]";
      std::optional<sim::Vec3f> c = colour_of(component);
      if (!c) c = colour;
      std::vector<std::string> l = layers;
      for (std::string& s : layers_of(component)) l.push_back(std::move(s));
      if (Status s = walk(referred, location * shapes_->GetLocation(component), path + "/" + name, c, l, depth + 1);
          !s.ok())
        return s;
    }
    return Ok{};
  }
  Result<std::optional<std::uint32_t>> id = part(label, path);
  if (!id.ok()) return id.error();
  if (!*id) return Ok{};
  CadPlacement p;
  p.part = **id;
  p.to_world = to_affine(location.Transformation(), unit_m_);
  if (!p.to_world.finite()) return fail("'" + path + "': the placement is not finite");
  p.path = path;
  p.colour = colour;
  p.layers = layers;
  model_.placements.push_back(std::move(p));
  return Ok{};
}

Result<CadModel> CadReader::read() {
  Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
  app->NewDocument("MDTV-XCAF", doc_);
  if (Status s = is_iges_path(path_) ? read_iges() : read_step(); !s.ok()) return s.error();
  shapes_ = XCAFDoc_DocumentTool::ShapeTool(doc_->Main());
  colours_ = XCAFDoc_DocumentTool::ColorTool(doc_->Main());
  layers_ = XCAFDoc_DocumentTool::LayerTool(doc_->Main());
  model_.tessellation = tess_;
  model_.file_unit_m = 0.001;
  if (model_.file_unit.empty()) model_.file_unit = "MM";

  TDF_LabelSequence roots;
  shapes_->GetFreeShapes(roots);
  if (roots.Length() == 0) return fail("the file holds no shapes (no product with a shape representation)");
  const std::vector<std::string> names = root_names(roots);
  for (int i = 1; i <= roots.Length(); ++i) {
    const TDF_Label& root = roots.Value(i);
    if (Status s = walk(root, TopLoc_Location(), names[static_cast<std::size_t>(i - 1)], colour_of(root),
                        layers_of(root), 0);
        !s.ok())
      return s.error();
  }
  if (model_.placements.empty())
    return fail(parts_.empty() ? std::string("the file holds no shapes")
                               : "the file holds no shapes with faces (" + std::to_string(parts_.size()) +
                                     " left out, the first " + first_left_out_ + ")");
  return std::move(model_);
}

}  // namespace

std::vector<std::string> CadReader::root_names(const TDF_LabelSequence& roots) const {
  std::vector<std::string> names;
  std::map<std::string, int> seen;
  for (int i = 1; i <= roots.Length(); ++i) {
    const TDF_Label& root = roots.Value(i);
    std::string name = name_of(root);
    if (name.empty()) {
      const std::string entity = entity_of(shapes_->GetShape(root));
      name = entity.empty() ? "part" + std::to_string(i) : entity;
    }
    if (const int n = ++seen[name]; n > 1) name += "[" + std::to_string(n) + "]";
    names.push_back(std::move(name));
  }
  return names;
}

Result<std::vector<std::pair<std::string, TopoDS_Shape>>> CadReader::free_shapes() {
  Handle(XCAFApp_Application) app = XCAFApp_Application::GetApplication();
  app->NewDocument("MDTV-XCAF", doc_);
  if (Status s = is_iges_path(path_) ? read_iges() : read_step(); !s.ok()) return s.error();
  shapes_ = XCAFDoc_DocumentTool::ShapeTool(doc_->Main());
  TDF_LabelSequence roots;
  shapes_->GetFreeShapes(roots);
  if (roots.Length() == 0) return fail("the file holds no shapes (no product with a shape representation)");
  std::vector<std::pair<std::string, TopoDS_Shape>> out;
  const std::vector<std::string> names = root_names(roots);
  for (int i = 1; i <= roots.Length(); ++i)
    out.emplace_back(names[static_cast<std::size_t>(i - 1)], shapes_->GetShape(roots.Value(i)));
  return out;
}

Result<CadModel> read_cad_file(const std::string& path, const CadTessellation& tessellation, bool parallel) {
  if (!(tessellation.angular_deflection_deg > 0.0 && tessellation.angular_deflection_deg <= 90.0))
    return make_error(path, "the angular deflection must lie in (0, 90] degrees");
  if (!(tessellation.chordal_relative > 0.0) || !(tessellation.chordal_min_m > 0.0) ||
      !(tessellation.chordal_m >= 0.0))
    return make_error(path, "the chordal deflection must be > 0");
  try {
    CadReader reader(path, tessellation, parallel, quiet_messenger());
    return reader.read();
  } catch (const Standard_Failure& e) {
    return make_error(path, std::string("OpenCASCADE failed: ") + e.GetMessageString());
  } catch (const std::exception& e) {
    return make_error(path, std::string("OpenCASCADE failed: ") + e.what());
  }
}

namespace {

// A closed meridian (curves end to end from the axis back to it, the axis
// closing it) turned into a solid: each curve a B-spline within `tolerance`
// of its points (a straight edge where it has two), the curves joined at
// shared vertices, the planar face revolved about Z.
Result<TopoDS_Shape> revolved_solid(const StepRevolvedPart& part, double tolerance, double& deviation) {
  const std::size_t n = std::min(part.rho.size(), part.z.size());
  auto point = [&](std::size_t i) { return gp_Pnt(part.rho[i], 0.0, part.z[i]); };
  std::vector<std::size_t> ends = part.curves;
  ends.push_back(n - 1);
  BRepBuilderAPI_MakeWire wire;
  const TopoDS_Vertex first = BRepBuilderAPI_MakeVertex(point(0));
  TopoDS_Vertex start = first;
  for (std::size_t c = 0; c + 1 < ends.size(); ++c) {
    const std::size_t a = ends[c], b = ends[c + 1];
    const TopoDS_Vertex end = BRepBuilderAPI_MakeVertex(point(b));
    if (b - a < 3) {
      wire.Add(BRepBuilderAPI_MakeEdge(start, end).Edge());
    } else {
      TColgp_Array1OfPnt points(1, static_cast<int>(b - a + 1));
      for (std::size_t i = a; i <= b; ++i) points.SetValue(static_cast<int>(i - a) + 1, point(i));
      GeomAPI_PointsToBSpline fit(points, 3, 8, GeomAbs_C2, tolerance);
      if (!fit.IsDone() || fit.Curve().IsNull())
        return make_error("OpenCASCADE found no B-spline within " + format_number(tolerance) + " mm of curve " +
                          std::to_string(c + 1));
      const Handle(Geom_BSplineCurve) curve = fit.Curve();
      for (int i = points.Lower(); i <= points.Upper(); ++i) {
        GeomAPI_ProjectPointOnCurve projection(points.Value(i), curve);
        if (projection.NbPoints() > 0) deviation = std::max(deviation, projection.LowerDistance());
      }
      BRepBuilderAPI_MakeEdge edge(curve, start, end);
      if (!edge.IsDone()) return make_error("OpenCASCADE could not make the edge of curve " + std::to_string(c + 1));
      wire.Add(edge.Edge());
    }
    if (!wire.IsDone()) return make_error("OpenCASCADE could not join curve " + std::to_string(c + 1) + " to the others");
    start = end;
  }
  // Along the axis, back to the first point.
  wire.Add(BRepBuilderAPI_MakeEdge(start, first).Edge());
  if (!wire.IsDone()) return make_error("OpenCASCADE could not close the meridian along the axis");
  BRepBuilderAPI_MakeFace face(wire.Wire(), true);
  if (!face.IsDone()) return make_error("OpenCASCADE could not make the meridian's face");
  BRepPrimAPI_MakeRevol revol(face.Face(), gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)));
  if (!revol.IsDone()) return make_error("OpenCASCADE could not turn the meridian about the axis");
  return revol.Shape();
}

// A cover (step_export.h) of OpenCASCADE's primitives, in millimetres.
TopoDS_Shape cover_shape(const StepRevolvedPart& c) {
  const double z = c.cover_z, t = c.cover_t;
  const gp_Ax1 axis(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1));
  if (c.cover == "box") {
    if (t > 0.0) return BRepPrimAPI_MakeBox(gp_Pnt(-c.cover_a / 2, -c.cover_b / 2, z - t), c.cover_a, c.cover_b, t).Shape();
    return BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, z), gp_Dir(0, 0, 1)), -c.cover_a / 2, c.cover_a / 2,
                                   -c.cover_b / 2, c.cover_b / 2)
        .Face();
  }
  if (c.cover == "disc") {
    if (t > 0.0) return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, z - t), gp_Dir(0, 0, 1)), c.cover_a / 2, t).Shape();
    return BRepPrimAPI_MakeRevol(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, z), gp_Pnt(c.cover_a / 2, 0, z)).Edge(), axis).Shape();
  }
  // The dome, built bulging down and mirrored about z where it bulges up: its
  // meridian in the XZ plane, turned about Z.
  const double a = c.cover_a / 2, s = std::abs(c.cover_b), r = (a * a + s * s) / (2 * s);
  const double zc = z - s + r;  // the spheres' centre
  const double flip = c.cover_b < 0.0 ? -1.0 : 1.0;
  auto at = [&](double rho, double height) { return gp_Pnt(rho, 0, z + flip * (height - z)); };
  auto arc = [&](double radius, double rho_end) {  // from the apex to the base plane, through its middle
    const double end = std::asin(rho_end / radius), mid = end / 2;
    return BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(at(0, zc - radius), at(radius * std::sin(mid), zc - radius * std::cos(mid)),
                                                      at(rho_end, zc - radius * std::cos(end)))
                                       .Value())
        .Edge();
  };
  if (t <= 0.0) return BRepPrimAPI_MakeRevol(arc(r, a), axis).Shape();
  const double ri = r - t, rho_in = std::sqrt(ri * ri - (r - s) * (r - s));
  BRepBuilderAPI_MakeWire wire;
  wire.Add(arc(r, a));
  wire.Add(BRepBuilderAPI_MakeEdge(at(a, z), at(rho_in, zc - ri * std::cos(std::asin(rho_in / ri)))).Edge());
  wire.Add(arc(ri, rho_in));
  wire.Add(BRepBuilderAPI_MakeEdge(at(0, zc - ri), at(0, zc - r)).Edge());
  return BRepPrimAPI_MakeRevol(BRepBuilderAPI_MakeFace(wire.Wire(), true).Face(), axis).Shape();
}

}  // namespace

namespace {

// A part of planar faces (StepRevolvedPart::faces): each polygon a plane face
// through its corners (repeated corners dropped), and of B-spline patches
// (StepRevolvedPart::patches): each grid a B-spline surface within
// `tolerance` of its points (the largest distance found into `deviation`),
// all sewn within `tolerance`.
Result<TopoDS_Shape> planar_faces(const StepRevolvedPart& part, double tolerance, double& deviation) {
  BRepBuilderAPI_Sewing sewing(tolerance);
  std::size_t k = 0;
  for (std::size_t f = 0; f < part.faces.size(); ++f) {
    std::vector<gp_Pnt> corners;
    for (std::size_t c = 0; c < part.faces[f] && k + 2 < part.corners.size(); ++c, k += 3) {
      const gp_Pnt p(part.corners[k], part.corners[k + 1], part.corners[k + 2]);
      if (corners.empty() || p.Distance(corners.back()) > 1e-9) corners.push_back(p);
    }
    while (corners.size() > 1 && corners.back().Distance(corners.front()) <= 1e-9) corners.pop_back();
    if (corners.size() < 3) continue;  // a facet shrunk to a line (on the axis)
    BRepBuilderAPI_MakePolygon polygon;
    for (const gp_Pnt& p : corners) polygon.Add(p);
    polygon.Close();
    if (!polygon.IsDone()) return make_error("face " + std::to_string(f + 1) + ": OpenCASCADE could not join its corners");
    BRepBuilderAPI_MakeFace face(polygon.Wire(), true);
    if (!face.IsDone()) return make_error("face " + std::to_string(f + 1) + ": its corners do not lie on one plane");
    sewing.Add(face.Face());
  }
  std::size_t k2 = 0;
  for (std::size_t q = 0; q + 1 < part.patches.size(); q += 2) {
    const int nu = static_cast<int>(part.patches[q]), nv = static_cast<int>(part.patches[q + 1]);
    TColgp_Array2OfPnt grid(1, nu, 1, nv);
    for (int i = 1; i <= nu; ++i)
      for (int j = 1; j <= nv && k2 + 2 < part.patch_points.size(); ++j, k2 += 3)
        grid.SetValue(i, j, gp_Pnt(part.patch_points[k2], part.patch_points[k2 + 1], part.patch_points[k2 + 2]));
    GeomAPI_PointsToBSplineSurface fit(grid, 3, 8, GeomAbs_C2, tolerance);
    if (!fit.IsDone() || fit.Surface().IsNull())
      return make_error("patch " + std::to_string(q / 2 + 1) + ": OpenCASCADE found no B-spline surface within " +
                        format_number(tolerance) + " mm of its points");
    const Handle(Geom_BSplineSurface) surface = fit.Surface();
    for (int i = 1; i <= nu; ++i)
      for (int j = 1; j <= nv; ++j) {
        GeomAPI_ProjectPointOnSurf projection(grid.Value(i, j), surface);
        if (projection.NbPoints() > 0) deviation = std::max(deviation, projection.LowerDistance());
      }
    BRepBuilderAPI_MakeFace face(surface, Precision::Confusion());
    if (!face.IsDone()) return make_error("patch " + std::to_string(q / 2 + 1) + ": OpenCASCADE could not make its face");
    sewing.Add(face.Face());
  }
  sewing.Perform();
  TopoDS_Shape out = sewing.SewedShape();
  if (out.IsNull()) return make_error("OpenCASCADE could not sew the faces");
  return out;
}

}  // namespace

Status write_step_file(const StepExport& request, const std::string& path, double* max_deviation_mm) {
  if (request.parts.empty()) return make_error(path, "nothing to write: no parts");
  if (!(request.tolerance_mm > 0.0)) return make_error(path, "the tolerance must be > 0");
  try {
    Handle(CollectingPrinter) printer = quiet_messenger();
    Handle(TDocStd_Document) doc;
    XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
    Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    const TDF_Label assembly = shapes->NewShape();
    TDataStd_Name::Set(assembly, TCollection_ExtendedString(request.product.empty() ? "design" : request.product.c_str(), true));
    double deviation = 0.0;
    for (const StepRevolvedPart& part : request.parts) {
      if (!part.cover.empty()) {
        const TopoDS_Shape cover = cover_shape(part);
        if (cover.IsNull()) return make_error(path, part.name + ": OpenCASCADE could not make the cover");
        const TDF_Label label = shapes->AddShape(cover, false);
        TDataStd_Name::Set(label, TCollection_ExtendedString(part.name.c_str(), true));
        const TDF_Label component = shapes->AddComponent(assembly, label, TopLoc_Location());
        TDataStd_Name::Set(component, TCollection_ExtendedString(part.name.c_str(), true));
        continue;
      }
      if (!part.file.empty()) {
        // A CAD file's shapes, placed: each free shape transformed (a copy
        // of its geometry, so that a scale is exact) and named "NAME/<its name>".
        CadReader reader(part.file, CadTessellation{}, false, printer);
        Result<std::vector<std::pair<std::string, TopoDS_Shape>>> shapes_in = reader.free_shapes();
        if (!shapes_in.ok()) return make_error(path, part.name + ": " + to_string(shapes_in.error()));
        const std::vector<double>& m = part.place;
        gp_Trsf trsf;
        trsf.SetValues(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]);
        for (const auto& [name, shape] : *shapes_in) {
          BRepBuilderAPI_Transform placed(shape, trsf, true);
          if (!placed.IsDone()) return make_error(path, part.name + ": OpenCASCADE could not place " + name);
          const std::string full = part.name + "/" + name;
          const TDF_Label label = shapes->AddShape(placed.Shape(), false);
          TDataStd_Name::Set(label, TCollection_ExtendedString(full.c_str(), true));
          const TDF_Label component = shapes->AddComponent(assembly, label, TopLoc_Location());
          TDataStd_Name::Set(component, TCollection_ExtendedString(full.c_str(), true));
        }
        continue;
      }
      if (!part.faces.empty() || !part.patches.empty()) {
        Result<TopoDS_Shape> faces = planar_faces(part, request.tolerance_mm, deviation);
        if (!faces.ok()) return make_error(path, part.name + ": " + faces.error().message);
        const TDF_Label label = shapes->AddShape(*faces, false);
        TDataStd_Name::Set(label, TCollection_ExtendedString(part.name.c_str(), true));
        const TDF_Label component = shapes->AddComponent(assembly, label, TopLoc_Location());
        TDataStd_Name::Set(component, TCollection_ExtendedString(part.name.c_str(), true));
        continue;
      }
      const std::size_t n = std::min(part.rho.size(), part.z.size());
      if (n < 2) return make_error(path, part.name + ": a profile needs at least 2 points");
      if (!part.curves.empty()) {
        Result<TopoDS_Shape> solid = revolved_solid(part, request.tolerance_mm, deviation);
        if (!solid.ok()) return make_error(path, part.name + ": " + solid.error().message);
        if (part.place.size() == 12) {  // placed (a lens off the axis or tilted)
          const std::vector<double>& m = part.place;
          gp_Trsf trsf;
          trsf.SetValues(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]);
          BRepBuilderAPI_Transform placed(*solid, trsf, true);
          if (!placed.IsDone()) return make_error(path, part.name + ": OpenCASCADE could not place the solid");
          *solid = placed.Shape();
        }
        const TDF_Label label = shapes->AddShape(*solid, false);
        TDataStd_Name::Set(label, TCollection_ExtendedString(part.name.c_str(), true));
        const TDF_Label component = shapes->AddComponent(assembly, label, TopLoc_Location());
        TDataStd_Name::Set(component, TCollection_ExtendedString(part.name.c_str(), true));
        continue;
      }
      TColgp_Array1OfPnt points(1, static_cast<int>(n));
      const bool extruded = part.extrude_mm > 0.0;  // a trough: the profile in the XZ plane at y = −L/2
      const double y0 = extruded ? -0.5 * part.extrude_mm : 0.0;
      for (std::size_t i = 0; i < n; ++i) points.SetValue(static_cast<int>(i) + 1, gp_Pnt(part.rho[i], y0, part.z[i]));
      GeomAPI_PointsToBSpline fit(points, 3, 8, GeomAbs_C2, request.tolerance_mm);
      if (!fit.IsDone() || fit.Curve().IsNull())
        return make_error(path, part.name + ": OpenCASCADE found no B-spline within " +
                                    format_number(request.tolerance_mm) + " mm of the profile");
      const Handle(Geom_BSplineCurve) curve = fit.Curve();
      for (int i = points.Lower(); i <= points.Upper(); ++i) {
        GeomAPI_ProjectPointOnCurve projection(points.Value(i), curve);
        if (projection.NbPoints() > 0) deviation = std::max(deviation, projection.LowerDistance());
      }
      BRepBuilderAPI_MakeEdge edge(curve);
      if (!edge.IsDone()) return make_error(path, part.name + ": OpenCASCADE could not make the profile's edge");
      const TopoDS_Shape profile = edge.Edge();
      TopoDS_Shape surface;
      if (extruded) {
        BRepPrimAPI_MakePrism prism(profile, gp_Vec(0.0, part.extrude_mm, 0.0));
        if (!prism.IsDone()) return make_error(path, part.name + ": OpenCASCADE could not extrude the profile");
        surface = prism.Shape();
      } else {
        BRepPrimAPI_MakeRevol revol(profile, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)));
        if (!revol.IsDone()) return make_error(path, part.name + ": OpenCASCADE could not turn the profile about the axis");
        surface = revol.Shape();
      }
      const TDF_Label label = shapes->AddShape(surface, false);
      TDataStd_Name::Set(label, TCollection_ExtendedString(part.name.c_str(), true));
      const TDF_Label component = shapes->AddComponent(assembly, label, TopLoc_Location());
      TDataStd_Name::Set(component, TCollection_ExtendedString(part.name.c_str(), true));
    }
    shapes->UpdateAssemblies();
    STEPCAFControl_Writer writer;
    writer.SetNameMode(true);
    Interface_Static::SetCVal("write.step.schema", "AP214IS");
    Interface_Static::SetCVal("write.step.unit", "MM");
    if (!writer.Transfer(doc, STEPControl_AsIs)) return make_error(path, "OpenCASCADE could not translate the parts to STEP");
    if (writer.Write(path.c_str()) != IFSelect_RetDone) return make_error(path, "OpenCASCADE could not write the file");
    if (max_deviation_mm) *max_deviation_mm = deviation;
    (void)printer;
    return Ok{};
  } catch (const Standard_Failure& e) {
    return make_error(path, std::string("OpenCASCADE failed: ") + e.GetMessageString());
  } catch (const std::exception& e) {
    return make_error(path, std::string("OpenCASCADE failed: ") + e.what());
  }
}

}  // namespace gonio::io
