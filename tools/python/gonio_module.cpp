// `import gonio`: the Python module (gonio._gonio, re-exported by
// gonio/__init__.py; stubs in gonio/__init__.pyi). It binds the libraries
// the `gonio` command uses and computes nothing of its own: files are read
// by io::read_photometric_file, figures are gonio info --json's objects
// (tools/photometric_report.h), simulations run the progressive loop of
// gonio simulate. The only file that includes pybind11.
//
// Conventions a Python user meets:
// - Arrays share memory with the C++ objects (no copy) and keep them alive;
//   the candela table is (horizontal angles, vertical angles), i.e. (C, γ)
//   for Type C, in candela.
// - Figures are plain Python data (dict, list, float, None): the JSON of
//   `gonio info --json` under the same keys, null as None.
// - Bad input raises gonio.GonioError with .file, .line, .column and
//   .message; bad arguments raise ValueError; an undefined planning figure
//   returns None with a gonio.UndefinedFigureWarning saying why.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gonio/version.h"
#include "io/photometric/photometric_file.h"
#include "photometry/compare.h"
#include "photometry/planning.h"
#include "photometry/summary.h"
#include "photometry/validation.h"
#include "tools/cli.h"
#include "tools/json_figures.h"
#include "tools/photometric_report.h"
#include "tools/ray_file_far_field.h"

namespace py = pybind11;

namespace gonio::python {
namespace {

// The exception and warning classes, made once at import (kept for the
// interpreter's life: a static py::object would be released after it ends).
PyObject* g_error_type = nullptr;
PyObject* g_warning_type = nullptr;

py::object none_if_empty(const std::string& s) { return s.empty() ? py::object(py::none()) : py::object(py::str(s)); }
py::object none_if_zero(int v) { return v > 0 ? py::object(py::int_(v)) : py::object(py::none()); }

// gonio.GonioError(str(error)) with .message, .file, .line, .column.
[[noreturn]] void raise_error(const Error& e) {
  py::object type = py::reinterpret_borrow<py::object>(g_error_type);
  py::object error = type(to_string(e));
  error.attr("message") = e.message;
  error.attr("file") = none_if_empty(e.where.file);
  error.attr("line") = none_if_zero(e.where.line);
  error.attr("column") = none_if_zero(e.where.column);
  PyErr_SetObject(g_error_type, error.ptr());
  throw py::error_already_set();
}

template <class T>
T take(Result<T> r) {
  if (!r.ok()) raise_error(r.error());
  return std::move(r.value());
}

// A JSON value as plain Python data (objects keep their key order).
template <class Json>
py::object to_python(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return py::none();
    case Json::value_t::boolean: return py::bool_(j.template get<bool>());
    case Json::value_t::number_integer: return py::int_(j.template get<std::int64_t>());
    case Json::value_t::number_unsigned: return py::int_(j.template get<std::uint64_t>());
    case Json::value_t::number_float: return py::float_(j.template get<double>());
    case Json::value_t::string: return py::str(j.template get_ref<const std::string&>());
    case Json::value_t::array: {
      py::list out;
      for (const auto& v : j) out.append(to_python(v));
      return out;
    }
    case Json::value_t::object: {
      py::dict out;
      for (auto it = j.begin(); it != j.end(); ++it) out[py::str(it.key())] = to_python(it.value());
      return out;
    }
    default: return py::none();  // binary and discarded values: never built here
  }
}

// os.fspath(path): str or os.PathLike.
std::string fspath(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

io::LdtIsym3Order isym3_order(const std::string& word) {
  if (word == "standard") return io::LdtIsym3Order::C270_C0_C90;
  if (word == "qlumedit") return io::LdtIsym3Order::C90_C180_C270;
  throw py::value_error("ldt_isym3 must be 'standard' or 'qlumedit', not '" + word + "'");
}

photometry::UgrOptions ugr_options(const std::string& word) {
  const std::optional<photometry::UgrBackground> b = photometry::parse_ugr_background(word);
  if (!b) throw py::value_error("background must be 'cie190' or 'flux-transfer', not '" + word + "'");
  photometry::UgrOptions o;
  o.background = *b;
  return o;
}

// A photometry as Python holds it: the file as read (or simulated) and the
// name its figures and messages carry.
struct Photometry {
  std::shared_ptr<io::PhotometricFile> file;
  std::string name;
  bool simulated = false;  // a simulation's table, not read from a file

  const photometry::Distribution& d() const { return file->distribution; }
  // Arrays are writable views: check before every computation.
  void require_valid() const {
    if (Status s = photometry::validate(d()); !s.ok()) {
      Error e = s.error();
      if (e.where.file.empty()) e.where.file = name;
      raise_error(e);
    }
  }
  photometry::PlanningFigures planning(double floor_reflectance, const photometry::UgrOptions& ugr) const {
    require_valid();
    return photometry::planning_figures(d(), floor_reflectance, ugr);
  }
};

Photometry make_photometry(io::PhotometricFile file, const std::string& path) {
  const bool container = !file.container.empty();
  const std::string name = container ? path + ":" + file.container_entry : path;
  return {std::make_shared<io::PhotometricFile>(std::move(file)), name, false};
}

io::PhotometricReadOptions read_options(const std::string& isym3, const std::string& gldf_photometry) {
  io::PhotometricReadOptions o;
  o.ldt.isym3_order = isym3_order(isym3);
  o.gldf_photometry = gldf_photometry;
  cli::enable_ray_files(o);
  return o;
}

Photometry read(const py::object& path_object, const std::optional<std::string>& photometry,
                const std::string& ldt_isym3) {
  const std::string path = fspath(path_object);
  const io::PhotometricReadOptions options = read_options(ldt_isym3, photometry.value_or(""));
  Result<io::PhotometricFile> file = [&] {
    py::gil_scoped_release unlocked;
    return io::read_photometric_file(path, options);
  }();
  return make_photometry(take(std::move(file)), path);
}

std::vector<Photometry> read_all(const py::object& path_object, const std::string& ldt_isym3) {
  const std::string path = fspath(path_object);
  const io::PhotometricReadOptions options = read_options(ldt_isym3, "");
  Result<std::vector<io::PhotometricFile>> files = [&] {
    py::gil_scoped_release unlocked;
    return io::read_photometric_files(path, options);
  }();
  std::vector<Photometry> out;
  for (io::PhotometricFile& f : take(std::move(files))) out.push_back(make_photometry(std::move(f), path));
  return out;
}

// A view of a vector owned by `owner` (a Python object holding it alive).
template <class T>
py::array_t<T> view(std::vector<T>& v, const py::object& owner, std::vector<py::ssize_t> shape) {
  std::vector<py::ssize_t> strides(shape.size(), static_cast<py::ssize_t>(sizeof(T)));
  for (std::size_t i = shape.size() - 1; i > 0; --i) strides[i - 1] = strides[i] * shape[i];
  return py::array_t<T>(shape, strides, v.data(), owner);
}

py::object lamps_py(const std::vector<photometry::LampSet>& lamps) {
  py::list out;
  for (const photometry::LampSet& l : lamps) out.append(to_python(cli::lamp_json(l)));
  return out;
}

cli::OrderedJson planning_json(const Photometry& p, double floor_reflectance, const std::string& background) {
  cli::OrderedJson j;
  cli::put_planning(j, p.planning(floor_reflectance, ugr_options(background)));
  return j;
}

// One planning figure of info --json: its object, or None with a warning
// that says why it is undefined.
py::object figure(const cli::OrderedJson& j, const std::string& key) {
  if (!j[key].is_null()) return to_python(j[key]);
  const std::string why = j.contains(key + "_why") ? j[key + "_why"].template get<std::string>() : "undefined";
  if (PyErr_WarnEx(g_warning_type, (key + ": " + why).c_str(), 2) != 0) throw py::error_already_set();
  return py::none();
}

double checked_floor(double floor_reflectance) {
  if (!(floor_reflectance >= 0.0 && floor_reflectance <= 0.95))
    throw py::value_error("floor_reflectance must lie in [0, 0.95] (gonio info --cu-floor)");
  return floor_reflectance;
}

std::vector<Finding> write(const Photometry& p, const py::object& path_object, const std::optional<std::string>& version,
                           const std::string& ldt_isym3, const std::string& gldf_photometry) {
  const std::string path = fspath(path_object);
  p.require_valid();
  const std::optional<io::PhotometricFormat> format = io::format_for_path(path);
  if (!format || *format == io::PhotometricFormat::Tm25)
    throw py::value_error("cannot tell the output format from '" + path +
                          "': its extension must be .ies, .ldt, .xml or .gldf");
  io::PhotometricWriteOptions options;
  if (version) {
    if (*format != io::PhotometricFormat::Ies && *format != io::PhotometricFormat::Gldf)
      throw py::value_error("version applies to .ies output only");
    if (*version != "2019" && *version != "2002") throw py::value_error("version must be '2019' or '2002'");
    options.ies.version = *version == "2002" ? io::IesVersion::LM63_2002 : io::IesVersion::LM63_2019;
  }
  options.ldt.isym3_order = isym3_order(ldt_isym3);
  options.ies.file_generation_info = std::string("Written by Gonio ") + kVersion + " (Python) from " +
                                     std::filesystem::path(p.name).filename().string() + " (" +
                                     io::to_string(p.file->format) + ")";
  if (gldf_photometry == "ldt") {
    options.gldf_photometry = io::PhotometricFormat::Ldt;
  } else if (gldf_photometry == "ies") {
    options.gldf_photometry = io::PhotometricFormat::Ies;
  } else if (gldf_photometry == "tm33") {
    options.gldf_photometry = io::PhotometricFormat::Tm33;
  } else {
    throw py::value_error("gldf_photometry must be 'ldt', 'ies' or 'tm33'");
  }
  std::vector<Finding> warnings;
  Status written = [&] {
    py::gil_scoped_release unlocked;
    return io::write_photometric_file(path, p.d(), options, &warnings);
  }();
  take(std::move(written));
  for (Finding& w : warnings)
    if (w.where.file.empty()) w.where.file = path;
  return warnings;
}

py::object compare(const py::object& a_object, const py::object& b_object, double c_step, double gamma_step,
                   bool normalize) {
  const auto photometry_of = [](const py::object& o) {
    if (py::isinstance<Photometry>(o)) return o.cast<Photometry>();
    return read(o, std::nullopt, "standard");
  };
  const Photometry a = photometry_of(a_object), b = photometry_of(b_object);
  const double c_steps = 360.0 / c_step, g_steps = 90.0 / gamma_step;
  if (!(c_step > 0.0 && gamma_step > 0.0) || std::abs(c_steps - std::round(c_steps)) > 1e-9 * c_steps ||
      std::abs(g_steps - std::round(g_steps)) > 1e-9 * g_steps)
    throw py::value_error("c_step must divide 360 and gamma_step 90 into whole steps (e.g. 5 and 2.5)");
  a.require_valid();
  b.require_valid();
  photometry::CompareOptions options;
  options.c_step_deg = c_step;
  options.gamma_step_deg = gamma_step;
  options.normalize_flux = normalize;
  const photometry::Comparison c = take(photometry::compare(a.d(), b.d(), options));
  return to_python(cli::compare_json(a.name, *a.file, b.name, *b.file, c, options));
}

void bind_photometry(py::module_& m) {
  py::class_<Finding>(m, "Finding", "One observation of a reader or check: a stable code, a message, where.")
      .def_property_readonly("severity", [](const Finding& f) { return std::string(to_string(f.severity)); })
      .def_readonly("code", &Finding::code)
      .def_readonly("message", &Finding::message)
      .def_property_readonly("file", [](const Finding& f) { return none_if_empty(f.where.file); })
      .def_property_readonly("line", [](const Finding& f) { return none_if_zero(f.where.line); })
      .def_property_readonly("column", [](const Finding& f) { return none_if_zero(f.where.column); })
      .def("__str__", [](const Finding& f) { return cli::format_finding(f); })
      .def("__repr__", [](const Finding& f) { return "<gonio.Finding " + cli::format_finding(f) + ">"; });

  py::class_<Photometry>(m, "Photometry",
                         "A light distribution read from a file (or simulated), with what follows from it.\n\n"
                         "vertical_deg, horizontal_deg and candela share the object's memory (no copy):\n"
                         "writing into them changes what write() writes and what the figures are computed\n"
                         "from. candela[h, v] is the intensity [cd] at horizontal_deg[h] (C, or H for\n"
                         "Types A and B) and vertical_deg[v] (gamma, or V).")
      .def_readonly("path", &Photometry::name, "the file it was read from (FILE:ENTRY inside a GLDF)")
      .def_property_readonly(
          "format",
          [](const Photometry& p) -> py::object {
            if (p.simulated) return py::none();
            return py::str(io::to_string(p.file->format));
          },
          "the format of the photometry itself: IES, EULUMDAT, TM-33 or TM-25; None for a simulation's table")
      .def_property_readonly(
          "format_label",
          [](const Photometry& p) { return p.simulated ? std::string("simulated") : io::format_label(*p.file); },
          "format and version as messages name them, e.g. 'IES LM-63-2019'; 'simulated' for a simulation's table")
      .def_property_readonly(
          "version",
          [](const Photometry& p) -> py::object {
            if (p.file->ies_version) return py::str(io::to_string(*p.file->ies_version));
            if (p.file->tm33_version) return py::str(io::to_string(*p.file->tm33_version));
            return py::none();
          },
          "the IES LM-63 or TM-33 version the file declared; None for other formats")
      .def_property_readonly("container", [](const Photometry& p) { return none_if_empty(p.file->container); },
                             "the GLDF container it was read from, else None")
      .def_property_readonly("container_entry",
                             [](const Photometry& p) { return none_if_empty(p.file->container_entry); })
      .def_property_readonly("container_id", [](const Photometry& p) { return none_if_empty(p.file->container_id); })
      .def_property_readonly("photometric_type",
                             [](const Photometry& p) { return std::string(photometry::to_string(p.d().type)); })
      .def_property_readonly("symmetry",
                             [](const Photometry& p) { return std::string(photometry::to_string(p.d().symmetry)); })
      .def_property_readonly(
          "vertical_deg",
          [](py::object self) {
            Photometry& p = self.cast<Photometry&>();
            auto& v = p.file->distribution.vertical_deg;
            return view(v, self, {static_cast<py::ssize_t>(v.size())});
          },
          "vertical angles [deg]: gamma (Type C), V (Types A, B); a view, no copy")
      .def_property_readonly(
          "horizontal_deg",
          [](py::object self) {
            Photometry& p = self.cast<Photometry&>();
            auto& h = p.file->distribution.horizontal_deg;
            return view(h, self, {static_cast<py::ssize_t>(h.size())});
          },
          "horizontal angles [deg]: C-planes (Type C), H (Types A, B); a view, no copy")
      .def_property_readonly(
          "candela",
          [](py::object self) {
            Photometry& p = self.cast<Photometry&>();
            photometry::Distribution& d = p.file->distribution;
            return view(d.candela, self,
                        {static_cast<py::ssize_t>(d.horizontal_deg.size()),
                         static_cast<py::ssize_t>(d.vertical_deg.size())});
          },
          "intensities [cd], shape (horizontal angles, vertical angles); a view, no copy")
      .def_property_readonly("absolute", [](const Photometry& p) { return p.d().absolute; },
                             "absolute photometry (candela as measured, no rated lamp flux)")
      .def_property_readonly("lamps", [](const Photometry& p) { return lamps_py(p.d().lamps); },
                             "lamp sets: count, type, flux_lm, color, color_rendering, power_w")
      .def_property_readonly("alternative_lamps", [](const Photometry& p) { return lamps_py(p.d().alternative_lamps); })
      .def_property_readonly("ballast_factor", [](const Photometry& p) { return p.d().ballast_factor; })
      .def_property_readonly("input_watts",
                             [](const Photometry& p) -> py::object {
                               const double w = p.d().input_watts;
                               return std::isfinite(w) ? py::object(py::float_(w)) : py::object(py::none());
                             })
      .def_property_readonly(
          "opening",
          [](const Photometry& p) {
            const photometry::LuminousOpening& o = p.d().opening;
            py::dict out;
            out["shape"] = photometry::to_string(o.shape);
            out["length_m"] = o.length_m;
            out["width_m"] = o.width_m;
            out["height_m"] = o.height_m;
            return out;
          },
          "the luminous opening: shape, length_m (along C0-C180), width_m (C90-C270), height_m")
      .def_property_readonly(
          "luminaire_dimensions",
          [](const Photometry& p) {
            const photometry::LuminaireDimensions& l = p.d().luminaire;
            cli::OrderedJson j = {{"length_m", cli::json_number<cli::OrderedJson>(l.length_m)},
                                  {"width_m", cli::json_number<cli::OrderedJson>(l.width_m)},
                                  {"height_m", cli::json_number<cli::OrderedJson>(l.height_m)}};
            return to_python(j);
          })
      .def_property_readonly(
          "keywords",
          [](const Photometry& p) {
            py::list out;
            for (const photometry::Keyword& k : p.d().keywords) out.append(py::make_tuple(k.key, k.value));
            return out;
          },
          "(KEY, value) pairs in file order: LM-63 keywords, and EULUMDAT's header strings under the same keys")
      .def_property_readonly("findings", [](const Photometry& p) { return p.file->findings; },
                             "what the reader noticed: warnings and notes with file and line")
      .def_property_readonly(
          "ray_set",
          [](const Photometry& p) -> py::object {
            if (!p.file->ray_set) return py::none();
            return to_python(cli::ray_set_json(*p.file->ray_set));
          },
          "of a TM-25 ray file its rays (count, flux, extent, spectrum), else None")
      .def(
          "summary",
          [](const Photometry& p) {
            p.require_valid();
            const photometry::Summary s = photometry::summarize(p.d());
            cli::OrderedJson j;
            j["rated_lamp_flux_lm"] = cli::json_number<cli::OrderedJson>(s.rated_lamp_flux_lm);
            cli::put_summary(j, p.d(), s);
            return to_python(j);
          },
          "Flux, LOR, DFF, zonal flux, peak, beam and field angles, CIE flux code, efficacy:\n"
          "gonio info --json's keys (flux_lm, lor, dff, zones, max_cd, beam, field, ...).")
      .def(
          "ugr_table",
          [](const Photometry& p, const std::string& background) {
            return figure(planning_json(p, 0.2, background), "ugr_table");
          },
          py::arg("background") = "cie190",
          "The UGR catalogue table (CIE 190:2010, CIE 117 tabular method), as gonio info --json's\n"
          "ugr_table; None (with an UndefinedFigureWarning) where it is undefined.")
      .def(
          "cu_table",
          [](const Photometry& p, double floor_reflectance) {
            return figure(planning_json(p, checked_floor(floor_reflectance), "cie190"), "cu_table");
          },
          py::arg("floor_reflectance") = 0.2,
          "Coefficients of utilisation (IES zonal cavity method) as gonio info --json's cu_table;\n"
          "None (with an UndefinedFigureWarning) where undefined.")
      .def(
          "luminance_table",
          [](const Photometry& p) { return figure(planning_json(p, 0.2, "cie190"), "luminance_table"); },
          "Luminance over gamma in C0 and C90 [cd/m2] as gonio info --json's luminance_table;\n"
          "None (with an UndefinedFigureWarning) where undefined (no luminous opening).")
      .def(
          "bug", [](const Photometry& p) { return to_python(planning_json(p, 0.2, "cie190")["bug"]); },
          "The BUG rating (IES TM-15-11 Addendum A): b, u, g, text, zones_lm.")
      .def(
          "spacing_criterion",
          [](const Photometry& p) { return to_python(planning_json(p, 0.2, "cie190")["spacing_criterion"]); },
          "The IES spacing criterion in C0-C180, C90-C270 and diagonal (None with a *_why key where undefined).")
      .def(
          "info",
          [](const Photometry& p, double cu_floor, const std::string& ugr_background) {
            const photometry::PlanningFigures planning = p.planning(checked_floor(cu_floor), ugr_options(ugr_background));
            cli::OrderedJson j = cli::info_json(p.name, *p.file, photometry::summarize(p.d()), planning);
            if (!p.file->container.empty()) j["gldf_photometry_id"] = p.file->container_id;
            return to_python(j);
          },
          py::arg("cu_floor") = 0.2, py::arg("ugr_background") = "cie190",
          "Everything gonio info --json prints for this photometry, as one dict.")
      .def(
          "check",
          [](const Photometry& p) {
            p.require_valid();
            std::vector<Finding> findings = photometry::check(p.d());
            for (Finding& f : findings)
              if (f.where.file.empty()) f.where.file = p.name;
            return findings;
          },
          "The plausibility checks of gonio check (default options): a list of Findings.")
      .def("write", &write, py::arg("path"), py::arg("version") = py::none(), py::kw_only(),
           py::arg("ldt_isym3") = "standard", py::arg("gldf_photometry") = "ldt",
           "Writes the photometry to PATH (.ies, .ldt, .xml for TM-33, .gldf), atomically, as\n"
           "gonio convert does: version '2019' or '2002' for IES. Returns the writer's notes\n"
           "(what was converted or filled in). Raises GonioError where it cannot write.")
      .def("__repr__", [](const Photometry& p) {
        return "<gonio.Photometry " + p.name + " (" + (p.simulated ? std::string("simulated") : io::format_label(*p.file)) + ", Type " +
               photometry::to_string(p.d().type) + ", " + std::to_string(p.d().horizontal_deg.size()) + " x " +
               std::to_string(p.d().vertical_deg.size()) + " angles)>";
      });

  m.def("read", &read, py::arg("path"), py::arg("photometry") = py::none(), py::kw_only(),
        py::arg("ldt_isym3") = "standard",
        "Reads a photometric file of any format Gonio reads (IES LM-63, EULUMDAT, IES TM-33,\n"
        "GLDF, a TM-25 ray file's far field), by extension, else by content. Of a GLDF the\n"
        "photometry with id (or entry 'ldc/NAME') `photometry`, else the first. ldt_isym3:\n"
        "the plane order of EULUMDAT Isym 3 ('standard' or 'qlumedit'). Raises GonioError\n"
        "(file, line) where the file cannot be read.");
  m.def("read_all", &read_all, py::arg("path"), py::kw_only(), py::arg("ldt_isym3") = "standard",
        "Every photometry of a file: one, or each of a GLDF container's.");
  m.def("compare", &compare, py::arg("a"), py::arg("b"), py::kw_only(), py::arg("c_step") = 5.0,
        py::arg("gamma_step") = 2.5, py::arg("normalize") = false,
        "Compares B with the reference A (Photometry objects or paths) on one Type C grid over\n"
        "the sphere, as gonio compare --json: rms_relative and max_relative to A's peak, the\n"
        "flux of each, beam and field angle differences.");
}

}  // namespace
}  // namespace gonio::python

PYBIND11_MODULE(_gonio, m) {
  using namespace gonio::python;
  m.doc() = "Gonio's libraries from Python (import gonio; see help(gonio)).";
  m.attr("__version__") = gonio::kVersion;
  g_error_type = PyErr_NewExceptionWithDoc("gonio.GonioError",
                                           "An input Gonio refuses: .message, and .file, .line, .column where known.",
                                           PyExc_Exception, nullptr);
  g_warning_type = PyErr_NewExceptionWithDoc(
      "gonio.UndefinedFigureWarning", "A planning figure that is undefined for this photometry (the message says why).",
      PyExc_UserWarning, nullptr);
  if (!g_error_type || !g_warning_type) throw py::error_already_set();
  m.attr("GonioError") = py::reinterpret_borrow<py::object>(g_error_type);
  m.attr("UndefinedFigureWarning") = py::reinterpret_borrow<py::object>(g_warning_type);
  bind_photometry(m);
}
