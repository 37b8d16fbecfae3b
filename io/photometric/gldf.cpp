#include "io/photometric/gldf.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include "gonio/version.h"
#include "io/support/content_hash.h"
#include "io/support/xml.h"
#include "photometry/error_at.h"
#include "photometry/format.h"
#include "photometry/summary.h"

namespace gonio::io {
namespace {



constexpr const char* kProductXml = "product.xml";

std::string number(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string uuid_like(std::uint64_t a, std::uint64_t b) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%08x-%04x-4%03x-8%03x-%012llx", static_cast<unsigned>(a >> 32),
                static_cast<unsigned>((a >> 16) & 0xffff), static_cast<unsigned>(a & 0xfff),
                static_cast<unsigned>((b >> 48) & 0xfff),
                static_cast<unsigned long long>(b & 0xffffffffffffull));
  return buf;
}

XmlElement& locale(XmlElement& parent, const std::string& name, const std::string& text) {
  XmlElement& e = parent.add(name);
  e.add("Locale", text).set("language", "en");
  return e;
}

std::string trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

void descriptive(XmlElement& photometry, const photometry::Distribution& d) {
  if (photometry::validate(d).ok() == false) return;
  const photometry::Summary s = photometry::summarize(d);
  XmlElement dp;
  dp.name = "DescriptivePhotometry";
  if (s.lor_defined && s.lor >= 0.0 && s.lor <= 1.0) dp.add("LightOutputRatio", number(s.lor));
  if (std::isfinite(s.efficacy_lm_per_w) && s.efficacy_lm_per_w >= 0.0 && s.efficacy_lm_per_w <= 683.0)
    dp.add("LuminousEfficacy", number(s.efficacy_lm_per_w));
  if (std::isfinite(s.dff) && s.dff >= 0.0 && s.dff <= 1.0) dp.add("DownwardFluxFraction", number(s.dff));
  const auto pair = [&](const char* name, const photometry::BeamSpread& a, const photometry::BeamSpread& b) {
    if (!std::isfinite(a.angle_deg) || !std::isfinite(b.angle_deg)) return;
    XmlElement& e = dp.add(name);
    e.add("C0-C180", number(a.angle_deg));
    e.add("C90-C270", number(b.angle_deg));
  };
  pair("TenthPeakDivergence", s.field_c0_c180, s.field_c90_c270);
  pair("HalfPeakDivergence", s.beam_c0_c180, s.beam_c90_c270);
  if (!dp.children.empty()) photometry.children.push_back(std::move(dp));
}

std::string structure_xml(const L3dGeometry& g, const std::string& created_with, std::int64_t created_unix) {
  XmlElement root;
  root.name = "Luminaire";
  root.set("xmlns:xsi", "http://www.w3.org/2001/XMLSchema-instance");
  // L3D 0.11.0, the version globallightingdata/l3d's xsd/l3d.xsd and its
  // examples are; that schema requires Header/FormatVersion (tests validate
  // against it: Gldf.L3dStructureXmlValidatesAgainstTheL3dSchema).
  root.set("xsi:noNamespaceSchemaLocation", "https://gldf.io/xsd/l3d/0.11.0/l3d.xsd");
  XmlElement& header = root.add("Header");
  header.add("CreatedWithApplication", created_with);
  header.add("CreationTimeCode", format_utc(created_unix, "%Y-%m-%dT%H:%M:%S"));
  header.add("FormatVersion").set("major", "0").set("minor", "11");
  XmlElement& definitions = root.add("GeometryDefinitions");
  const auto define = [&](const std::string& id) {
    definitions.add("GeometryFileDefinition").set("id", id).set("filename", id + ".obj").set("units", "m");
  };
  define(g.id);
  for (const L3dDefinition& d : g.definitions) define(d.id);
  const auto xyz = [](XmlElement& parent, const char* name, const Vec3& v) {
    parent.add(name).set("x", number(v.x)).set("y", number(v.y)).set("z", number(v.z));
  };
  XmlElement& structure = root.add("Structure");
  structure.children.reserve(1 + g.parts.size());
  XmlElement& body = structure.add("Geometry").set("partName", g.id + "Body");
  xyz(body, "Position", Vec3{});
  xyz(body, "Rotation", Vec3{});
  body.add("GeometryReference").set("geometryId", g.id);
  XmlElement& leos = body.add("LightEmittingObjects");
  for (const L3dEmitter& e : g.emitters) {
    XmlElement& leo = leos.add("LightEmittingObject").set("partName", e.name);
    xyz(leo, "Position", e.position_m);
    xyz(leo, "Rotation", Vec3{});
    leo.add("Rectangle").set("sizeX", number(e.size_x_m)).set("sizeY", number(e.size_y_m));
  }
  for (const L3dPart& part : g.parts) {
    XmlElement& e = structure.add("Geometry").set("partName", part.name);
    xyz(e, "Position", part.position_m);
    xyz(e, "Rotation", part.rotation_deg);
    e.add("GeometryReference").set("geometryId", part.geometry_id);
  }
  return write_xml(root);
}

}  // namespace

// ------------------------------------------------------------------ reading

Result<GldfFile> parse_gldf(std::string_view bytes, const std::string& name) {
  if (bytes.size() > kMaxGldfBytes)
    return make_error(name, "GLDF archive too large (" + std::to_string(bytes.size()) +
                                " bytes, at most " + std::to_string(kMaxGldfBytes) + " accepted)");
  auto entries = read_zip(bytes, name);
  if (!entries.ok()) return entries.error();
  GldfFile out;
  std::map<std::string, const std::string*> by_name;
  for (const ZipEntry& e : *entries) {
    out.entries.push_back(e.name);
    by_name[e.name] = &e.bytes;
  }
  const auto product = by_name.find(kProductXml);
  if (product == by_name.end())
    return make_error(name, "no product.xml in the archive: not a GLDF container");
  const std::string xml_name = name + ":" + kProductXml;
  auto root = parse_xml(*product->second, xml_name);
  if (!root.ok()) return root.error();
  if (root->name != "Root")
    return make_error(xml_name, root->line, "root element <" + root->name + "> is not GLDF's <Root>");
  if (const XmlElement* h = root->child("Header"))
    if (const XmlElement* m = h->child("Manufacturer")) out.manufacturer = trimmed(m->text);
  if (const XmlElement* pd = root->child("ProductDefinitions"))
    if (const XmlElement* meta = pd->child("ProductMetaData"))
      if (const XmlElement* n = meta->child("Name"))
        if (const XmlElement* l = n->child("Locale")) out.product_name = trimmed(l->text);

  const XmlElement* general = root->child("GeneralDefinitions");
  struct FileRef {
    std::string content_type, type, value;
    int line;
  };
  std::map<std::string, FileRef> files;
  if (general)
    if (const XmlElement* fs = general->child("Files"))
      for (const XmlElement* f : fs->children_named("File")) {
        const std::string* id = f->attribute("id");
        if (!id) return make_error(xml_name, f->line, "<File> without an id");
        const std::string* ct = f->attribute("contentType");
        const std::string* type = f->attribute("type");
        files[*id] = FileRef{ct ? *ct : "", type ? *type : "localFileName", trimmed(f->text), f->line};
      }
  const XmlElement* photometries = general ? general->child("Photometries") : nullptr;
  if (photometries)
    for (const XmlElement* p : photometries->children_named("Photometry")) {
      const std::string* id = p->attribute("id");
      const XmlElement* ref = p->child("PhotometryFileReference");
      const std::string* file_id = ref ? ref->attribute("fileId") : nullptr;
      if (!id || !file_id)
        return make_error(xml_name, p->line, "<Photometry> without an id or a <PhotometryFileReference fileId>");
      const auto f = files.find(*file_id);
      if (f == files.end())
        return make_error(xml_name, ref->line,
                          "photometry '" + *id + "' refers to file id '" + *file_id + "', which <Files> lacks");
      const FileRef& file = f->second;
      if (file.type == "url") {
        out.findings.push_back({Severity::Warning, "gldf-url-not-fetched",
                                "photometry '" + *id + "' is at " + file.value + "; not fetched",
                                {xml_name, file.line, 0}});
        continue;
      }
      if (file.content_type != "ldc/eulumdat" && file.content_type != "ldc/ies" &&
          file.content_type != "ldc/iesxml") {
        out.findings.push_back({Severity::Warning, "gldf-photometry-type",
                                "photometry '" + *id + "' has content type '" + file.content_type +
                                    "', which Gonio does not read",
                                {xml_name, file.line, 0}});
        continue;
      }
      if (!is_safe_entry_name(file.value))
        return make_error(xml_name, file.line,
                          "file '" + file.value + "' is not a relative name inside the archive; refused");
      const std::string folder = file.content_type.substr(0, file.content_type.find('/'));
      std::string entry = folder + "/" + file.value;
      auto found = by_name.find(entry);
      if (found == by_name.end()) {
        entry = file.value;
        found = by_name.find(entry);
      }
      if (found == by_name.end())
        return make_error(xml_name, file.line, "photometry '" + *id + "' refers to '" + folder + "/" +
                                                   file.value + "', which the archive lacks");
      out.photometries.push_back({*id, entry, file.content_type, *found->second, p->line});
    }
  if (out.photometries.empty())
    return make_error(xml_name, photometries ? photometries->line : root->line,
                      "no photometry Gonio can read in the archive");
  return out;
}

// ------------------------------------------------------------------ writing

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// An instance's placement in L3D's frame, when L3D can state it without
// depending on how its Euler order is read (l3d_from_scene).
struct L3dPlacement {
  double scale = 1.0;
  Vec3 rotation_deg;
  Vec3 position_m;
  sim::Affine turn;  // the mesh's vertices into L3D's axes, scaled
};

std::optional<L3dPlacement> l3d_placement(const sim::Affine& a, const photometry::PhotometricFrame& f) {
  const double det = a.determinant();
  if (!(det > 0.0) || !std::isfinite(det)) return std::nullopt;  // mirrored or singular
  // F: world axes → L3D's (rows C0, C90, zenith); its transpose is its inverse.
  sim::Affine frame, frame_t;
  const Vec3 rows[3] = {f.c0, f.c90, f.up};
  for (int i = 0; i < 3; ++i) {
    frame.m[i][0] = frame_t.m[0][i] = rows[i].x;
    frame.m[i][1] = frame_t.m[1][i] = rows[i].y;
    frame.m[i][2] = frame_t.m[2][i] = rows[i].z;
  }
  sim::Affine linear = a;
  linear.offset = Vec3{};
  L3dPlacement p;
  p.scale = std::cbrt(det);
  // R = F·A·Fᵀ / scale must be a rotation, about one of L3D's axes.
  const sim::Affine r = sim::scaling(1.0 / p.scale, 1.0 / p.scale, 1.0 / p.scale) * frame * linear * frame_t;
  constexpr double kTolerance = 1e-9;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double rrt = r.m[i][0] * r.m[j][0] + r.m[i][1] * r.m[j][1] + r.m[i][2] * r.m[j][2];
      if (std::abs(rrt - (i == j ? 1.0 : 0.0)) > kTolerance) return std::nullopt;  // not scale · rotation
    }
  // The axis the rotation keeps (z first: a ring about the luminaire's axis).
  if (std::abs(r.m[2][2] - 1.0) <= kTolerance)
    p.rotation_deg.z = std::atan2(r.m[1][0], r.m[0][0]) / kDeg;
  else if (std::abs(r.m[0][0] - 1.0) <= kTolerance)
    p.rotation_deg.x = std::atan2(r.m[2][1], r.m[1][1]) / kDeg;
  else if (std::abs(r.m[1][1] - 1.0) <= kTolerance)
    p.rotation_deg.y = std::atan2(r.m[0][2], r.m[2][2]) / kDeg;
  else
    return std::nullopt;  // about a skew axis
  p.position_m = f.to_local(a.offset);
  p.turn = sim::scaling(p.scale, p.scale, p.scale) * frame;
  return p;
}

// Appends a mesh's vertices (through `place`) and triangles to an OBJ whose
// vertices so far number base − 1; `flip` reverses the winding (a mirroring
// placement).
template <class Place>
void append_obj(std::string& obj, const sim::Mesh& m, Place&& place, bool flip, std::size_t& base) {
  for (const sim::Vec3f& p : m.positions) {
    const Vec3 q = place(sim::to_double(p));
    obj += "v " + number(q.x) + " " + number(q.y) + " " + number(q.z) + "\n";
  }
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const std::size_t b = flip ? 2 : 1, c = flip ? 1 : 2;
    obj += "f " + std::to_string(base + m.indices[t]) + " " + std::to_string(base + m.indices[t + b]) + " " +
           std::to_string(base + m.indices[t + c]) + "\n";
  }
  base += m.positions.size();
}

std::string obj_header(const std::string& scene_name, const std::string& id) {
  return "# " + scene_name + ": " + std::string("written by Gonio ") + kVersion +
         "; metres, X = C0, Y = C90, Z = zenith\no " + id + "\n";
}

}  // namespace

L3dGeometry l3d_from_scene(const sim::SceneDesc& scene) {
  L3dGeometry g;
  const photometry::PhotometricFrame& f = scene.frame;
  const auto& meshes = scene.meshes;
  const auto& instances = scene.instances;
  const auto valid = [&](const sim::Instance& i) {
    return i.mesh < meshes.size() && meshes[i.mesh].instanced && meshes[i.mesh].triangle_count() > 0;
  };
  // Which instances L3D places as parts; the rest are flattened into the body.
  std::vector<std::optional<L3dPlacement>> placed(instances.size());
  bool body_has_triangles = false;
  for (const sim::Mesh& m : meshes) body_has_triangles |= !m.instanced && m.triangle_count() > 0;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    if (!valid(instances[i])) continue;
    placed[i] = l3d_placement(instances[i].to_world, f);
    body_has_triangles |= !placed[i];
  }
  if (!body_has_triangles)
    for (std::size_t i = 0; i < instances.size(); ++i)
      if (placed[i]) {
        placed[i].reset();
        break;
      }

  g.obj = obj_header(scene.name, g.id);
  std::size_t base = 1;
  for (const sim::Mesh& m : meshes)
    if (!m.instanced) append_obj(g.obj, m, [&](const Vec3& p) { return f.to_local(p); }, false, base);
  for (std::size_t i = 0; i < instances.size(); ++i)
    if (valid(instances[i]) && !placed[i]) {
      const sim::Affine& a = instances[i].to_world;
      append_obj(g.obj, meshes[instances[i].mesh], [&](const Vec3& p) { return f.to_local(a.point(p)); },
                 a.determinant() < 0.0, base);
    }

  // One definition per instanced mesh and scale (equal to 10⁻⁹).
  std::map<std::uint32_t, std::vector<std::pair<double, std::size_t>>> defined;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    if (!placed[i]) continue;
    const L3dPlacement& p = *placed[i];
    const std::uint32_t mesh = instances[i].mesh;
    auto& scales = defined[mesh];
    std::size_t d = g.definitions.size();
    for (const auto& [scale, index] : scales)
      if (std::abs(scale - p.scale) <= 1e-9 * scale) d = index;
    if (d == g.definitions.size()) {
      L3dDefinition def;
      def.id = "mesh" + std::to_string(mesh) + (scales.empty() ? "" : "s" + std::to_string(scales.size()));
      def.obj = obj_header(scene.name, def.id);
      std::size_t def_base = 1;
      append_obj(def.obj, meshes[mesh], [&](const Vec3& q) { return p.turn.linear(q); }, false, def_base);
      scales.emplace_back(p.scale, d);
      g.definitions.push_back(std::move(def));
    }
    g.parts.push_back({"part" + std::to_string(g.parts.size() + 1), g.definitions[d].id, p.position_m,
                       p.rotation_deg});
  }

  // Where the emitters are.
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  double z_sum = 0.0;
  std::size_t n = 0;
  const auto take = [&](const Vec3& q) {
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
    z_sum += q.z;
    ++n;
  };
  for (const sim::Emitter& e : scene.emitters) {
    if (e.kind != sim::Emitter::Kind::Area) {  // a point, or a ray set at its node
      take(f.to_local(e.position));
    } else if (e.mesh < meshes.size()) {
      const bool on_instance = e.instance != sim::kNoInstance && e.instance < instances.size();
      for (const sim::Vec3f& p : meshes[e.mesh].positions)
        take(f.to_local(on_instance ? instances[e.instance].to_world.point(sim::to_double(p)) : sim::to_double(p)));
    }
  }
  if (n > 0) {
    L3dEmitter leo;
    leo.name = "lightEmittingObject";
    leo.position_m = {0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), z_sum / static_cast<double>(n)};
    leo.size_x_m = std::max(1e-3, hi.x - lo.x);
    leo.size_y_m = std::max(1e-3, hi.y - lo.y);
    g.emitters.push_back(leo);
  }
  return g;
}

Result<std::string> write_l3d(const L3dGeometry& geometry, const std::string& created_with,
                              std::int64_t created_unix) {
  std::vector<ZipEntry> entries{{"structure.xml", structure_xml(geometry, created_with, created_unix)},
                                 {geometry.id + "/" + geometry.id + ".obj", geometry.obj}};
  for (const L3dDefinition& d : geometry.definitions) entries.push_back({d.id + "/" + d.id + ".obj", d.obj});
  return write_zip(entries, created_unix);
}

std::string gldf_product_xml(const GldfProduct& p) {
  const std::string application = std::string("Gonio ") + kVersion;
  // An id that names the same contents the same way.
  ContentHash contents;
  contents.text(p.name);
  for (const GldfPhotometryOut& ph : p.photometries) contents.text(ph.bytes);
  if (p.geometry) {
    contents.text(p.geometry->obj);
    for (const L3dDefinition& d : p.geometry->definitions) contents.text(d.obj);
    for (const L3dPart& part : p.geometry->parts) {
      contents.text(part.geometry_id);
      contents.vec(part.position_m);
      contents.vec(part.rotation_deg);
    }
  }
  const std::uint64_t h = contents.digest();
  contents.text(application);

  XmlElement root;
  root.name = "Root";
  root.set("xmlns:xsi", "http://www.w3.org/2001/XMLSchema-instance");
  root.set("xsi:noNamespaceSchemaLocation", "https://gldf.io/xsd/gldf/1.0.0-rc.3/gldf.xsd");
  XmlElement& header = root.add("Header");
  header.add("Manufacturer", p.manufacturer.empty() ? "not stated" : p.manufacturer);
  header.add("FormatVersion").set("major", "1").set("minor", "0").set("pre-release", "3");
  header.add("CreatedWithApplication", application);
  header.add("GldfCreationTimeCode", format_utc(p.created_unix, "%Y-%m-%dT%H:%M:%SZ"));
  header.add("UniqueGldfId", uuid_like(h, contents.digest()));

  XmlElement& general = root.add("GeneralDefinitions");
  XmlElement& files = general.add("Files");
  for (std::size_t i = 0; i < p.photometries.size(); ++i)
    files.add("File", p.photometries[i].file_name)
        .set("id", "photometryFile" + std::to_string(i + 1))
        .set("contentType", p.photometries[i].content_type)
        .set("type", "localFileName");
  if (p.geometry)
    files.add("File", p.geometry->id + ".l3d")
        .set("id", "geometryFile")
        .set("contentType", "geo/l3d")
        .set("type", "localFileName");
  XmlElement& photometries = general.add("Photometries");
  for (std::size_t i = 0; i < p.photometries.size(); ++i) {
    XmlElement& ph = photometries.add("Photometry").set("id", "photometry" + std::to_string(i + 1));
    ph.add("PhotometryFileReference").set("fileId", "photometryFile" + std::to_string(i + 1));
    descriptive(ph, p.photometries[i].distribution);
  }
  XmlElement& emitter = general.add("Emitters").add("Emitter").set("id", "emitter");
  emitter.add("ChangeableLightEmitter").add("PhotometryReference").set("photometryId", "photometry1");
  if (p.geometry)
    general.add("Geometries")
        .add("ModelGeometry")
        .set("id", "geometry")
        .add("GeometryFileReference")
        .set("fileId", "geometryFile");

  XmlElement& products = root.add("ProductDefinitions");
  XmlElement& meta = products.add("ProductMetaData");
  meta.add("UniqueProductId", p.name);
  locale(meta, "ProductNumber", p.name);
  locale(meta, "Name", p.name);
  if (!p.description.empty()) locale(meta, "Description", p.description);
  XmlElement& variant = products.add("Variants").add("Variant").set("id", "variant1");
  locale(variant, "Name", p.name);
  XmlElement& geometry = variant.add("Geometry");
  if (p.geometry && !p.geometry->emitters.empty()) {
    XmlElement& model = geometry.add("ModelGeometryReference").set("geometryId", "geometry");
    for (const L3dEmitter& e : p.geometry->emitters)
      model.add("EmitterReference").set("emitterId", "emitter").add("EmitterObjectExternalName", e.name);
  } else {
    geometry.add("EmitterReference").set("emitterId", "emitter");
  }
  return write_xml(root);
}

Result<std::string> write_gldf(const GldfProduct& p) {
  if (p.photometries.empty()) return make_error("a GLDF container needs a photometry");
  std::vector<ZipEntry> entries;
  entries.push_back({kProductXml, gldf_product_xml(p)});
  for (const GldfPhotometryOut& ph : p.photometries) entries.push_back({"ldc/" + ph.file_name, ph.bytes});
  if (p.geometry) {
    auto l3d = write_l3d(*p.geometry, std::string("Gonio ") + kVersion, p.created_unix);
    if (!l3d.ok()) return l3d.error();
    entries.push_back({"geo/" + p.geometry->id + ".l3d", std::move(l3d).value()});
  }
  return write_zip(entries, p.created_unix);
}

}  // namespace gonio::io
