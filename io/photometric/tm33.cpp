#include "io/photometric/tm33.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "io/support/text.h"
#include "io/support/xml.h"
#include "photometry/error_at.h"

namespace gonio::io {
namespace {

using photometry::Distribution;
using photometry::FileGenerationType;
using photometry::PhotometricType;
using photometry::Symmetry;

constexpr const char* kRoot23 = "IESTM33-22";
constexpr const char* kRoot18 = "IESTM33";
// ATLA S001 / UNI 11733 as the main open-source toolkit (eulumdat-rs's
// crates/atla) writes it, and the root of ATLA's own sample document.
constexpr const char* kRootOpticalData = "LuminaireOpticalData";
constexpr const char* kRootAtlaSample = "ATLA_S001_A";
constexpr const char* kKeywordPrefix = "_TM33_";
constexpr const char* kGonioCustomId = "gonio-keywords";

// Element paths below the root that hold one value each, in the order of
// TM-33-23's schema (Version 1.1). Three blocks are handled by code of their
// own and stand here for their place in the order: Emitter/TiltAngles,
// Emitter/LuminousData/LuminousIntensity, Emitter/SpectralData/EmitterSpectral.
const std::vector<std::string>& schema_paths() {
  static const std::vector<std::string> paths = [] {
    std::vector<std::string> p = {
        "Header/Manufacturer", "Header/CatalogNumber", "Header/GTIN", "Header/Description",
        "Header/Laboratory", "Header/ReportNumber", "Header/ReportDate", "Header/DocumentCreator",
        "Header/DocumentCreationDate", "Header/UniqueIdentifier", "Header/Comment",
        "Header/Reference", "Header/MoreInfoURI",
        "Luminaire/Dimensions/Length", "Luminaire/Dimensions/Width", "Luminaire/Dimensions/Height",
        "Luminaire/Shape", "Luminaire/NumEmitter",
        "Equipment/Gonioradiometer/Type", "Equipment/Gonioradiometer/MeasurementEquipment",
        "Equipment/IntegratingSphere/MeasurementEquipment",
        "Equipment/Spectroradiometer/MeasurementEquipment",
        "Equipment/Spectroradiometer/BandwidthFWHM",
        "Equipment/Spectroradiometer/BandwidthCorrected",
        "Equipment/Spectroradiometer/BandwidthMethod",
        "Emitter/Quantity", "Emitter/Description", "Emitter/CatalogNumber", "Emitter/RatedLumens",
        "Emitter/InputWattage", "Emitter/PowerFactor", "Emitter/BallastFactor",
        "Emitter/TiltAngles",
        "Emitter/ColorTemperature/FixedCCT", "Emitter/ColorTemperature/MinCCT",
        "Emitter/ColorTemperature/MaxCCT", "Emitter/ColorRendering/CIE_CRI/Ra",
        "Emitter/ColorRendering/CIE_CRI/R9", "Emitter/ColorRendering/IES_TM30/Rf",
        "Emitter/ColorRendering/IES_TM30/Rg"};
    for (const char* kind : {"Rfh", "Rcsh"})
      for (int i = 1; i <= 16; ++i)
        p.push_back(std::string("Emitter/ColorRendering/IES_TM30/") + kind + (i < 10 ? "0" : "") +
                    std::to_string(i));
    for (const char* s :
         {"Emitter/Duv", "Emitter/SPRatio", "Emitter/DataGeneration/Simulation",
          "Emitter/DataGeneration/Laboratory/Certification",
          "Emitter/DataGeneration/Laboratory/ApprovalBody",
          "Emitter/DataGeneration/Laboratory/ApprovalScope",
          "Emitter/DataGeneration/Laboratory/MeasUncertainty/MeasurementType",
          "Emitter/DataGeneration/Laboratory/MeasUncertainty/Uncertainty",
          "Emitter/DataGeneration/IntensityScaling", "Emitter/DataGeneration/AngleInterpolation",
          "Emitter/LuminousData/LuminousIntensity", "Emitter/LuminousData/LuminousFlux",
          "Emitter/SpectralData/EmitterSpectral", "Emitter/EmitterCenter/LengthOffset",
          "Emitter/EmitterCenter/WidthOffset", "Emitter/EmitterCenter/HeightOffset"})
      p.push_back(s);
    for (const char* r :
         {"InputWattage", "PowerFactor", "BallastFactor", "ColorTemperature", "CIE_CRI", "IES_TM30",
          "Duv", "SPRatio", "LuminousIntensity", "LuminousFlux", "RadiantIntensity", "RadiantFlux",
          "PhotonIntensity", "PhotonFlux", "SpectralPower", "SpectralIntensity", "AngularColor",
          "Illuminance", "Irradiance", "PhotonFluxDensity", "SpectralIrradiance"})
      p.push_back(std::string("Emitter/Regulatory/") + r);
    return p;
  }();
  return paths;
}

// Blocks of the standard that Gonio's photometric model does not hold.
const std::map<std::string, const char*>& not_kept() {
  static const std::map<std::string, const char*> m = {
      {"Emitter/RadiantData", "radiant intensity"},
      {"Emitter/PhotonData", "photon intensity"},
      {"Emitter/SpectralData/AngularSpectral", "angular spectral intensity"},
      {"Emitter/AngularColor", "angular colour"},
      {"Emitter/IllumData", "illuminance"},
      {"Emitter/IrradData", "irradiance"},
      {"Emitter/PFDData", "photon flux density"},
      {"Emitter/SpecIrradData", "spectral irradiance"},
      {"Emitter/Channels", "channel multipliers"},
      {"Emitter/EmissionAreas", "emission areas"},
  };
  return m;
}

// Header leaves that are LM-63 keywords of their own.
const std::map<std::string, std::string>& keyword_of_path() {
  static const std::map<std::string, std::string> m = {
      {"Header/Manufacturer", "MANUFAC"}, {"Header/CatalogNumber", "LUMCAT"},
      {"Header/Description", "LUMINAIRE"}, {"Header/Laboratory", "TESTLAB"},
      {"Header/ReportNumber", "TEST"},     {"Header/ReportDate", "ISSUEDATE"},
      {"Header/Comment", "OTHER"},         {"Emitter/CatalogNumber", "LAMPCAT"},
  };
  return m;
}

// Leaves whose values become fields of the model (read and written by code).
const std::set<std::string>& model_paths() {
  static const std::set<std::string> s = {
      "Luminaire/Dimensions/Length", "Luminaire/Dimensions/Width", "Luminaire/Dimensions/Height",
      "Luminaire/NumEmitter", "Equipment/Gonioradiometer/Type", "Emitter/Quantity",
      "Emitter/Description", "Emitter/RatedLumens", "Emitter/InputWattage", "Emitter/BallastFactor",
      "Emitter/ColorTemperature/FixedCCT", "Emitter/ColorRendering/CIE_CRI/Ra",
      "Emitter/DataGeneration/Simulation", "Emitter/DataGeneration/IntensityScaling",
      "Emitter/DataGeneration/AngleInterpolation"};
  return s;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// "Header/GTIN" -> "_TM33_HEADER_GTIN".
std::string keyword_for(const std::string& path) {
  std::string key = kKeywordPrefix + upper(path);
  for (char& c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) c = '_';
  return key;
}

std::string local_name(const std::string& name) {
  const auto colon = name.find(':');
  return colon == std::string::npos ? name : name.substr(colon + 1);
}

void strip_prefixes(XmlElement& e) {
  e.name = local_name(e.name);
  for (XmlElement& c : e.children) strip_prefixes(c);
}

std::string trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

// The shortest decimal that reads back as the same double (std::to_chars):
// what TM-33 output writes, so every number round-trips exactly.
std::string number(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// The attribute as a number; nullopt where it is missing or no number.
std::optional<double> number_attribute(const XmlElement& e, std::string_view name) {
  std::optional<double> v;
  if (const std::string* a = e.attribute(name)) v = parse_number(trimmed(*a));
  return v;
}

struct Leaf {
  std::string text;
  int line;
};

class Tm33Reader {
 public:
  Tm33Reader(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

  Result<Tm33File> read() {
    auto doc = parse_xml(bytes_, name_);
    if (!doc.ok()) return doc.error();
    XmlElement root = std::move(doc).value();
    strip_prefixes(root);
    if (root.name == kRoot23) {
      out_.version = Tm33Version::TM33_23;
    } else if (root.name == kRoot18 || root.name == kRootAtlaSample) {
      out_.version = Tm33Version::Atla_S001;
    } else if (root.name == kRootOpticalData) {
      out_.version = Tm33Version::LuminaireOpticalData;
    } else {
      return fail(root.line, "root element <" + root.name + "> is not TM-33's <" + kRoot23 +
                                 "> (TM-33-23), <" + kRoot18 + "> (ATLA S001 / TM-33-18) or <" +
                                 kRootOpticalData + "> (ATLA S001 / UNI 11733)");
    }
    const XmlElement* version = root.child("Version");
    if (!version && out_.version == Tm33Version::LuminaireOpticalData) {
      // <LuminaireOpticalData version="1.0">: the version as an attribute.
      if (const std::string* a = root.attribute("version")) root.add("Version", *a).line = root.line;
      version = root.child("Version");
    }
    if (!version) return fail(root.line, "<Version> is missing");
    const std::string v = trimmed(version->text);
    const std::string expected = out_.version == Tm33Version::TM33_23 ? "1.1" : "1.0";
    if (v != expected && !(out_.version == Tm33Version::Atla_S001 && v == "1.1"))
      warn(version->line, "tm33-version",
           "<Version> " + v + " where <" + root.name + "> has " + expected + "; read as " +
               to_string(out_.version));
    if (!normalise(root)) return error_;
    const XmlElement* header = root.child("Header");
    if (!header) return fail(root.line, "<Header> is missing");
    const auto emitters = root.children_named("Emitter");
    if (emitters.empty()) return fail(root.line, "no <Emitter>");

    const XmlElement* emitter = nullptr;
    for (const XmlElement* e : emitters) {
      const XmlElement* data = e->child("LuminousData");
      if (data && data->child("LuminousIntensity")) {
        if (!emitter) {
          emitter = e;
        } else {
          warn(e->line, "tm33-emitter-ignored",
               "a further <Emitter> with luminous intensity data is not read: Gonio's model is "
               "one distribution (the first emitter's)");
        }
      }
    }
    if (!emitter) {
      const bool photon = emitters.front()->child("PhotonData") || emitters.front()->child("RadiantData");
      return fail(emitters.front()->line,
                  std::string("no <Emitter> has luminous intensity data (<LuminousData>/<LuminousIntensity>") +
                      (photon ? "; photon or radiant intensity is not luminous intensity, which Gonio reads)"
                              : ")"));
    }

    for (const XmlElement& c : root.children) {
      if (c.name == "Header" || c.name == "Luminaire" || c.name == "Equipment") {
        if (!walk(c, c.name)) return error_;
      } else if (&c == emitter) {
        if (!walk(c, "Emitter")) return error_;
      } else if (c.name == "CustomData") {
        custom_data(c);
      } else if (c.name != "Version" && c.name != "Emitter") {
        info(c.line, "tm33-unknown-element", "<" + c.name + "> is not a TM-33 element; not kept");
      }
    }
    if (!luminous_intensity_) return fail(emitter->line, "no <LuminousIntensity>");
    if (!model()) return error_;
    if (Status s = photometry::validate(out_.distribution); !s.ok())
      return fail(luminous_intensity_->line, s.error().message);
    for (Finding& f : out_.findings) f.where.file = name_;
    return std::move(out_);
  }

 private:
  Error fail(int line, std::string message) {
    error_ = make_error(name_, line, std::move(message));
    return error_;
  }
  void warn(int line, std::string code, std::string message) {
    out_.findings.push_back({Severity::Warning, std::move(code), std::move(message), {name_, line, 0}});
  }
  void info(int line, std::string code, std::string message) {
    out_.findings.push_back({Severity::Info, std::move(code), std::move(message), {name_, line, 0}});
  }

  // ------------------------------------------------------------- dialects
  //
  // The layouts in circulation beside the standard's are rewritten here into
  // the standard's tree (TM-33-23 / ATLA S001 as published: Version 1.1,
  // Header, Luminaire, Equipment/Gonioradiometer, Emitter with
  // LuminousData/LuminousIntensity/IntData h v and
  // SpectralData/EmitterSpectral/PwrData w), keeping each element's line, so
  // that one reader reads them all. Each rewrite used is listed once in a
  // "tm33-dialect" info line. What the rewrites cover (element names as
  // eulumdat-rs's ATLA crate writes them, in <LuminaireOpticalData> and in
  // <IESTM33-22>):
  //   Header: Comments -> Comment, UUID -> UniqueIdentifier, IssueDate ->
  //     ReportDate (where there is none), TestDate -> LM-63 [TESTDATE].
  //   Luminaire: NumEmitters -> NumEmitter.
  //   Equipment: Goniometer -> Gonioradiometer, GoniometerType -> Type.
  //   Emitter: InputWatts -> InputWattage, CCT and FixedCCT ->
  //     ColorTemperature/FixedCCT, ColorRendering/Ra, R9 -> CIE_CRI/..,
  //     ColorRendering/Rf, Rg -> IES_TM30/.., MeasuredLumens ->
  //     LuminousData/LuminousFlux, DataGeneration/Interpolated, Scaled,
  //     Source -> AngleInterpolation, IntensityScaling, Simulation;
  //     IntensityDistribution -> LuminousData; in LuminousData,
  //     <IntensityData horz vert> (with SymmType, Multiplier,
  //     AbsolutePhotometry, Number*, PhotometryType, Metric beside them) ->
  //     LuminousIntensity/IntData h v; SpectralDistribution (Wavelengths and
  //     Values as lists, Units) -> SpectralData/EmitterSpectral.
  bool normalise(XmlElement& root) {
    for (XmlElement& c : root.children) {
      if (c.name == "Header") {
        rename(c, "Comments", "Comment");
        rename(c, "UUID", "UniqueIdentifier");
        if (!c.child("ReportDate")) rename(c, "IssueDate", "ReportDate");
        for (auto it = c.children.begin(); it != c.children.end();) {
          if (it->name == "TestDate") {
            custom_keywords_.push_back({"TESTDATE", trimmed(it->text)});
            used("<TestDate> as LM-63 [TESTDATE]");
            it = c.children.erase(it);
          } else {
            ++it;
          }
        }
      } else if (c.name == "Luminaire") {
        rename(c, "NumEmitters", "NumEmitter");
      } else if (c.name == "Equipment") {
        rename(c, "Goniometer", "Gonioradiometer");
        for (XmlElement& g : c.children)
          if (g.name == "Gonioradiometer") rename(g, "GoniometerType", "Type");
      } else if (c.name == "Emitter") {
        if (!normalise_emitter(c)) return false;
      }
    }
    if (photometry_type_) {
      XmlElement& equipment = child_at(root, "Equipment", photometry_type_->line);
      XmlElement& gonio = child_at(equipment, "Gonioradiometer", photometry_type_->line);
      if (!gonio.child("Type")) {
        photometry_type_->name = "Type";
        gonio.children.push_back(std::move(*photometry_type_));
        used("<PhotometryType> as <Equipment>/<Gonioradiometer>/<Type>");
      }
    }
    if (!dialect_.empty()) {
      std::string list;
      for (const std::string& d : dialect_) list += (list.empty() ? "" : ", ") + d;
      info(root.line, "tm33-dialect", "read in the standard's layout: " + list);
    }
    return true;
  }

  void used(const std::string& what) {
    if (std::find(dialect_.begin(), dialect_.end(), what) == dialect_.end()) dialect_.push_back(what);
  }

  void rename(XmlElement& parent, const std::string& from, const std::string& to) {
    for (XmlElement& c : parent.children)
      if (c.name == from) {
        c.name = to;
        used("<" + from + "> as <" + to + ">");
      }
  }

  // The child of that name, created (at `line`) if there is none.
  static XmlElement& child_at(XmlElement& parent, const std::string& name, int line) {
    for (XmlElement& c : parent.children)
      if (c.name == name) return c;
    XmlElement& c = parent.add(name);
    c.line = line;
    return c;
  }

  // Moves every child `from` of `parent` to `path` below it (its last part the
  // new name), creating the elements between.
  void move(XmlElement& parent, const std::string& from, const std::string& path) {
    std::vector<XmlElement> moved;
    for (auto it = parent.children.begin(); it != parent.children.end();) {
      if (it->name == from) {
        moved.push_back(std::move(*it));
        it = parent.children.erase(it);
      } else {
        ++it;
      }
    }
    for (XmlElement& m : moved) {
      XmlElement* at = &parent;
      std::size_t start = 0;
      for (auto slash = path.find('/'); slash != std::string::npos; slash = path.find('/', start)) {
        at = &child_at(*at, path.substr(start, slash - start), m.line);
        start = slash + 1;
      }
      m.name = path.substr(start);
      at->children.push_back(std::move(m));
      used("<" + from + "> as <" + path + ">");
    }
  }

  bool normalise_emitter(XmlElement& e) {
    rename(e, "InputWatts", "InputWattage");
    move(e, "CCT", "ColorTemperature/FixedCCT");
    move(e, "FixedCCT", "ColorTemperature/FixedCCT");
    for (XmlElement& c : e.children) {
      if (c.name == "ColorRendering") {
        move(c, "Ra", "CIE_CRI/Ra");
        move(c, "R9", "CIE_CRI/R9");
        move(c, "Rf", "IES_TM30/Rf");
        move(c, "Rg", "IES_TM30/Rg");
      } else if (c.name == "DataGeneration") {
        rename(c, "Interpolated", "AngleInterpolation");
        rename(c, "Scaled", "IntensityScaling");
        for (XmlElement& g : c.children)
          if (g.name == "Source" && !c.child("Simulation")) {
            const std::string u = upper(trimmed(g.text));
            g.name = "Simulation";
            g.text = u.rfind("SIMUL", 0) == 0 || u == "CALCULATED" ? "true" : "false";
            used("<Source> " + trimmed(u) + " as <Simulation>");
          }
      }
    }
    if (!e.child("LuminousData")) rename(e, "IntensityDistribution", "LuminousData");
    if (e.child("LuminousData") && e.child("MeasuredLumens") && !e.child("LuminousData")->child("LuminousFlux"))
      move(e, "MeasuredLumens", "LuminousData/LuminousFlux");
    for (XmlElement& c : e.children)
      if (c.name == "LuminousData" && !intensity_data(c)) return false;
    std::vector<XmlElement> spectra;
    for (auto it = e.children.begin(); it != e.children.end();) {
      if (it->name == "SpectralDistribution") {
        spectra.push_back(std::move(*it));
        it = e.children.erase(it);
      } else {
        ++it;
      }
    }
    for (const XmlElement& s : spectra) {
      XmlElement spectral;
      if (!spectral_lists(s, spectral)) return false;
      child_at(e, "SpectralData", s.line).children.push_back(std::move(spectral));
      used("<SpectralDistribution> (lists) as <SpectralData>/<EmitterSpectral>");
    }
    return true;
  }

  // <LuminousData> holding <IntensityData horz vert> directly: the grid and
  // its description become a <LuminousIntensity> with <IntData h v>.
  bool intensity_data(XmlElement& data) {
    bool any = false;
    for (const XmlElement& c : data.children) any = any || c.name == "IntensityData";
    if (!any || data.child("LuminousIntensity")) return true;
    XmlElement li;
    li.name = "LuminousIntensity";
    li.line = data.line;
    std::vector<XmlElement> kept;
    for (XmlElement& c : data.children) {
      if (c.name == "IntensityData") {
        c.name = "IntData";
        for (auto& [key, value] : c.attributes) {
          if (key == "horz") key = "h";
          else if (key == "vert") key = "v";
        }
        li.children.push_back(std::move(c));
      } else if (c.name == "SymmType" || c.name == "Symm") {
        c.name = "Symm";
        li.children.push_back(std::move(c));
      } else if (c.name == "Multiplier" || c.name == "AbsolutePhotometry" || c.name == "NumberMeasured" ||
                 c.name == "NumberHorz" || c.name == "NumberVert") {
        li.children.push_back(std::move(c));
      } else if (c.name == "Metric") {
        const std::string m = upper(trimmed(c.text));
        if (m != "LUMINOUS") {
          fail(c.line, "<Metric> '" + trimmed(c.text) +
                           "': the intensities are not luminous intensities (cd), which Gonio reads");
          return false;
        }
      } else if (c.name == "PhotometryType") {
        // The photometric type where <Equipment> does not give it; added to
        // the root after its children are walked (adding now would move them).
        if (!photometry_type_) photometry_type_ = std::move(c);
      } else {
        kept.push_back(std::move(c));
      }
    }
    data.children = std::move(kept);
    data.children.insert(data.children.begin(), std::move(li));
    used("<IntensityData horz vert> in <LuminousData> as <LuminousIntensity>/<IntData h v>");
    per_klm_ = true;
    return true;
  }

  // <SpectralDistribution><Wavelengths>380 390 ...</Wavelengths><Values>...
  // </Values><Units>Relative</Units>: one <EmitterSpectral> with <PwrData w>.
  bool spectral_lists(const XmlElement& s, XmlElement& out) {
    out.name = "EmitterSpectral";
    out.line = s.line;
    const XmlElement* w = s.child("Wavelengths");
    const XmlElement* v = s.child("Values");
    if (!w || !v) {
      fail(s.line, "<SpectralDistribution> needs <Wavelengths> and <Values>");
      return false;
    }
    const auto list = [&](const XmlElement& e, std::vector<double>& out_values) {
      std::string token;
      const std::string text = e.text + " ";
      for (char c : text) {
        if (std::isspace(static_cast<unsigned char>(c)) || c == ',' || c == ';') {
          if (token.empty()) continue;
          const auto n = parse_number(token);
          if (!n) {
            fail(e.line, "<" + e.name + "> '" + token + "' is not a number");
            return false;
          }
          out_values.push_back(*n);
          token.clear();
        } else {
          token += c;
        }
      }
      return true;
    };
    std::vector<double> nm, values;
    if (!list(*w, nm) || !list(*v, values)) return false;
    if (nm.size() != values.size()) {
      fail(v->line, "<SpectralDistribution> has " + std::to_string(nm.size()) + " wavelengths but " +
                        std::to_string(values.size()) + " values");
      return false;
    }
    const XmlElement* units = s.child("Units");
    const std::string u = units ? upper(trimmed(units->text)) : "";
    if (u == "RELATIVE") out.add("Normalized", "true").line = units->line;
    for (std::size_t i = 0; i < nm.size(); ++i) {
      XmlElement& p = out.add("PwrData", number(values[i]));
      p.set("w", number(nm[i]));
      p.line = v->line;
    }
    return true;
  }

  bool walk(const XmlElement& e, const std::string& path) {
    for (const XmlElement& c : e.children) {
      const std::string p = path + "/" + c.name;
      if (p == "Emitter/TiltAngles") {
        tilt_ = &c;
      } else if (p == "Emitter/LuminousData/LuminousIntensity") {
        luminous_intensity_ = &c;
      } else if (p == "Emitter/SpectralData/EmitterSpectral") {
        spectra_.push_back(&c);
      } else if (auto it = not_kept().find(p); it != not_kept().end()) {
        warn(c.line, "tm33-not-kept",
             "<" + c.name + "> (" + it->second + ") is not part of Gonio's photometric model; not kept");
      } else if (!c.children.empty()) {
        if (!walk(c, p)) return false;
      } else if (std::find(schema_paths().begin(), schema_paths().end(), p) != schema_paths().end() ||
                 p == "Emitter/LuminousData/MeasuredCCT") {
        leaves_[p].push_back({trimmed(c.text), c.line});
      } else {
        info(c.line, "tm33-unknown-element", "<" + p + "> is not a TM-33 element; not kept");
      }
    }
    return true;
  }

  void custom_data(const XmlElement& c) {
    const XmlElement* id = c.child("UniqueIdentifier");
    if (id && trimmed(id->text) == kGonioCustomId) {
      for (const XmlElement* k : c.children_named("Keyword")) {
        const std::string* key = k->attribute("key");
        if (key) custom_keywords_.push_back({*key, k->text});
      }
      return;
    }
    const XmlElement* name = c.child("Name");
    warn(c.line, "tm33-not-kept",
         "<CustomData> '" + (name ? trimmed(name->text) : std::string("unnamed")) +
             "' is not part of Gonio's photometric model; not kept");
  }

  const Leaf* leaf(const std::string& path) const {
    auto it = leaves_.find(path);
    return it == leaves_.end() || it->second.empty() ? nullptr : &it->second.front();
  }

  std::optional<double> number_at(const std::string& path, bool& ok) {
    const Leaf* l = leaf(path);
    if (!l) return std::nullopt;
    auto v = parse_number(l->text);
    if (!v) {
      fail(l->line, "<" + path.substr(path.rfind('/') + 1) + "> '" + l->text + "' is not a number");
      ok = false;
    }
    return v;
  }

  std::optional<bool> boolean_at(const std::string& path, bool& ok) {
    const Leaf* l = leaf(path);
    if (!l) return std::nullopt;
    const std::string u = upper(l->text);  // "False" as DLC's template writes it
    if (u == "TRUE" || u == "1") return true;
    if (u == "FALSE" || u == "0") return false;
    fail(l->line, "<" + path.substr(path.rfind('/') + 1) + "> '" + l->text + "' is not true or false");
    ok = false;
    return std::nullopt;
  }

  bool model() {
    Distribution& d = out_.distribution;
    bool ok = true;
    // Keywords first, in schema order, so that an IES file lists them so.
    for (const std::string& path : schema_paths()) {
      auto it = leaves_.find(path);
      if (it == leaves_.end() || model_paths().count(path)) continue;
      const auto named = keyword_of_path().find(path);
      for (const Leaf& l : it->second)
        d.keywords.push_back({named != keyword_of_path().end() ? named->second : keyword_for(path), l.text});
    }
    if (auto it = leaves_.find("Emitter/LuminousData/MeasuredCCT"); it != leaves_.end())
      for (const Leaf& l : it->second) d.keywords.push_back({keyword_for("Emitter/LuminousData/MeasuredCCT"), l.text});
    for (photometry::Keyword& k : custom_keywords_) d.keywords.push_back(std::move(k));

    // Photometric type.
    d.type = PhotometricType::C;
    if (const Leaf* t = leaf("Equipment/Gonioradiometer/Type")) {
      // "CIE_C" as published, "CIE _ C" as TM-33-23's tables print it, "Type C" and "C".
      std::string u;
      for (char c : upper(t->text))
        if (!std::isspace(static_cast<unsigned char>(c))) u += c;
      if (u.rfind("TYPE", 0) == 0) u = u.substr(4);
      if (u.size() == 1) u = "IES_" + u;
      if (u == "CIE_C" || u == "IES_C") d.type = PhotometricType::C;
      else if (u == "CIE_B" || u == "IES_B") d.type = PhotometricType::B;
      else if (u == "CIE_A" || u == "IES_A") d.type = PhotometricType::A;
      else {
        fail(t->line, "photometric type '" + t->text +
                          "' is not one Gonio reads (CIE_A, CIE_B, CIE_C, IES_A, IES_B, IES_C)");
        return false;
      }
      if (u.rfind("CIE", 0) == 0) d.keywords.push_back({keyword_for("Equipment/Gonioradiometer/Type"), u});
    } else {
      info(0, "tm33-type-assumed", "no <Gonioradiometer>/<Type>: read as Type C");
    }

    // Luminaire body [m].
    const auto length = number_at("Luminaire/Dimensions/Length", ok);
    const auto width = number_at("Luminaire/Dimensions/Width", ok);
    const auto height = number_at("Luminaire/Dimensions/Height", ok);
    if (!ok) return false;
    // Metres as the standard has them; millimetres as eulumdat-rs writes them
    // (a 600 mm panel as 600): a dimension over 20 m is read as millimetres.
    const double scale = std::max({length.value_or(0.0), width.value_or(0.0), height.value_or(0.0)}) > 20.0
                             ? 1e-3 : 1.0;
    if (scale != 1.0)
      warn(leaf("Luminaire/Dimensions/Length") ? leaf("Luminaire/Dimensions/Length")->line : 0,
           "tm33-dimensions-mm",
           "luminaire dimensions over 20 m read as millimetres (the standard's unit is the metre)");
    if (length) d.luminaire.length_m = *length * scale;
    if (width) d.luminaire.width_m = *width * scale;
    if (height) d.luminaire.height_m = *height * scale;

    // Emitter.
    photometry::LampSet lamp;
    const auto quantity = number_at("Emitter/Quantity", ok);
    if (!ok) return false;
    if (quantity) {
      if (*quantity < 1 || *quantity != std::floor(*quantity) || *quantity > 1e6) {
        fail(leaf("Emitter/Quantity")->line, "<Quantity> must be a whole number of at least 1");
        return false;
      }
      lamp.count = static_cast<int>(*quantity);
    }
    if (const Leaf* l = leaf("Emitter/Description")) lamp.type = l->text;
    const auto rated = number_at("Emitter/RatedLumens", ok);
    const auto watts = number_at("Emitter/InputWattage", ok);
    const auto ballast = number_at("Emitter/BallastFactor", ok);
    const auto cct = number_at("Emitter/ColorTemperature/FixedCCT", ok);
    const auto ra = number_at("Emitter/ColorRendering/CIE_CRI/Ra", ok);
    if (!ok) return false;
    if (watts) {
      d.input_watts = *watts * lamp.count;
      lamp.power_w = d.input_watts;
    }
    if (ballast) d.ballast_factor = *ballast;
    if (cct) lamp.color = number(*cct) + " K";
    if (ra) lamp.color_rendering = number(*ra);

    const XmlElement& li = *luminous_intensity_;
    std::optional<bool> absolute;
    if (const XmlElement* a = li.child("AbsolutePhotometry")) {
      const std::string t = trimmed(a->text);
      if (upper(t) == "TRUE" || t == "1") absolute = true;
      else if (upper(t) == "FALSE" || t == "0") absolute = false;
      else {
        fail(a->line, "<AbsolutePhotometry> '" + t + "' is not true or false");
        return false;
      }
    }
    d.absolute = absolute.value_or(!rated.has_value());
    if (!d.absolute) {
      if (!rated || !(*rated > 0.0)) {
        warn(li.line, "tm33-no-rated-lumens",
             "relative photometry without a positive <RatedLumens>: read as absolute photometry");
        d.absolute = true;
      } else {
        lamp.flux_lm = *rated * lamp.count;
      }
    } else if (rated) {
      d.keywords.push_back({keyword_for("Emitter/RatedLumens"), leaf("Emitter/RatedLumens")->text});
    }
    d.lamps = {lamp};

    // Data generation: the LM-63-2019 file generation type.
    const auto simulation = boolean_at("Emitter/DataGeneration/Simulation", ok);
    const auto scaled = boolean_at("Emitter/DataGeneration/IntensityScaling", ok);
    const auto interpolated = boolean_at("Emitter/DataGeneration/AngleInterpolation", ok);
    if (!ok) return false;
    if (simulation || scaled || interpolated || leaf("Emitter/DataGeneration/Laboratory/Certification")) {
      const bool accredited = leaf("Emitter/DataGeneration/Laboratory/Certification") != nullptr;
      const bool s = scaled.value_or(false), i = interpolated.value_or(false);
      if (simulation.value_or(false)) d.file_generation = FileGenerationType::ComputerSimulation;
      else if (accredited)
        d.file_generation = i ? (s ? FileGenerationType::AccreditedLabInterpolatedScaled
                                   : FileGenerationType::AccreditedLabInterpolated)
                              : (s ? FileGenerationType::AccreditedLabScaled : FileGenerationType::AccreditedLab);
      else
        d.file_generation = i ? (s ? FileGenerationType::UnaccreditedLabInterpolatedScaled
                                   : FileGenerationType::UnaccreditedLabInterpolated)
                              : (s ? FileGenerationType::UnaccreditedLabScaled : FileGenerationType::UnaccreditedLab);
    }

    if (tilt_ && !read_tilt(*tilt_)) return false;
    if (!read_intensity(li)) return false;
    // The dialect's <IntensityData> are candelas per 1000 lamp lumens for
    // relative photometry: eulumdat-rs's ATLA model (crates/atla, types.rs:
    // IntensityUnits, default CandelaPerKilolumen) writes an LDT's cd/klm into
    // them unchanged, and its files' rated lumens only agree with their
    // intensities so read.
    if (per_klm_ && !d.absolute && lamp.flux_lm > 0.0) {
      const double per_klm = lamp.flux_lm / 1000.0;
      for (double& cd : d.candela) cd *= per_klm;
      info(li.line, "tm33-dialect-cd-per-klm",
           "<IntensityData> read as cd/klm (the unit of the tool that writes this layout) and scaled to the "
           "rated " + number(lamp.flux_lm) + " lm");
    }
    for (const XmlElement* s : spectra_)
      if (!read_spectrum(*s)) return false;
    return true;
  }

  bool read_tilt(const XmlElement& t) {
    photometry::Tilt& tilt = out_.distribution.tilt;
    for (const XmlElement* e : t.children_named("Tilt")) {
      const auto a = number_attribute(*e, "angle");
      const auto f = parse_number(trimmed(e->text));
      if (!a || !f) {
        fail(e->line, "<Tilt> needs a numeric angle attribute and factor");
        return false;
      }
      tilt.angles_deg.push_back(*a);
      tilt.factors.push_back(*f);
    }
    if (tilt.angles_deg.empty()) return true;
    tilt.kind = photometry::Tilt::Kind::Include;
    tilt.lamp_geometry = 1;
    info(t.line, "tilt-geometry-assumed",
         "TM-33 has no lamp-to-luminaire geometry for tilt data: geometry 1 (vertical base-up or "
         "base-down) assumed");
    return true;
  }

  bool read_intensity(const XmlElement& li) {
    Distribution& d = out_.distribution;
    double multiplier = 1.0;
    if (const XmlElement* m = li.child("Multiplier")) {
      const auto v = parse_number(trimmed(m->text));
      if (!v || !(*v > 0.0)) {
        fail(m->line, "<Multiplier> '" + trimmed(m->text) + "' is not a positive number");
        return false;
      }
      multiplier = *v;
    }
    const auto count = [&](const char* tag, std::optional<long>& out) {
      const XmlElement* e = li.child(tag);
      if (!e) return true;
      const auto v = parse_number(trimmed(e->text));
      if (!v || *v < 1 || *v != std::floor(*v) || *v > 1e7) {
        fail(e->line, std::string("<") + tag + "> '" + trimmed(e->text) + "' is not a positive whole number");
        return false;
      }
      out = static_cast<long>(*v);
      return true;
    };
    std::optional<long> measured, n_horz, n_vert;
    if (!count("NumberMeasured", measured) || !count("NumberHorz", n_horz) || !count("NumberVert", n_vert))
      return false;

    struct Point {
      double h, v, value;
      int line;
    };
    std::vector<Point> points;
    for (const XmlElement& e : li.children) {
      if (e.name != "IntData") continue;
      const auto hv = number_attribute(e, "h");
      const auto vv = number_attribute(e, "v");
      if (!hv || !vv) {
        fail(e.line, "<IntData> needs numeric h and v attributes");
        return false;
      }
      const auto value = parse_number(trimmed(e.text));
      if (!value) {
        fail(e.line, "<IntData> '" + trimmed(e.text) + "' is not a number");
        return false;
      }
      points.push_back({*hv, *vv, *value * multiplier, e.line});
    }
    if (points.empty()) {
      fail(li.line, "<LuminousIntensity> holds no <IntData>");
      return false;
    }
    if (measured && static_cast<std::size_t>(*measured) != points.size()) {
      fail(li.child("NumberMeasured")->line, "<NumberMeasured> " + std::to_string(*measured) + " but " +
                                                 std::to_string(points.size()) + " <IntData>");
      return false;
    }
    std::vector<double> hs, vs;
    for (const Point& p : points) {
      hs.push_back(p.h);
      vs.push_back(p.v);
    }
    std::sort(hs.begin(), hs.end());
    hs.erase(std::unique(hs.begin(), hs.end()), hs.end());
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    if (n_horz && static_cast<std::size_t>(*n_horz) != hs.size()) {
      fail(li.child("NumberHorz")->line, "<NumberHorz> " + std::to_string(*n_horz) + " but the data has " +
                                             std::to_string(hs.size()) + " horizontal angles");
      return false;
    }
    if (n_vert && static_cast<std::size_t>(*n_vert) != vs.size()) {
      fail(li.child("NumberVert")->line, "<NumberVert> " + std::to_string(*n_vert) + " but the data has " +
                                             std::to_string(vs.size()) + " vertical angles");
      return false;
    }
    if (hs.size() * vs.size() != points.size()) {
      fail(li.line, "the " + std::to_string(points.size()) + " <IntData> do not form a grid of " +
                        std::to_string(hs.size()) + " horizontal x " + std::to_string(vs.size()) +
                        " vertical angles");
      return false;
    }
    d.horizontal_deg = hs;
    d.vertical_deg = vs;
    d.candela.assign(points.size(), photometry::kNaN);
    int negative = 0, first_negative_line = 0;
    for (const Point& p : points) {
      const std::size_t i = static_cast<std::size_t>(std::lower_bound(hs.begin(), hs.end(), p.h) - hs.begin());
      const std::size_t j = static_cast<std::size_t>(std::lower_bound(vs.begin(), vs.end(), p.v) - vs.begin());
      double& slot = d.candela[i * vs.size() + j];
      if (!std::isnan(slot)) {
        fail(p.line, "<IntData> h=" + number(p.h) + " v=" + number(p.v) + " is given twice");
        return false;
      }
      double value = p.value;
      if (value < 0.0) {
        if (negative++ == 0) first_negative_line = p.line;
        value = 0.0;
      }
      slot = value;
    }
    if (negative > 0)
      warn(first_negative_line, "negative-intensity",
           std::to_string(negative) + " negative intensities read as 0 (the first here)");

    // Symmetry: <Symm> where given, else the range of h as LM-63 reads it.
    std::optional<Symmetry> symm;
    int symm_line = li.line;
    if (const XmlElement* s = li.child("Symm")) {
      symm_line = s->line;
      // "Symm_Quad", "Symm _ Quad" as TM-33-23's tables print it, "Symm _ Bi90".
      std::string t;
      for (char c : upper(s->text))
        if (!std::isspace(static_cast<unsigned char>(c)) && c != '_') t += c;
      if (t.rfind("SYMM", 0) == 0) t = t.substr(4);
      if (t == "NONE" || t == "ARBITRARY") symm = Symmetry::None;
      else if (t == "BI0") symm = Symmetry::C0_C180;
      else if (t == "BI90") symm = Symmetry::C90_C270;
      else if (t == "QUAD") symm = Symmetry::Quadrant;
      else if (t == "FULL") symm = Symmetry::Rotational;
      else {
        fail(s->line, "<Symm> '" + trimmed(s->text) + "' is not a TM-33 symmetry");
        return false;
      }
    }
    const double first = hs.front(), last = hs.back();
    if (d.type == PhotometricType::C) {
      Symmetry by_range = Symmetry::None;
      if (hs.size() == 1) by_range = Symmetry::Rotational;
      else if (first == 0.0 && last == 90.0) by_range = Symmetry::Quadrant;
      else if (first == 0.0 && last == 180.0) by_range = Symmetry::C0_C180;
      else if (first == 90.0 && last == 270.0) by_range = Symmetry::C90_C270;
      if (symm && *symm != by_range && !(*symm == Symmetry::None && first == 0.0 && last <= 360.0)) {
        fail(symm_line, std::string("<Symm> says ") + photometry::to_string(*symm) +
                            " but the horizontal angles run from " + number(first) + " to " + number(last));
        return false;
      }
      d.symmetry = symm.value_or(by_range);
    } else {
      d.symmetry = first == 0.0 && last > 0.0 ? Symmetry::Lateral : Symmetry::None;
      if (hs.size() == 1) d.symmetry = Symmetry::None;
    }
    return true;
  }

  bool read_spectrum(const XmlElement& e) {
    photometry::Spectrum s;
    if (const XmlElement* n = e.child("EmitterName")) s.emitter = trimmed(n->text);
    double multiplier = 1.0;
    if (const XmlElement* m = e.child("Multiplier")) {
      const auto v = parse_number(trimmed(m->text));
      if (!v) {
        fail(m->line, "<Multiplier> '" + trimmed(m->text) + "' is not a number");
        return false;
      }
      multiplier = *v;
    }
    if (const XmlElement* n = e.child("Normalized")) s.normalized = trimmed(n->text) == "true" || trimmed(n->text) == "1";
    std::vector<std::pair<double, double>> data;
    for (const XmlElement* p : e.children_named("PwrData")) {
      const auto wv = number_attribute(*p, "w");
      const auto value = parse_number(trimmed(p->text));
      if (!wv || !value) {
        fail(p->line, "<PwrData> needs a numeric w attribute and value");
        return false;
      }
      data.emplace_back(*wv, *value * multiplier);
    }
    std::sort(data.begin(), data.end());
    for (std::size_t i = 1; i < data.size(); ++i)
      if (data[i].first == data[i - 1].first) {
        fail(e.line, "<EmitterSpectral> gives wavelength " + number(data[i].first) + " nm twice");
        return false;
      }
    if (const XmlElement* n = e.child("NumberWavelength")) {
      const auto v = parse_number(trimmed(n->text));
      if (!v || *v != static_cast<double>(data.size())) {
        fail(n->line, "<NumberWavelength> " + trimmed(n->text) + " but " + std::to_string(data.size()) +
                          " <PwrData>");
        return false;
      }
    }
    for (const auto& [w, v] : data) {
      s.wavelength_nm.push_back(w);
      s.values.push_back(v);
    }
    for (const char* dropped : {"Timestamp", "Quantum"})
      if (e.child(dropped))
        warn(e.child(dropped)->line, "tm33-not-kept",
             std::string("<") + dropped + "> of a spectrum is not kept");
    out_.distribution.spectra.push_back(std::move(s));
    return true;
  }

  std::string_view bytes_;
  std::string name_;
  Tm33File out_;
  Error error_;
  std::map<std::string, std::vector<Leaf>> leaves_;
  std::vector<photometry::Keyword> custom_keywords_;
  const XmlElement* tilt_ = nullptr;
  const XmlElement* luminous_intensity_ = nullptr;
  std::vector<const XmlElement*> spectra_;
  std::vector<std::string> dialect_;  // the dialect's rewrites used, in order
  bool per_klm_ = false;              // intensities in the dialect's <IntensityData> (cd/klm)
  std::optional<XmlElement> photometry_type_;  // the dialect's <PhotometryType>, the first
};

// ------------------------------------------------------------------ writing

class Tm33Writer {
 public:
  Tm33Writer(const Distribution& d, std::vector<Finding>* warnings) : d_(d), warnings_(warnings) {}

  std::string write() {
    std::map<std::string, std::vector<std::string>> values;
    std::vector<bool> used(d_.keywords.size(), false);
    std::map<std::string, std::string> path_of_keyword;
    for (const std::string& p : schema_paths()) path_of_keyword[keyword_for(p)] = p;
    for (const auto& [p, k] : keyword_of_path()) path_of_keyword[k] = p;
    for (std::size_t i = 0; i < d_.keywords.size(); ++i) {
      auto it = path_of_keyword.find(upper(d_.keywords[i].key));
      if (it == path_of_keyword.end() || model_paths().count(it->second)) continue;
      values[it->second].push_back(d_.keywords[i].value);
      used[i] = true;
    }
    // Required header strings.
    for (const char* p : {"Header/Description", "Header/Laboratory", "Header/ReportNumber", "Header/ReportDate"}) {
      if (values.count(p)) continue;
      if (std::string(p) == "Header/ReportDate")
        if (const photometry::Keyword* k = d_.find_keyword("TESTDATE")) {
          values[p].push_back(k->value);
          continue;
        }
      values[p].push_back("not stated");
      warn("tm33-required-missing", std::string("required <") + (p + 7) + "> unknown: written as 'not stated'");
    }

    const photometry::LampSet lamp = d_.lamps.empty() ? photometry::LampSet{} : d_.lamps.front();
    const int count = std::max(1, lamp.count);
    // Luminaire: only with its required dimensions.
    const auto& b = d_.luminaire;
    if (std::isfinite(b.length_m) && std::isfinite(b.width_m) && std::isfinite(b.height_m)) {
      values["Luminaire/Dimensions/Length"] = {number(b.length_m)};
      values["Luminaire/Dimensions/Width"] = {number(b.width_m)};
      values["Luminaire/Dimensions/Height"] = {number(b.height_m)};
      values["Luminaire/NumEmitter"] = {"1"};
    } else {
      for (const char* p : {"Luminaire/Shape"})
        if (values.erase(p)) warn("tm33-luminaire-dropped", "<Luminaire> needs dimensions, which are unknown: <Shape> not written");
    }
    // Photometric type (CIE_ where the source said so).
    const char letter = d_.type == PhotometricType::C ? 'C' : d_.type == PhotometricType::B ? 'B' : 'A';
    std::string type = std::string("IES_") + letter;
    if (const photometry::Keyword* k = d_.find_keyword(keyword_for("Equipment/Gonioradiometer/Type")))
      if (upper(k->value) == std::string("CIE_") + letter) type = k->value;
    for (std::size_t i = 0; i < d_.keywords.size(); ++i)
      if (upper(d_.keywords[i].key) == keyword_for("Equipment/Gonioradiometer/Type")) used[i] = true;
    values["Equipment/Gonioradiometer/Type"] = {type};

    values["Emitter/Quantity"] = {std::to_string(count)};
    std::string description = lamp.type;
    if (description.empty())
      if (const photometry::Keyword* k = d_.find_keyword("LAMP")) description = k->value;
    if (description.empty()) {
      description = "not stated";
      warn("tm33-required-missing", "required <Emitter>/<Description> unknown: written as 'not stated'");
    }
    values["Emitter/Description"] = {description};
    if (!d_.absolute && std::isfinite(lamp.flux_lm)) values["Emitter/RatedLumens"] = {number(lamp.flux_lm / count)};
    for (std::size_t i = 0; i < d_.keywords.size(); ++i)
      if (upper(d_.keywords[i].key) == keyword_for("Emitter/RatedLumens")) {
        if (d_.absolute) values["Emitter/RatedLumens"] = {d_.keywords[i].value};
        used[i] = true;
      }
    const double watts = std::isfinite(d_.input_watts) ? d_.input_watts : lamp.power_w;
    if (std::isfinite(watts)) {
      values["Emitter/InputWattage"] = {number(watts / count)};
    } else {
      warn("tm33-required-missing", "required <Emitter>/<InputWattage> unknown: not written");
    }
    if (d_.ballast_factor != 1.0) values["Emitter/BallastFactor"] = {number(d_.ballast_factor)};
    if (!lamp.color.empty()) {
      if (auto k = leading_integer(lamp.color, "K"); k && *k >= 1000 && *k <= 100000)
        values["Emitter/ColorTemperature/FixedCCT"] = {std::to_string(*k)};
      else
        warn("tm33-lamp-color", "lamp colour '" + lamp.color + "' is not a colour temperature in K; not written");
    }
    if (!lamp.color_rendering.empty()) {
      if (auto ra = leading_integer(lamp.color_rendering, ""); ra && *ra >= 0 && *ra <= 100)
        values["Emitter/ColorRendering/CIE_CRI/Ra"] = {std::to_string(*ra)};
      else
        warn("tm33-color-rendering", "colour rendering '" + lamp.color_rendering +
                                         "' is not a CIE Ra index; not written");
    }
    generation(values);

    XmlElement root;
    root.name = kRoot23;
    root.add("Version", "1.1");
    for (const std::string& p : schema_paths()) {
      if (p == "Emitter/TiltAngles") {
        tilt(element(root, "Emitter"));
        continue;
      }
      if (p == "Emitter/LuminousData/LuminousIntensity") {
        intensity(element(element(root, "Emitter"), "LuminousData").add("LuminousIntensity"));
        continue;
      }
      if (p == "Emitter/SpectralData/EmitterSpectral") {
        spectra(root);
        continue;
      }
      auto it = values.find(p);
      if (it == values.end()) continue;
      const auto slash = p.rfind('/');
      XmlElement* parent = &root;
      std::size_t start = 0;
      while (start < slash) {
        const auto next = p.find('/', start);
        parent = &element(*parent, p.substr(start, next - start));
        start = next + 1;
      }
      for (const std::string& v : it->second) parent->add(p.substr(slash + 1), v);
    }
    custom_keywords(root, used);
    lost_fields();
    return write_xml(root);
  }

 private:
  void warn(std::string code, std::string message) {
    if (warnings_) warnings_->push_back({Severity::Warning, std::move(code), std::move(message), {}});
  }
  void note(std::string code, std::string message) {
    if (warnings_) warnings_->push_back({Severity::Info, std::move(code), std::move(message), {}});
  }

  // The last child of that name, created if there is none.
  static XmlElement& element(XmlElement& parent, const std::string& name) {
    for (auto it = parent.children.rbegin(); it != parent.children.rend(); ++it)
      if (it->name == name) return *it;
    return parent.add(name);
  }

  static std::optional<int> leading_integer(const std::string& text, const std::string& unit) {
    std::string t = trimmed(text);
    if (!unit.empty() && t.size() > unit.size() && upper(t.substr(t.size() - unit.size())) == unit)
      t = trimmed(t.substr(0, t.size() - unit.size()));
    if (unit.empty() && upper(t).rfind("RA", 0) == 0) t = trimmed(t.substr(2));
    const auto v = parse_number(t);
    if (!v || *v != std::floor(*v)) return std::nullopt;
    return static_cast<int>(*v);
  }

  void generation(std::map<std::string, std::vector<std::string>>& values) {
    using F = FileGenerationType;
    const F g = d_.file_generation;
    if (g == F::Undefined) return;
    const bool simulation = g == F::ComputerSimulation;
    const bool accredited = g == F::AccreditedLab || g == F::AccreditedLabScaled ||
                            g == F::AccreditedLabInterpolated || g == F::AccreditedLabInterpolatedScaled;
    const bool scaled = g == F::UnaccreditedLabScaled || g == F::UnaccreditedLabInterpolatedScaled ||
                        g == F::AccreditedLabScaled || g == F::AccreditedLabInterpolatedScaled;
    const bool interpolated = g == F::UnaccreditedLabInterpolated || g == F::UnaccreditedLabInterpolatedScaled ||
                              g == F::AccreditedLabInterpolated || g == F::AccreditedLabInterpolatedScaled;
    values["Emitter/DataGeneration/Simulation"] = {simulation ? "true" : "false"};
    values["Emitter/DataGeneration/IntensityScaling"] = {scaled ? "true" : "false"};
    values["Emitter/DataGeneration/AngleInterpolation"] = {interpolated ? "true" : "false"};
    if (accredited && !values.count("Emitter/DataGeneration/Laboratory/Certification"))
      warn("tm33-accreditation", "accredited laboratory without its certification, approval body and scope: "
                                 "TM-33's <Laboratory> needs them, so the accreditation is not written");
  }

  void tilt(XmlElement& emitter) {
    const photometry::Tilt& t = d_.tilt;
    if (t.kind == photometry::Tilt::Kind::None || t.angles_deg.empty()) return;
    XmlElement& e = emitter.add("TiltAngles");
    e.add("NumberAngles", std::to_string(t.angles_deg.size()));
    for (std::size_t i = 0; i < t.angles_deg.size() && i < t.factors.size(); ++i)
      e.add("Tilt", number(t.factors[i])).set("angle", number(t.angles_deg[i]));
    if (t.lamp_geometry != 1)
      warn("tm33-tilt-geometry", "TILT lamp-to-luminaire geometry " + std::to_string(t.lamp_geometry) +
                                     " has no TM-33 element; not written");
  }

  void intensity(XmlElement& li) {
    li.add("AbsolutePhotometry", d_.absolute ? "true" : "false");
    if (d_.type == PhotometricType::C) {
      const char* symm = "Symm_None";
      switch (d_.symmetry) {
        case Symmetry::Rotational: symm = "Symm_Full"; break;
        case Symmetry::C0_C180: symm = "Symm_Bi_0"; break;
        case Symmetry::C90_C270: symm = "Symm_Bi_90"; break;
        case Symmetry::Quadrant: symm = "Symm_Quad"; break;
        default: break;
      }
      li.add("Symm", symm);
    }
    li.add("Multiplier", "1");
    li.add("NumberMeasured", std::to_string(d_.candela.size()));
    li.add("NumberHorz", std::to_string(d_.horizontal_deg.size()));
    li.add("NumberVert", std::to_string(d_.vertical_deg.size()));
    li.children.reserve(li.children.size() + d_.candela.size());
    for (std::size_t h = 0; h < d_.horizontal_deg.size(); ++h)
      for (std::size_t v = 0; v < d_.vertical_deg.size(); ++v)
        li.add("IntData", number(d_.at(h, v)))
            .set("h", number(d_.horizontal_deg[h]))
            .set("v", number(d_.vertical_deg[v]));
  }

  void spectra(XmlElement& root) {
    for (const photometry::Spectrum& s : d_.spectra) {
      XmlElement& e = element(element(root, "Emitter"), "SpectralData").add("EmitterSpectral");
      if (!s.emitter.empty()) e.add("EmitterName", s.emitter);
      e.add("NumberWavelength", std::to_string(s.wavelength_nm.size()));
      if (s.normalized) e.add("Normalized", "true");
      for (std::size_t i = 0; i < s.wavelength_nm.size() && i < s.values.size(); ++i)
        e.add("PwrData", number(s.values[i])).set("w", number(s.wavelength_nm[i]));
    }
  }

  // LM-63 keywords without a TM-33 element, in a CustomData block of
  // Gonio's, so that IES -> TM-33 -> IES keeps them.
  void custom_keywords(XmlElement& root, const std::vector<bool>& used) {
    XmlElement custom;
    custom.name = "CustomData";
    custom.add("Name", "LM-63 keywords without a TM-33 element (Gonio)");
    custom.add("UniqueIdentifier", kGonioCustomId);
    int n = 0;
    for (std::size_t i = 0; i < d_.keywords.size(); ++i) {
      if (used[i]) continue;
      const std::string key = upper(d_.keywords[i].key);
      if (key == "LAMP" && d_.keywords[i].value == (d_.lamps.empty() ? "" : d_.lamps.front().type)) continue;
      if (key.rfind(kKeywordPrefix, 0) == 0) {
        warn("tm33-keyword-dropped", "[" + d_.keywords[i].key + "] is not an element of TM-33-23; not written");
        continue;
      }
      custom.add("Keyword", d_.keywords[i].value).set("key", d_.keywords[i].key);
      ++n;
    }
    if (n > 0) {
      note("tm33-custom-keywords", std::to_string(n) + (n == 1 ? " keyword" : " keywords") +
                                       " without a TM-33 element written in <CustomData> '" + kGonioCustomId +
                                       "'");
      root.children.push_back(std::move(custom));
    }
  }

  void lost_fields() {
    if (d_.lamps.size() > 1)
      warn("tm33-lamp-sets-merged", std::to_string(d_.lamps.size()) +
                                        " lamp sets: TM-33 is written with the first as its emitter");
    if (!d_.alternative_lamps.empty())
      warn("tm33-alternative-lamps", std::to_string(d_.alternative_lamps.size()) +
                                         " alternative lamp sets have no TM-33 element; not written");
    if (d_.opening.shape != photometry::OpeningShape::Point)
      warn("tm33-opening", std::string("luminous opening (") + photometry::to_string(d_.opening.shape) +
                               ") is not written: TM-33's emission areas describe faces Gonio's model lacks");
    if (std::isfinite(d_.declared_lor_percent) || std::isfinite(d_.declared_dff_percent))
      warn("tm33-declared-ratios", "declared LOR/DFF have no TM-33 element; not written");
    if (!d_.direct_ratios.empty())
      warn("tm33-direct-ratios", "direct ratios have no TM-33 element; not written");
    if (std::isfinite(d_.measurement_tilt_deg) && d_.measurement_tilt_deg != 0.0)
      warn("tm33-measurement-tilt", "measurement tilt has no TM-33 element; not written");
    if (d_.ballast_lamp_factor != 1.0)
      warn("tm33-ballast-lamp-factor", "LM-63 ballast-lamp photometric factor has no TM-33 element; not written");
  }

  const Distribution& d_;
  std::vector<Finding>* warnings_;
};

}  // namespace

const char* to_string(Tm33Version version) {
  switch (version) {
    case Tm33Version::TM33_23: return "TM-33-23";
    case Tm33Version::LuminaireOpticalData: return "ATLA S001/UNI 11733 (LuminaireOpticalData)";
    default: return "TM-33-18/ATLA S001";
  }
}

bool looks_like_tm33(std::string_view bytes) {
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);
  bytes = bytes.substr(0, 65536);
  std::size_t i = 0;
  while (i < bytes.size()) {
    while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
    if (i >= bytes.size() || bytes[i] != '<') return false;
    if (bytes.compare(i, 4, "<!--") == 0) {
      const auto end = bytes.find("-->", i + 4);
      if (end == std::string_view::npos) return false;
      i = end + 3;
    } else if (bytes.compare(i, 2, "<?") == 0 || bytes.compare(i, 2, "<!") == 0) {
      // A DOCTYPE's internal subset ends with "]>".
      const auto gt = bytes.find('>', i + 2), bracket = bytes.find('[', i + 2);
      const auto end = bracket < gt ? bytes.find("]>", bracket) : gt;
      if (end == std::string_view::npos) return false;
      i = end + (bracket < gt ? 2 : 1);
    } else {
      std::size_t j = i + 1;
      while (j < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[j])) && bytes[j] != '>' &&
             bytes[j] != '/')
        ++j;
      const std::string name = local_name(std::string(bytes.substr(i + 1, j - i - 1)));
      return name == kRoot23 || name == kRoot18 || name == kRootOpticalData || name == kRootAtlaSample;
    }
  }
  return false;
}

Result<Tm33File> parse_tm33(std::string_view bytes, const std::string& name) {
  return Tm33Reader(bytes, name).read();
}

std::string write_tm33(const Distribution& d, std::vector<Finding>* warnings) {
  return Tm33Writer(d, warnings).write();
}

}  // namespace gonio::io
