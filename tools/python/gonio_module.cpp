// `import gonio`: the Python module (gonio._gonio, re-exported by
// gonio/__init__.py; stubs in gonio/__init__.pyi). It binds the libraries
// the `gonio` command uses (the application library tools/run and what it
// stands on) and computes nothing of its own: files are read by
// io::read_photometric_file, figures are gonio info --json's objects
// (tools/run/photometric_report.h), simulations run gonio simulate's own
// loop, app::simulate, and write its files (tools/run/simulate.h). The only
// file that includes pybind11.
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

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "design/design_export.h"
#include "design/design_file.h"
#include "io/model/toml_tree.h"
#include "gonio/version.h"
#include "io/model/cad.h"
#include "io/model/cad_model.h"
#include "io/model/parts_file.h"
#include "io/model/toml_tree.h"
#include "io/photometric/photometric_file.h"
#include "io/support/file_io.h"
#include "io/support/process.h"
#include "photometry/compare.h"
#include "photometry/format.h"
#include "photometry/planning.h"
#include "photometry/summary.h"
#include "photometry/validation.h"
#include "sim/distributed.h"
#include "sim/detectors/far_field.h"
#include "sim/ledger.h"
#include "tools/run/console.h"
#include "tools/run/distributed_run.h"
#include "tools/run/json_figures.h"
#include "tools/run/model_input.h"
#include "tools/run/optimize_run.h"
#include "tools/run/photometric_report.h"
#include "tools/run/progressive_run.h"
#include "tools/run/ray_file_far_field.h"
#include "tools/run/resampler_cache.h"
#include "tools/run/simulate.h"
#include "tools/run/simulation_outputs.h"
#include "tools/run/simulation_run.h"
#include "tools/run/tolerance_run.h"

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

// The folder a run writes into: `out` where given, else a fresh scratch
// folder (io::ScratchDir, held in `scratch` and removed with it).
std::string working_folder(const py::object& out, const char* prefix, std::optional<io::ScratchDir>& scratch) {
  if (!out.is_none()) return fspath(out);
  scratch.emplace(prefix);
  if (scratch->path().empty()) throw std::runtime_error("cannot create a scratch folder for the run");
  return scratch->path().string();
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
  app::enable_ray_files(o);
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

// One of a photometry's angle lists as a view kept alive by the Photometry.
template <std::vector<double> photometry::Distribution::*angles>
py::array_t<double> angles_view(const py::object& self) {
  std::vector<double>& a = self.cast<Photometry&>().file->distribution.*angles;
  return view(a, self, {static_cast<py::ssize_t>(a.size())});
}

py::object lamps_py(const std::vector<photometry::LampSet>& lamps) {
  py::list out;
  for (const photometry::LampSet& l : lamps) out.append(to_python(app::lamp_json(l)));
  return out;
}

app::OrderedJson planning_json(const Photometry& p, double floor_reflectance, const std::string& background) {
  app::OrderedJson j;
  app::put_planning(j, p.planning(floor_reflectance, ugr_options(background)));
  return j;
}

// One planning figure of info --json: its object, or None with a warning
// that says why it is undefined.
py::object figure(const app::OrderedJson& j, const std::string& key) {
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
  return to_python(app::compare_json(a.name, *a.file, b.name, *b.file, c, options));
}

void bind_photometry(py::module_& m) {
  py::class_<Finding>(m, "Finding", "One observation of a reader or check: a stable code, a message, where.")
      .def_property_readonly("severity", [](const Finding& f) { return std::string(to_string(f.severity)); })
      .def_readonly("code", &Finding::code)
      .def_readonly("message", &Finding::message)
      .def_property_readonly("file", [](const Finding& f) { return none_if_empty(f.where.file); })
      .def_property_readonly("line", [](const Finding& f) { return none_if_zero(f.where.line); })
      .def_property_readonly("column", [](const Finding& f) { return none_if_zero(f.where.column); })
      .def("__str__", [](const Finding& f) { return app::format_finding(f); })
      .def("__repr__", [](const Finding& f) { return "<gonio.Finding " + app::format_finding(f) + ">"; });

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
      .def_property_readonly("vertical_deg", angles_view<&photometry::Distribution::vertical_deg>,
                             "vertical angles [deg]: gamma (Type C), V (Types A, B); a view, no copy")
      .def_property_readonly("horizontal_deg", angles_view<&photometry::Distribution::horizontal_deg>,
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
            app::OrderedJson j = {{"length_m", app::json_number<app::OrderedJson>(l.length_m)},
                                  {"width_m", app::json_number<app::OrderedJson>(l.width_m)},
                                  {"height_m", app::json_number<app::OrderedJson>(l.height_m)}};
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
            return to_python(app::ray_set_json(*p.file->ray_set));
          },
          "of a TM-25 ray file its rays (count, flux, extent, spectrum), else None")
      .def(
          "summary",
          [](const Photometry& p) {
            p.require_valid();
            const photometry::Summary s = photometry::summarize(p.d());
            app::OrderedJson j;
            j["rated_lamp_flux_lm"] = app::json_number<app::OrderedJson>(s.rated_lamp_flux_lm);
            app::put_summary(j, p.d(), s);
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
            app::OrderedJson j = app::info_json(p.name, *p.file, photometry::summarize(p.d()), planning);
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

// ------------------------------------------------------------ simulate

// The far field of a run: a copy the result owns (the simulation, its scene
// and its BVH are released when simulate() returns).
struct FarField {
  std::shared_ptr<const sim::FarField> field;
};

// A read-only view of `data` shaped (6, N, N) (cube face, row y, column x),
// kept alive by `owner`.
template <class T>
py::array_t<T> cube_view(const T* data, int n, const py::object& owner) {
  const py::ssize_t s = static_cast<py::ssize_t>(sizeof(T)), nn = n;
  py::array_t<T> a({py::ssize_t{6}, nn, nn}, {s * nn * nn, s * nn, s}, data, owner);
  a.attr("flags").attr("writeable") = false;
  return a;
}

// gonio.Design: a design file held in memory (design/design_file.h); its
// variables set by name, written back, exported as STEP, and simulated as it
// stands without writing a file (gonio.simulate: app::ModelInputOptions::design).
struct PyDesign {
  std::shared_ptr<design::Design> d;
};

PyDesign load_design(const py::object& path_object) {
  const std::string path = fspath(path_object);
  if (!design::is_design_path(path))
    raise_error(make_error(path, "not a design file: its name must end with .design.toml"));
  return {std::make_shared<design::Design>(take(design::read_design_file(path)))};
}

py::dict design_variables(const PyDesign& self) {
  py::dict out;
  for (const design::Variable& v : self.d->variables) out[py::str(v.name)] = v.value;
  return out;
}

py::dict design_bounds(const PyDesign& self) {
  py::dict out;
  for (const design::Variable& v : self.d->variables)
    out[py::str(v.name)] = py::make_tuple(v.min ? py::object(py::float_(*v.min)) : py::object(py::none()),
                                          v.max ? py::object(py::float_(*v.max)) : py::object(py::none()));
  return out;
}

void design_set(PyDesign& self, const std::string& name, double value) {
  if (Status s = design::set_variable(*self.d, name, value); !s.ok()) raise_error(s.error());
}

void design_write(const PyDesign& self, const py::object& path_object) {
  const std::string path = fspath(path_object);
  if (Status s = io::write_file_atomic(path, design::write_design(self.d->document)); !s.ok()) raise_error(s.error());
}

py::dict design_export_step(const PyDesign& self, const py::object& path_object, double tolerance_mm) {
  const std::string path = fspath(path_object);
  if (!(tolerance_mm > 0.0)) throw py::value_error("tolerance_mm must be > 0");
  Result<design::StepExportInfo> info = [&] {
    py::gil_scoped_release unlocked;
    return design::write_design_step(*self.d, path, tolerance_mm);
  }();
  const design::StepExportInfo i = take(std::move(info));
  py::dict out;
  out["step"] = path;
  out["sidecar"] = i.sidecar;
  out["parts"] = i.parts;
  out["max_deviation_mm"] = i.max_deviation_mm;
  return out;
}

struct Iteration {
  app::IterationReport report;
};

struct SimulationResult {
  std::string model;
  FarField far_field;
  Photometry photometry;
  sim::Ledger ledger;
  double estimated_rms_error_pct = 0.0;
  std::string stopped_by;
  int iterations_done = 0;
  std::uint64_t photons = 0;
  double trace_s = 0.0;
  std::string symmetry_reason;
  std::vector<Finding> model_findings;
  std::vector<std::string> files;
  py::object report = py::none();
  int exit_code = 0;
};

py::dict ledger_line(const sim::LedgerLine& l) {
  py::dict d;
  d["photons"] = l.photons;
  d["flux_lm"] = l.flux_lm;
  return d;
}

py::dict ledger_py(const sim::Ledger& l) {
  py::dict d;
  for (const auto& [key, line] : {std::pair{"emitted", &l.emitted}, {"escaped", &l.escaped},
                                  {"absorbed", &l.absorbed}, {"cutoff", &l.cutoff}})
    d[key] = ledger_line(*line);
  d["photons_close"] = l.photons_close();
  d["flux_imbalance_lm"] = l.flux_imbalance_lm();
  py::list emitters, meshes, materials;
  for (const sim::EmitterLedger& e : l.emitters) {
    py::dict x;
    x["name"] = e.name;
    for (const auto& [key, line] : {std::pair{"emitted", &e.emitted}, {"escaped", &e.escaped},
                                    {"absorbed", &e.absorbed}, {"cutoff", &e.cutoff}})
      x[key] = ledger_line(*line);
    emitters.append(x);
  }
  for (const sim::MeshLedger& m : l.meshes) {
    py::dict x;
    x["name"] = m.name;
    x["material"] = m.material;
    x["placements"] = m.placements;
    x["hits"] = m.hits;
    x["absorbed"] = ledger_line(m.absorbed);
    x["cutoff"] = ledger_line(m.cutoff);
    meshes.append(x);
  }
  for (const sim::MaterialLedger& m : l.materials) {
    py::dict x;
    x["name"] = m.name;
    x["hits"] = m.hits;
    x["absorbed"] = ledger_line(m.absorbed);
    x["cutoff"] = ledger_line(m.cutoff);
    materials.append(x);
  }
  d["emitters"] = emitters;
  d["meshes"] = meshes;
  d["materials"] = materials;
  return d;
}

// What a Python caller's callbacks left: an exception to raise once the run
// has stopped (KeyboardInterrupt from Ctrl-C, or the callback's own).
struct PythonStop {
  std::optional<py::error_already_set> error;
  // Runs Python's signal handlers (Ctrl-C raises KeyboardInterrupt there);
  // true where one raised. Needs the GIL.
  bool signalled() {
    if (PyErr_CheckSignals() == 0) return false;
    error.emplace();
    return true;
  }
};

// The checks and plan of gonio simulate (app::plan_simulation, the
// command's own); a bad argument is a ValueError naming the option as the
// command spells it ("--photons must be between 1 and 4294967295, got 0").
app::SimulatePlan plan_run(const std::string& model, std::uint64_t photons, int iterations, std::uint64_t seed,
                           const std::string& sampler, int threads, const std::string& out, double target_error,
                           double c_step, double gamma_step, const std::string& symmetry, const std::string& formats,
                           const std::string& ies_version, const std::optional<std::string>& name, int max_bounces,
                           bool cache) {
  // Beyond the signed range: negative, so out of the option's bounds too.
  const auto signed_value = [](std::uint64_t v) {
    return v > static_cast<std::uint64_t>(std::numeric_limits<long long>::max()) ? -1LL : static_cast<long long>(v);
  };
  app::SimulateOptions o;
  o.out_dir = out;
  o.photons = signed_value(photons);
  o.iterations = iterations;
  o.seed = signed_value(seed);
  o.sampler = sampler;
  o.threads = threads;
  o.max_bounces = max_bounces;
  o.target_error_pct = target_error;
  o.c_step = c_step;
  o.gamma_step = gamma_step;
  o.symmetry_name = symmetry;
  o.format_list = formats;
  o.ies_version = ies_version;
  o.stem = name.value_or(std::string());
  if (name && name->empty()) throw py::value_error("name: '' is not a plain file name");
  o.no_cache = !cache;
  Result<app::SimulatePlan> plan = app::plan_simulation(model, o);
  if (!plan.ok()) throw py::value_error(plan.error().message);
  return std::move(plan.value());
}

// gonio.Model: a luminaire built in memory (meshes from numpy arrays, the
// CAD sidecar's materials and emitters as dicts), traced by gonio.simulate
// without a file: each mesh becomes a part of an io::CadModel placed once
// (lengths in `length_unit`, as the sidecar's), the dicts a sidecar tree
// read by the sidecar's own reader (io::parse_parts_tree), and the CAD
// loader's scene builder (io::cad_scene) makes the scene, as for a design
// file (app::ModelInputOptions::build_scene).
struct PyModel {
  std::string name = "model";
  std::string length_unit = "mm";
  io::CadModel cad;
  std::vector<std::string> part_materials;   // one per part
  std::vector<std::pair<std::string, py::object>> materials;  // name, dict
  std::vector<py::object> emitters;          // dicts
  py::object frame = py::none();             // {"up": …, "c0": …} or None
};

// Plain Python data (dict, list, tuple, str, bool, int, float, numpy
// arrays and scalars) as a TOML node; `what` names it in errors.
io::TomlNode toml_from_python(const py::handle& v, const std::string& what) {
  io::TomlNode n;
  if (py::isinstance<py::bool_>(v)) {
    n.type = io::TomlNode::Type::Boolean;
    n.boolean = v.cast<bool>();
  } else if (py::isinstance<py::int_>(v)) {
    n.type = io::TomlNode::Type::Integer;
    n.integer = v.cast<std::int64_t>();
  } else if (py::isinstance<py::float_>(v) || py::hasattr(v, "dtype")) {
    if (py::hasattr(v, "tolist") && !py::isinstance<py::float_>(v)) return toml_from_python(v.attr("tolist")(), what);
    n.type = io::TomlNode::Type::Float;
    n.floating = v.cast<double>();
  } else if (py::isinstance<py::str>(v)) {
    n.type = io::TomlNode::Type::String;
    n.string = v.cast<std::string>();
  } else if (py::isinstance<py::dict>(v)) {
    n.type = io::TomlNode::Type::Table;
    for (const auto& [key, value] : v.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key)) throw py::type_error(what + ": keys must be strings");
      const std::string k = key.cast<std::string>();
      n.table.push_back({k, toml_from_python(value, what + "['" + k + "']")});
    }
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    n.type = io::TomlNode::Type::Array;
    std::size_t i = 0;
    for (const auto& item : v) n.array.push_back(toml_from_python(item, what + "[" + std::to_string(i++) + "]"));
  } else {
    throw py::type_error(what + ": " + py::str(py::type::of(v).attr("__name__")).cast<std::string>() +
                         " is not a value the sidecar takes (dict, list, str, bool, int, float)");
  }
  return n;
}

io::TomlNode toml_key(const std::string& text) {
  io::TomlNode n;
  n.type = io::TomlNode::Type::String;
  n.string = text;
  return n;
}

// A float64 array of shape (rows, columns), finite; errors name `what`.
py::array_t<double> float_rows(const py::object& a, std::size_t columns, const std::string& what) {
  py::array_t<double, py::array::c_style | py::array::forcecast> out;
  try {
    out = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  } catch (const py::error_already_set&) {
  }
  if (!out || out.ndim() != 2 || static_cast<std::size_t>(out.shape(1)) != columns || out.shape(0) == 0)
    throw py::value_error(what + ": an array of shape (N, " + std::to_string(columns) + ") of numbers is needed" +
                          (out ? ", not " + py::str(py::tuple(py::cast(std::vector<py::ssize_t>(out.shape(), out.shape() + out.ndim())))).cast<std::string>() : std::string()));
  const double* d = out.data();
  for (py::ssize_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(d[i]))
      throw py::value_error(what + ": row " + std::to_string(i / static_cast<py::ssize_t>(columns)) +
                            " holds a value that is not finite (" + format_number(d[i]) + ")");
  return out;
}

void model_add_mesh(PyModel& self, const std::string& name, const py::object& vertices, const py::object& triangles,
                    const py::object& normals, const std::string& material) {
  if (name.empty()) throw py::value_error("name: a mesh needs a name");
  for (const io::CadPart& p : self.cad.parts)
    if (p.name == name) throw py::value_error("name: a mesh named '" + name + "' is there already");
  if (material.empty()) throw py::value_error("material: name the mesh's material (Model.material)");
  const py::array_t<double> v = float_rows(vertices, 3, "vertices");
  const std::size_t n = static_cast<std::size_t>(v.shape(0));
  // Triangles: integers, indices into the vertices.
  py::array t_any = py::array::ensure(triangles);
  if (!t_any || t_any.ndim() != 2 || t_any.shape(1) != 3 || t_any.shape(0) == 0)
    throw py::value_error("triangles: an array of shape (M, 3) of vertex indices is needed");
  if (!py::dtype::of<std::int64_t>().attr("kind").equal(t_any.dtype().attr("kind")) &&
      !py::str(t_any.dtype().attr("kind")).equal(py::str("u")))
    throw py::value_error("triangles: vertex indices must be integers, not " +
                          py::str(t_any.dtype()).cast<std::string>());
  const auto t = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(t_any);
  io::CadSurface surface;
  const double unit = io::length_unit_m(self.length_unit).value_or(1e-3);
  surface.positions.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    surface.positions.push_back({static_cast<float>(v.at(i, 0) * unit), static_cast<float>(v.at(i, 1) * unit),
                                 static_cast<float>(v.at(i, 2) * unit)});
  for (py::ssize_t i = 0; i < t.shape(0); ++i)
    for (py::ssize_t k = 0; k < 3; ++k) {
      const std::int64_t index = t.at(i, k);
      if (index < 0 || static_cast<std::size_t>(index) >= n)
        throw py::value_error("triangles: row " + std::to_string(i) + " names vertex " + std::to_string(index) +
                              ", outside 0 … " + std::to_string(n - 1));
      surface.indices.push_back(static_cast<std::uint32_t>(index));
    }
  if (!normals.is_none()) {
    const py::array_t<double> nn = float_rows(normals, 3, "normals");
    if (static_cast<std::size_t>(nn.shape(0)) != n)
      throw py::value_error("normals: one per vertex is needed (" + std::to_string(n) + "), not " +
                            std::to_string(nn.shape(0)));
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 d{nn.at(i, 0), nn.at(i, 1), nn.at(i, 2)};
      if (!(length(d) > 0.0)) throw py::value_error("normals: row " + std::to_string(i) + " is zero");
      const Vec3 u = normalize(d);
      surface.normals.push_back({static_cast<float>(u.x), static_cast<float>(u.y), static_cast<float>(u.z)});
    }
  }
  io::CadPart part;
  part.name = name;
  part.surfaces.push_back(std::move(surface));
  io::CadPlacement placement;
  placement.part = static_cast<std::uint32_t>(self.cad.parts.size());
  placement.path = name;
  self.cad.parts.push_back(std::move(part));
  self.cad.placements.push_back(std::move(placement));
  self.part_materials.push_back(material);
}

// The scene of a model as it stands (a copy of its data: later changes to
// the Python object do not reach a run under way).
std::function<Result<sim::SceneDesc>(std::vector<Finding>*)> model_builder(const PyModel& self) {
  if (self.cad.parts.empty()) throw py::value_error("model: add a mesh first (Model.add_mesh)");
  if (self.emitters.empty()) throw py::value_error("model: add an emitter first (Model.add_emitter)");
  io::TomlNode root;
  root.type = io::TomlNode::Type::Table;
  root.table.push_back({"length_unit", toml_key(self.length_unit)});
  if (!self.frame.is_none()) root.table.push_back({"frame", toml_from_python(self.frame, "frame")});
  io::TomlNode materials;
  for (const auto& [name, keys] : self.materials)
    materials.table.push_back({name, toml_from_python(keys, "material '" + name + "'")});
  root.table.push_back({"materials", std::move(materials)});
  io::TomlNode emitters;
  emitters.type = io::TomlNode::Type::Array;
  for (std::size_t i = 0; i < self.emitters.size(); ++i)
    emitters.array.push_back(toml_from_python(self.emitters[i], "emitter " + std::to_string(i)));
  root.table.push_back({"emitters", std::move(emitters)});
  Result<io::PartsFile> parts =
      io::parse_parts_tree(root, self.name, {"length_unit", "frame", "materials", "emitters"}, "the model");
  if (!parts.ok()) raise_error(parts.error());
  for (std::size_t i = 0; i < self.cad.parts.size(); ++i) {
    if (!parts->material(self.part_materials[i]))
      throw py::value_error("material: mesh '" + self.cad.parts[i].name + "' names material '" +
                            self.part_materials[i] + "', which the model does not define (Model.material)");
    io::PartsRule rule;
    rule.match = self.cad.parts[i].name;
    rule.material = self.part_materials[i];
    parts->rules.push_back(std::move(rule));
  }
  auto cad = std::make_shared<const io::CadModel>(self.cad);
  auto sidecar = std::make_shared<const io::PartsFile>(std::move(*parts));
  const std::string name = self.name;
  return [cad, sidecar, name](std::vector<Finding>* findings) -> Result<sim::SceneDesc> {
    io::CadLoadOptions options;
    options.allow_outside_paths = true;  // the profiles a script names, wherever they are
    return io::cad_scene(*cad, *sidecar, name, options, findings);
  };
}

void bind_model(py::module_& m) {
  py::class_<PyModel>(m, "Model",
                      "A luminaire built in memory: meshes from numpy arrays, materials and emitters as dicts\n"
                      "with the CAD sidecar's keys (docs/cad.md), traced by gonio.simulate(model) without\n"
                      "writing a file. Frame: the sidecar's (zenith +Z, C0 +X unless `frame` says otherwise).")
      .def(py::init([](const std::string& length_unit, const py::object& frame, const std::string& name) {
             if (!io::length_unit_m(length_unit))
               throw py::value_error("length_unit: '" + length_unit + "' is not a length unit (mm, cm, m, inch, …)");
             if (name.empty()) throw py::value_error("name: the model needs a name (it names the outputs)");
             PyModel model;
             model.length_unit = length_unit;
             model.frame = frame;
             model.name = name;
             model.cad.format = "Gonio model (in memory)";
             model.cad.file_unit = "m";
             model.cad.file_unit_m = 1.0;
             return model;
           }),
           py::kw_only(), py::arg("length_unit") = "mm", py::arg("frame") = py::none(), py::arg("name") = "model",
           "length_unit: of the vertices and the emitters' positions (the sidecar's units); frame: {'up': "
           "[x, y, z], 'c0': [x, y, z]} as the sidecar's [frame]; name: the model's, which names the outputs.")
      .def("material", [](PyModel& self, const std::string& name, const py::dict& keys) {
             for (auto& [n, k] : self.materials)
               if (n == name) {
                 k = keys;
                 return;
               }
             self.materials.emplace_back(name, keys);
           },
           py::arg("name"), py::arg("keys"),
           "Defines (or replaces) a material: `keys` as a sidecar's [materials.NAME] table, e.g.\n"
           "{'mirror': 0.95} or {'preset': 'aluminium-anodised'}; read when the model is simulated.")
      .def("add_mesh", &model_add_mesh, py::arg("name"), py::arg("vertices"), py::arg("triangles"), py::kw_only(),
           py::arg("normals") = py::none(), py::arg("material"),
           "Adds a mesh: vertices (N, 3) in length_unit, triangles (M, 3) vertex indices counter-clockwise\n"
           "from the front, normals (N, 3) optional (shading normals; else the faces'). A wrong shape, a value\n"
           "that is not finite or an index out of range raises ValueError naming the argument.")
      .def("add_emitter", [](PyModel& self, const py::dict& emitter) { self.emitters.push_back(emitter); },
           py::arg("emitter"),
           "Adds an emitter: a dict as a sidecar's [[emitters]] table (name, position, nadir, c0, profile,\n"
           "ray_file, flux_lm, spectrum); paths relative to the working folder.")
      .def_property_readonly("name", [](const PyModel& self) { return self.name; })
      .def_property_readonly("meshes", [](const PyModel& self) {
        py::list out;
        for (const io::CadPart& p : self.cad.parts) out.append(p.name);
        return out;
      }, "the meshes' names, in the order they were added");
}

SimulationResult simulate(const py::object& model_object, std::uint64_t photons, int iterations, std::uint64_t seed,
                          const std::string& sampler, int threads, const py::object& out_object,
                          const py::object& on_iteration, double target_error, double c_step, double gamma_step,
                          const std::string& symmetry, const std::string& formats, const std::string& ies_version,
                          const std::optional<std::string>& name, int max_bounces, bool cache) {
  const auto start = std::chrono::steady_clock::now();
  // A gonio.Design is simulated as it stands now (a copy: setting its
  // variables during the run changes nothing), named by its file.
  std::shared_ptr<const design::Design> in_memory;
  if (py::isinstance<PyDesign>(model_object))
    in_memory = std::make_shared<const design::Design>(*model_object.cast<const PyDesign&>().d);
  std::function<Result<sim::SceneDesc>(std::vector<Finding>*)> builder;
  std::string built_name;
  if (py::isinstance<PyModel>(model_object)) {
    builder = model_builder(model_object.cast<const PyModel&>());
    built_name = model_object.cast<const PyModel&>().name;
  }
  const std::string model = in_memory ? in_memory->path : builder ? built_name : fspath(model_object);
  const std::string out = out_object.is_none() ? std::string() : fspath(out_object);
  app::SimulatePlan plan = plan_run(model, photons, iterations, seed, sampler, threads, out, target_error, c_step,
                                    gamma_step, symmetry, formats, ies_version, name, max_bounces, cache);
  plan.model_input.design = in_memory;
  plan.model_input.build_scene = builder;
  sim::Ranks ranks;  // this process alone
  plan.progressive.simulation.ranks = &ranks;

  // gonio simulate's own loop (app::simulate), followed from Python: after
  // each iteration (its callback, Ctrl-C) and between slices of an iteration
  // (Ctrl-C only). A callback returning False keeps what was traced (and
  // writes it where `out` is given); Ctrl-C or the callback's exception
  // writes nothing and is raised once the run has stopped.
  PythonStop stop;
  app::SimulateHooks hooks;
  hooks.on_message = [](Severity, const std::string&) {};  // the findings are the result's; the error is raised
  std::optional<Error> failure;
  hooks.on_failed = [&failure](const Error& e) { failure = e; };
  // The resampler of the output grid, for the estimate after each iteration.
  std::shared_ptr<const sim::Resampler> resampler;
  hooks.on_loaded = [&](const sim::SceneDesc& scene, const std::vector<Finding>&) -> const sim::Resampler* {
    resampler = app::shared_resampler(plan.progressive.simulation.face_size, scene.frame, plan.grid,
                                      plan.model_input.cache_dir);
    return resampler.get();
  };
  hooks.on_iteration = [&](const app::IterationReport& r, const sim::Simulation&) {
    py::gil_scoped_acquire locked;
    if (stop.signalled()) return false;
    if (on_iteration.is_none()) return true;
    try {
      const py::object go_on = on_iteration(Iteration{r});
      return go_on.is_none() || go_on.cast<bool>();
    } catch (py::error_already_set& e) {
      stop.error.emplace(std::move(e));
      return false;
    }
  };
  hooks.cancel = [&] {
    py::gil_scoped_acquire locked;
    return stop.signalled();
  };
  hooks.keep_when_stopped = [&] { return !stop.error; };
  std::optional<app::SimulateResult> ran = [&] {
    py::gil_scoped_release unlocked;
    return app::simulate(plan, hooks, start);
  }();
  // Ctrl-C or the callback's exception: raised here, nothing written.
  if (stop.error) throw std::move(*stop.error);
  if (!ran) {
    if (failure) raise_error(*failure);
    raise_error(make_error(model, "the simulation failed; nothing was simulated"));
  }

  SimulationResult result;
  result.model = model;
  result.model_findings = ran->findings;
  const app::ProgressiveOutcome& run = ran->run;
  const sim::Simulation& simulation = run.simulation;
  const sim::SimulationStats st = simulation.stats();
  result.ledger = simulation.ledger();
  result.estimated_rms_error_pct = run.estimated_rms_error_pct;
  result.stopped_by = app::to_string(run.stopped_by);
  result.iterations_done = run.iterations_done;
  result.photons = st.photons;
  result.trace_s = st.trace_s;

  // The far field, made once for the table and the result.
  auto far_field = std::make_shared<const sim::FarField>(simulation.far_field());
  // The candela table the IES and LDT files hold (tools/run/simulation_outputs.h):
  // the one written with `out` where the files held one (a grey run: the
  // files' table of a spectral run also carries its colour), else made here.
  Result<app::SimulatedTable> table = [&]() -> Result<app::SimulatedTable> {
    if (ran->files && !ran->files->outputs.symmetry_reason.empty() && !simulation.tracer().spectral() &&
        plan.model == model) {
      app::SimulatedTable written;
      written.distribution = std::move(ran->files->outputs.distribution);
      written.symmetry = ran->files->outputs.symmetry;
      written.symmetry_reason = ran->files->outputs.symmetry_reason;
      written.decision = ran->files->outputs.decision;
      return written;
    }
    py::gil_scoped_release unlocked;
    const app::OutputRequest request =
        app::table_request(simulation, model, plan.grid, plan.symmetry, plan.model_input.cache_dir);
    return app::simulated_table(*far_field, simulation.scene(), result.ledger, request);
  }();
  app::SimulatedTable t = take(std::move(table));
  io::PhotometricFile file;
  file.distribution = std::move(t.distribution);
  result.symmetry_reason = t.symmetry_reason;
  result.photometry = {std::make_shared<io::PhotometricFile>(std::move(file)), model + " (simulated)", true};
  result.far_field.field = std::move(far_field);
  if (ran->files) result.exit_code = ran->files->passed() ? app::kExitOk : app::kExitFailure;
  if (!out.empty()) {
    const std::filesystem::path report = std::filesystem::path(out) / "report.json";
    if (std::filesystem::exists(report)) {
      const Result<std::string> text = io::read_file(report.string(), std::size_t{1} << 28);
      const nlohmann::json j = text.ok() ? nlohmann::json::parse(*text, nullptr, false) : nlohmann::json();
      result.report = to_python(j);
      if (j.contains("written"))
        for (const auto& f : j["written"]) result.files.push_back(f.get<std::string>());
    }
  }
  return result;
}


// A Python value as a TOML node (merit=): dict a table, list or tuple an
// array, bool, int, float, str; anything else a TypeError naming the key.
io::TomlNode toml_of(const py::handle& value, const std::string& key) {
  io::TomlNode n;
  if (py::isinstance<py::dict>(value)) {
    n.type = io::TomlNode::Type::Table;
    for (const auto& [k, v] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k)) throw py::type_error("merit: the keys of " + key + " must be strings");
      const std::string name = k.cast<std::string>();
      n.table.push_back({name, toml_of(v, key.empty() ? name : key + "." + name)});
    }
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    n.type = io::TomlNode::Type::Array;
    for (const py::handle& v : value) n.array.push_back(toml_of(v, key));
  } else if (py::isinstance<py::bool_>(value)) {
    n.type = io::TomlNode::Type::Boolean;
    n.boolean = value.cast<bool>();
  } else if (py::isinstance<py::int_>(value)) {
    n.type = io::TomlNode::Type::Integer;
    n.integer = value.cast<std::int64_t>();
  } else if (py::isinstance<py::float_>(value)) {
    n.type = io::TomlNode::Type::Float;
    n.floating = value.cast<double>();
  } else if (py::isinstance<py::str>(value)) {
    n.type = io::TomlNode::Type::String;
    n.string = value.cast<std::string>();
  } else {
    throw py::type_error("merit: " + (key.empty() ? std::string("the table") : "'" + key + "'") +
                         " must be a dict, list, bool, int, float or str, not " +
                         std::string(py::str(py::type::of(value).attr("__name__"))));
  }
  return n;
}

// merit=: None, or a dict of the [merit] table's keys.
std::optional<io::TomlNode> merit_table(const py::object& merit) {
  if (merit.is_none()) return std::nullopt;
  if (!py::isinstance<py::dict>(merit)) throw py::type_error("merit must be a dict of the [merit] table's keys");
  return toml_of(merit, "");
}

// gonio optimize's own run (app::optimize_design). Without `out` it works in
// a temporary folder, removed afterwards. `callback(evaluation)` after each
// evaluation (a dict as history.json's rows); False stops, keeping the best.
py::dict optimize(const py::object& design_object, const py::object& target_object, const py::object& out_object,
                  const std::string& method, long long max_evals, long long stages, long long seed, int threads,
                  const std::optional<double>& photons_per_bin, bool smooth, double gamma_step,
                  long long final_photons, double max_time, const std::optional<std::string>& name,
                  const py::object& callback, const py::object& merit, long long jobs, long long population,
                  bool common_random, const std::optional<bool>& step) {
  const auto start = std::chrono::steady_clock::now();
  namespace fs = std::filesystem;
  app::OptimizeRunOptions o;
  o.design_path = py::isinstance<PyDesign>(design_object) ? design_object.cast<const PyDesign&>().d->path
                                                          : fspath(design_object);
  o.target_path = target_object.is_none() ? std::string() : fspath(target_object);
  const std::optional<design::OptimizeMethod> m = design::parse_optimize_method(method);
  if (!m) throw py::value_error("method must be 'bobyqa', 'cobyla', 'neldermead' or 'cmaes', not '" + method + "'");
  o.method = *m;
  if (max_evals < 1) throw py::value_error("max_evals must be at least 1");
  if (stages < 1 || stages > 8) throw py::value_error("stages must be between 1 and 8");
  if (photons_per_bin && !(*photons_per_bin >= 40.0 && *photons_per_bin <= 1e6))
    throw py::value_error("photons_per_bin must be between 40 and 1000000");
  if (!(gamma_step >= 0.1 && gamma_step <= 90.0)) throw py::value_error("gamma_step must be between 0.1 and 90");
  if (final_photons < 1) throw py::value_error("final_photons must be at least 1");
  if (seed < 0) throw py::value_error("seed must be at least 0");
  // The command's bounds (tools/cli/cmd_optimize.cpp).
  if (jobs < 0 || jobs > 4096) throw py::value_error("jobs must be between 0 and 4096");
  if (population < 0 || population > 100000) throw py::value_error("population must be between 0 and 100000");
  if (!(max_time >= 0.0 && max_time <= 1e7)) throw py::value_error("max_time must be between 0 and 1e7 seconds");
  if (threads < 0 || threads > 4096) throw py::value_error("threads must be between 0 and 4096");
  if (step.value_or(false) && out_object.is_none())
    throw py::value_error("step=True writes NAME.step into out: give out");
  o.jobs = jobs;
  o.population = population;
  o.no_common_random = !common_random;
  o.max_evals = max_evals;
  o.stages = stages;
  o.seed = seed;
  o.threads = threads;
  o.photons_per_bin = photons_per_bin;
  o.no_smooth = !smooth;
  o.gamma_step = gamma_step;
  o.final_photons = final_photons;
  o.max_time = max_time;
  o.name = name.value_or(std::string());
  o.merit = merit_table(merit);
  // No STEP export into a folder removed on return; with out, as step says
  // (default: written, as the command does).
  o.no_step = out_object.is_none() || !step.value_or(true);
  // The working folder: `out`, or a fresh temporary one, removed after.
  std::optional<io::ScratchDir> scratch;
  o.out_dir = working_folder(out_object, "gonio-optimize", scratch);

  std::optional<py::error_already_set> raised;
  app::OptimizeRunHooks hooks;
  std::vector<design::OptimizeVariable> variables;
  hooks.on_start = [&](const std::vector<design::OptimizeVariable>& v, const design::MeritSpec&, std::size_t,
                       std::uint64_t) { variables = v; };
  hooks.on_evaluation = [&](const design::EvaluationRecord& r) {
    if (PyErr_CheckSignals() != 0) {
      raised.emplace();
      return false;
    }
    if (callback.is_none()) return true;
    try {
      const py::object go_on = callback(to_python(app::evaluation_json(r, variables)));
      return go_on.is_none() || go_on.cast<bool>();
    } catch (py::error_already_set& e) {
      raised.emplace(std::move(e));
      return false;
    }
  };
  bool usage = false;
  Result<app::OptimizeRunOutcome> outcome = app::optimize_design(o, hooks, start, &usage);
  if (raised) throw std::move(*raised);
  if (!outcome.ok()) {
    if (usage) throw py::value_error(outcome.error().message);
    raise_error(outcome.error());
  }
  py::dict best;
  for (std::size_t i = 0; i < outcome->variables.size(); ++i)
    best[py::str(outcome->variables[i].name)] = outcome->run.best_values[i];
  std::vector<double> merits;
  for (const design::EvaluationRecord& r : outcome->run.history)
    if (r.stage >= 0) merits.push_back(r.merit);
  py::dict result;
  result["variables"] = best;
  result["merit_history"] = py::array_t<double>(static_cast<py::ssize_t>(merits.size()), merits.data());
  result["history"] = to_python(outcome->history);
  result["optimize"] = to_python(outcome->report["optimize"]);
  result["final"] = to_python(outcome->report["optimize"]["final"]);
  result["report"] = to_python(outcome->report);
  // A run that cannot improve (the command's exit 3) returns, as the command
  // writes every file: its kind ("flat", "pinned", "no_improvement") and
  // reason here; a run that failed raises GonioError instead.
  result["improvable"] = outcome->cannot_improve.empty();
  result["cannot_improve"] =
      outcome->cannot_improve.empty() ? py::object(py::none()) : py::object(py::str(outcome->cannot_improve));
  result["cannot_improve_kind"] = outcome->cannot_improve_kind.empty()
                                      ? py::object(py::none())
                                      : py::object(py::str(outcome->cannot_improve_kind));
  py::list files;
  if (!scratch) {  // files in a scratch folder are gone on return
    files.append(outcome->best_path);
    files.append(outcome->history_path);
    files.append(outcome->result->files->report_path);
    for (const auto& f : outcome->report.value("written", nlohmann::json::array())) files.append(f.get<std::string>());
  }
  result["files"] = files;
  return result;
}


// gonio tolerance's own run (app::tolerance_analysis). Without `out` it
// works in a temporary folder, removed afterwards.
py::dict tolerance(const py::object& model_object, const py::object& tolerances_object, long long trials,
                   const std::optional<std::string>& spec, long long seed, long long noise_seeds,
                   long long sampling_seed, long long bins, long long photons, int threads, int max_bounces,
                   double c_step, double gamma_step, const py::object& out_object, long long inverse_steps,
                   long long parallel_trials, const std::optional<std::string>& percentile,
                   const std::optional<std::string>& luminance_image) {
  namespace fs = std::filesystem;
  if (trials < 0 || trials > 100000) throw py::value_error("trials must be between 0 and 100000");
  if (inverse_steps < 0 || inverse_steps > 50) throw py::value_error("inverse_steps must be between 0 and 50");
  if (parallel_trials < 1 || parallel_trials > 256) throw py::value_error("parallel_trials must be between 1 and 256");
  if (noise_seeds < 0 || noise_seeds > 1000) throw py::value_error("noise_seeds must be between 0 and 1000");
  if (bins < 1 || bins > 1000) throw py::value_error("bins must be between 1 and 1000");
  if (seed < 0 || sampling_seed < 0) throw py::value_error("seed and sampling_seed must be at least 0");
  app::ToleranceRunOptions o;
  o.model = py::isinstance<PyDesign>(model_object) ? model_object.cast<const PyDesign&>().d->path
                                                   : fspath(model_object);
  // None: the design file's own [tolerances].
  o.tolerances_path = tolerances_object.is_none() ? std::string() : fspath(tolerances_object);
  o.inverse_steps = inverse_steps;
  o.parallel_trials = parallel_trials;
  o.spec_text = spec.value_or(std::string());
  o.percentile_text = percentile.value_or(std::string());
  o.trials = trials;
  o.noise_seeds = noise_seeds;
  o.sampling_seed = sampling_seed;
  o.bins = bins;
  app::SimulateOptions& so = o.simulate;
  so.iterations = 1;
  so.symmetry_name = "none";
  so.photons = photons;
  so.seed = seed;
  so.threads = threads;
  so.max_bounces = max_bounces;
  so.c_step = c_step;
  so.gamma_step = gamma_step;
  so.luminance_images = luminance_image;  // --luminance-image: CIE 232's dugr and ugr_cie232 per trace
  std::optional<io::ScratchDir> scratch;
  o.out_dir = working_folder(out_object, "gonio-tolerance", scratch);
  Result<app::SimulatePlan> plan = app::plan_simulation(o.model, so);
  if (!plan.ok()) throw py::value_error(plan.error().message);
  app::ToleranceRunHooks hooks;
  hooks.on_message = [](Severity, const std::string&) {};  // the error is raised
  bool usage = false;
  Result<app::ToleranceRunOutcome> outcome = [&] {
    py::gil_scoped_release unlocked;
    return app::tolerance_analysis(o, *plan, hooks, &usage);
  }();
  if (!outcome.ok()) {
    if (usage) throw py::value_error(outcome.error().message);
    raise_error(outcome.error());
  }
  const nlohmann::json& report = outcome->report;
  // Per figure (and per tolerance) the Monte Carlo trials as arrays.
  py::dict figures, values;
  const nlohmann::json& mc = report["monte_carlo"]["trials"];
  for (const auto& [key, unused] : report["nominal"].items()) {
    std::vector<double> v;
    for (const auto& t : mc) v.push_back(t["figures"][key].is_null() ? std::nan("") : t["figures"][key].get<double>());
    figures[py::str(key)] = py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
  }
  for (const auto& tol : report["tolerances"]) {
    const std::string name = tol["name"].get<std::string>();
    std::vector<double> v;
    for (const auto& t : mc) v.push_back(t["values"][name].get<double>());
    values[py::str(name)] = py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
  }
  py::list sensitivity;
  for (const auto& [key, figure] : report["sensitivity"].items())
    for (const auto& row : figure["rows"]) {
      py::dict r = to_python(row);
      r["figure"] = key;
      r["unit"] = to_python(figure["unit"]);
      sensitivity.append(r);
    }
  py::dict result;
  result["trials"] = figures;
  result["values"] = values;
  result["sensitivity"] = sensitivity;
  result["noise_floor"] = to_python(report["noise"]["floor"]);
  result["nominal"] = to_python(report["nominal"]);
  result["yield"] = to_python(report["monte_carlo"]["yield"]);
  result["inverse_sensitivity"] = to_python(report["inverse_sensitivity"]);
  result["percentile_trials"] = to_python(report["monte_carlo"]["percentile_trials"]);
  result["table"] = outcome->table;
  result["report"] = to_python(report);
  result["timing"] = to_python(outcome->timing);
  return result;
}


// gonio.Merit: the merit gonio optimize minimises, as a function of the
// variables' values for scipy and the like: every call is the command's own
// evaluation (app::optimize_design with `evaluate`), traced with the same
// seed (common random numbers), in a temporary folder kept for its life.
struct PyMerit {
  app::OptimizeRunOptions options;
  std::vector<design::OptimizeVariable> variables;
  std::uint64_t photons = 0;
  std::string folder;
  ~PyMerit() {
    std::error_code ignored;
    if (!folder.empty()) std::filesystem::remove_all(folder, ignored);
  }

  std::vector<design::MeritValue> evaluate(std::vector<std::vector<double>> points) {
    app::OptimizeRunOptions o = options;
    o.evaluate_only = true;
    o.evaluate = std::move(points);
    o.evaluate_photons = photons;
    app::OptimizeRunHooks hooks;
    bool usage = false;
    Result<app::OptimizeRunOutcome> outcome = [&] {
      py::gil_scoped_release unlocked;
      return app::optimize_design(o, hooks, std::chrono::steady_clock::now(), &usage);
    }();
    if (!outcome.ok()) {
      if (usage) throw py::value_error(outcome.error().message);
      raise_error(outcome.error());
    }
    variables = outcome->variables;
    photons = outcome->evaluate_photons;
    return outcome->merits;
  }
  // Values as a sequence in the design's order, or {name: value}.
  std::vector<double> values_of(const py::object& values) const {
    std::vector<double> out;
    if (py::isinstance<py::dict>(values)) {
      const py::dict d = values.cast<py::dict>();
      for (const design::OptimizeVariable& v : variables) {
        if (!d.contains(v.name)) throw py::value_error("no value for the variable '" + v.name + "'");
        out.push_back(d[py::str(v.name)].cast<double>());
      }
      if (d.size() != variables.size()) throw py::value_error("a value for a variable the design does not have");
      return out;
    }
    for (const py::handle& h : values) out.push_back(h.cast<double>());
    return out;
  }
};

std::unique_ptr<PyMerit> make_merit(const py::object& design_object, const py::object& target_object,
                                    const std::optional<double>& photons_per_bin, bool smooth,
                                    std::optional<std::uint64_t> photons, long long seed, int threads,
                                    double gamma_step, const py::object& merit) {
  auto m = std::make_unique<PyMerit>();
  app::OptimizeRunOptions& o = m->options;
  o.design_path = py::isinstance<PyDesign>(design_object) ? design_object.cast<const PyDesign&>().d->path
                                                          : fspath(design_object);
  o.target_path = target_object.is_none() ? std::string() : fspath(target_object);
  if (photons_per_bin && !(*photons_per_bin >= 40.0 && *photons_per_bin <= 1e6))
    throw py::value_error("photons_per_bin must be between 40 and 1000000");
  if (photons && *photons == 0) throw py::value_error("photons must be at least 1");
  if (seed < 0) throw py::value_error("seed must be at least 0");
  if (!(gamma_step >= 0.1 && gamma_step <= 90.0)) throw py::value_error("gamma_step must be between 0.1 and 90");
  o.photons_per_bin = photons_per_bin;
  o.no_smooth = !smooth;
  o.seed = seed;
  o.threads = threads;
  o.gamma_step = gamma_step;
  o.merit = merit_table(merit);
  m->photons = photons.value_or(0);
  m->folder = py::str(py::module_::import("tempfile").attr("mkdtemp")("", "gonio-merit-"));
  o.out_dir = m->folder;
  m->evaluate({});  // reads and checks the design, its variables and the target
  return m;
}

void bind_design(py::module_& m) {
  py::class_<PyDesign>(m, "Design",
                       "A design file (NAME.design.toml, docs/design.md) held in memory: its named variables\n"
                       "set by name, written back, exported as STEP, and simulated as it stands by\n"
                       "gonio.simulate(design) without writing a file.")
      .def(py::init(&load_design), py::arg("path"), "Reads a design file; a mistake raises GonioError naming its line.")
      .def_property_readonly("path", [](const PyDesign& self) { return self.d->path; }, "the file it was read from")
      .def_property_readonly("variables", &design_variables, "{name: value} of its variables, in the file's order")
      .def_property_readonly("bounds", &design_bounds, "{name: (min, max)} of its variables (None: unbounded)")
      .def("set", &design_set, py::arg("name"), py::arg("value"),
           "Sets a variable; one unknown, outside its bounds or not finite raises GonioError.")
      .def("write", &design_write, py::arg("path"), "Writes the design file with the variables' current values.")
      .def("export_step", &design_export_step, py::arg("path"), py::kw_only(),
           py::arg("tolerance_mm") = design::kStepToleranceMm,
           "Writes its parts as STEP (B-spline surfaces of revolution within tolerance_mm of the exact\n"
           "profiles, named parts) and the sidecar beside it, as gonio design export does; returns\n"
           "{step, sidecar, parts, max_deviation_mm}.")
      .def("__repr__", [](const PyDesign& self) {
        return "<gonio.Design " + self.d->path + ": " + std::to_string(self.d->variables.size()) + " variables>";
      });
}


void bind_simulation(py::module_& m) {
  py::class_<FarField>(m, "FarField",
                       "The simulated far field: a direction cube map, faces +X -X +Y -Y +Z -Z of the model's\n"
                       "world axes (OpenEXR's order; sim/detectors/cube_map.h), arrays of shape (6, N, N) indexed\n"
                       "[face, y, x], read-only views of the result (no copy).")
      .def_property_readonly("face_size", [](const FarField& f) { return f.field->face_size(); })
      .def_property_readonly("total_flux_lm", [](const FarField& f) { return f.field->total_flux_lm(); })
      .def_property_readonly(
          "flux_lm",
          [](py::object self) {
            const FarField& f = self.cast<const FarField&>();
            return cube_view(f.field->flux_lm().data(), f.field->face_size(), self);
          },
          "flux per texel [lm]")
      .def_property_readonly(
          "photons",
          [](py::object self) {
            const FarField& f = self.cast<const FarField&>();
            return cube_view(f.field->photons().data(), f.field->face_size(), self);
          },
          "photons counted per texel")
      .def_property_readonly(
          "solid_angle_sr",
          [](const FarField& f) {
            const int n = f.field->face_size();
            py::array_t<double> a({6, n, n});
            double* p = a.mutable_data();
            for (std::size_t t = 0; t < f.field->texel_count(); ++t) p[t] = f.field->grid().texel_solid_angle(t);
            return a;
          },
          "each texel's exact solid angle [sr] (a new array)")
      .def_property_readonly(
          "intensity_cd",
          [](const FarField& f) {
            const int n = f.field->face_size();
            py::array_t<double> a({6, n, n});
            double* p = a.mutable_data();
            for (std::size_t t = 0; t < f.field->texel_count(); ++t) p[t] = f.field->intensity_cd(t);
            return a;
          },
          "mean intensity over each texel [cd]: flux / solid angle (a new array)");

  py::class_<Iteration>(m, "Iteration", "What on_iteration receives after each iteration.")
      .def_property_readonly("iteration", [](const Iteration& i) { return i.report.progress.iteration; })
      .def_property_readonly("iterations", [](const Iteration& i) { return i.report.progress.iterations; })
      .def_property_readonly("photons_done", [](const Iteration& i) { return i.report.progress.photons_done; })
      .def_property_readonly("photons_total", [](const Iteration& i) { return i.report.progress.photons_total; })
      .def_property_readonly("elapsed_s", [](const Iteration& i) { return i.report.progress.elapsed_s; })
      .def_property_readonly("photons_per_s", [](const Iteration& i) { return i.report.progress.photons_per_s; })
      .def_property_readonly("remaining_s", [](const Iteration& i) { return i.report.progress.remaining_s; })
      .def_property_readonly("estimated_rms_error_pct",
                             [](const Iteration& i) { return i.report.estimated_rms_error_pct; })
      .def("__repr__", [](const Iteration& i) {
        return "<gonio.Iteration " + std::to_string(i.report.progress.iteration) + "/" +
               std::to_string(i.report.progress.iterations) + ", " + std::to_string(i.report.progress.photons_done) +
               " photons, estimated error " + format_number(i.report.estimated_rms_error_pct, 4) + " %>";
      });

  py::class_<SimulationResult>(m, "SimulationResult", "What gonio.simulate returns.")
      .def_readonly("model", &SimulationResult::model)
      .def_readonly("far_field", &SimulationResult::far_field, "the cube map (FarField)")
      .def_readonly("photometry", &SimulationResult::photometry,
                    "the C-gamma candela table the IES and LDT files hold (a Photometry)")
      .def_property_readonly("ledger", [](const SimulationResult& r) { return ledger_py(r.ledger); },
                             "the energy ledger: emitted, escaped, absorbed, cutoff (photons, flux_lm), per emitter, "
                             "mesh and material")
      .def_readonly("estimated_rms_error_pct", &SimulationResult::estimated_rms_error_pct,
                    "the run's estimated RMS candela error [% of the peak] (tools/run/progressive_run.h)")
      .def_readonly("stopped_by", &SimulationResult::stopped_by, "'iterations', 'target-error' or 'cancelled'")
      .def_readonly("iterations_done", &SimulationResult::iterations_done)
      .def_readonly("photons", &SimulationResult::photons)
      .def_readonly("trace_s", &SimulationResult::trace_s, "wall time tracing [s]")
      .def_readonly("symmetry_reason", &SimulationResult::symmetry_reason)
      .def_readonly("model_findings", &SimulationResult::model_findings, "warnings of the model's loader and checks")
      .def_readonly("files", &SimulationResult::files, "the files written into `out` (report.json's 'written')")
      .def_readonly("report", &SimulationResult::report, "report.json as a dict when `out` was given, else None")
      .def_readonly("exit_code", &SimulationResult::exit_code,
                    "gonio simulate's exit code for the files: 0, or 1 where an energy check failed")
      .def("__repr__", [](const SimulationResult& r) {
        return "<gonio.SimulationResult " + r.model + ": " + std::to_string(r.photons) + " photons in " +
               std::to_string(r.iterations_done) + " iterations, stopped by " + r.stopped_by + ">";
      });

  m.def("optimize", &optimize, py::arg("design"), py::arg("target") = py::none(), py::kw_only(),
        py::arg("out") = py::none(), py::arg("method") = "bobyqa", py::arg("max_evals") = 200,
        py::arg("stages") = 3, py::arg("seed") = 1, py::arg("threads") = 0, py::arg("photons_per_bin") = py::none(),
        py::arg("smooth") = true, py::arg("gamma_step") = 1.0, py::arg("final_photons") = 1'000'000,
        py::arg("max_time") = 0.0, py::arg("name") = py::none(), py::arg("callback") = py::none(),
        py::arg("merit") = py::none(), py::arg("jobs") = 0, py::arg("population") = 0,
        py::arg("common_random") = true, py::arg("step") = py::none(),
        "Optimises a design file's variables toward a target as gonio optimize does (the same run;\n"
        "docs/commands/optimize.md): returns {variables: the best {name: value}, merit_history:\n"
        "the stages' merits (numpy), history: every evaluation as history.json, optimize: report.json's\n"
        "optimize section, final: its final trace's figures, report, files}. Without out it works in a\n"
        "temporary folder. callback(evaluation) after each evaluation; False stops, keeping the best.\n"
        "merit: a dict of the [merit] table's keys (docs/design.md), replacing the design's table.\n"
        "jobs, population (cmaes), common_random=False (--no-common-random), step=False (--no-step;\n"
        "default: NAME.step with out) and max_time as the command's options.\n"
        "A run that cannot improve the design (the command's exit 3) returns, every file written:\n"
        "improvable False, cannot_improve (the reason) and cannot_improve_kind ('flat', 'pinned',\n"
        "'no_improvement'; None where it improved).\n"
        "Raises GonioError naming the file; bad arguments raise ValueError.");
  m.def("tolerance", &tolerance, py::arg("model"), py::arg("tolerances"), py::kw_only(), py::arg("trials") = 20,
        py::arg("spec") = py::none(), py::arg("seed") = 1, py::arg("noise_seeds") = 3, py::arg("sampling_seed") = 1,
        py::arg("bins") = 10, py::arg("photons") = 1'000'000, py::arg("threads") = 0, py::arg("max_bounces") = 100,
        py::arg("c_step") = 5.0, py::arg("gamma_step") = 2.5, py::arg("out") = py::none(),
        py::arg("inverse_steps") = 4, py::arg("parallel_trials") = 1, py::arg("percentile") = py::none(),
        py::arg("luminance_image") = py::none(),
        "How robust a luminaire is, as gonio tolerance does (the same run; docs/tolerance.md): returns\n"
        "{trials: {figure: numpy array over the Monte Carlo trials}, values: {tolerance: array of its\n"
        "drawn values}, sensitivity: [{figure, unit, tolerance, low, high, change_low, change_high,\n"
        "below_noise}], noise_floor: {figure: value}, nominal, yield, inverse_sensitivity, table, report,\n"
        "timing}. Figures include ugr, bug_b/u/g, cct, duv_max (NaN where undefined), axis_c0/c90.\n"
        "tolerances None: a design file's own [tolerances]. spec: 'beam_c0=24..28,ugr<=19'.\n"
        "inverse_steps: bisection steps of the traced inverse sensitivity; parallel_trials: trials at once.\n"
        "percentile: '5,95,beam_c0:50', the trials at those percentiles (nearest rank), written to out as\n"
        "pP_FIGURE.ies/.ldt and listed in percentile_trials.\n"
        "luminance_image: 'ugr' or 'C:G,...' as gonio tolerance --luminance-image: every trace's CIE 232\n"
        "figures dugr (largest delta UGR over the views) and ugr_cie232; NaN without it.\n"
        "Without out it works in a temporary folder.\n"
        "Raises GonioError naming the file; bad arguments raise ValueError.");
  py::class_<PyMerit>(m, "Merit",
                      "The merit gonio optimize minimises (docs/design.md \"Optimisation\") as a function of a\n"
                      "design's variables, for scipy.optimize and the like: merit(values) traces the design at\n"
                      "those values with the same photons every call (common random numbers: a deterministic\n"
                      "function), as the command's own evaluation does.")
      .def(py::init(&make_merit), py::arg("design"), py::arg("target") = py::none(), py::kw_only(),
           py::arg("photons_per_bin") = py::none(), py::arg("smooth") = true, py::arg("photons") = py::none(),
           py::arg("seed") = 1, py::arg("threads") = 0, py::arg("gamma_step") = 1.0, py::arg("merit") = py::none(),
           "Reads the design (its variables with bounds, its [merit] table) and the target (default: the\n"
           "table's); photons per call default to the first stage's (photons_per_bin × the merit's nodes);\n"
           "seed, threads and gamma_step (the tessellation's) as gonio optimize's options; merit: a dict\n"
           "of the [merit] table's keys, replacing the design's table.\n"
           "Raises GonioError naming the file.")
      .def(
          "__call__",
          [](PyMerit& self, const py::object& values) {
            return self.evaluate({self.values_of(values)}).front().merit;
          },
          py::arg("values"), "The merit at values (a sequence in the design's order, or {name: value}).")
      .def(
          "terms",
          [](PyMerit& self, const py::object& values) {
            const design::MeritValue v = self.evaluate({self.values_of(values)}).front();
            py::dict d;
            d["merit"] = v.merit;
            d["candela_rms_pct"] = v.candela_rms_pct;
            d["lor"] = v.lor;
            d["beam_angle_deg"] = v.beam_deg;
            d["target_beam_angle_deg"] = v.target_beam_deg;
            d["field_angle_deg"] = v.field_deg;
            d["target_field_angle_deg"] = v.target_field_deg;
            d["max_cd_above"] = v.max_cd_above;
            d["ugr"] = v.ugr;
            d["target_ugr"] = v.target_ugr;
            d["penalty"] = v.penalty;
            py::list limits;
            for (const design::MeritLimitValue& l : v.limits) {
              py::dict one;
              one["name"] = l.name;
              one["value"] = l.value;
              one["limit"] = l.limit;
              one["c"] = l.c;
              one["within"] = l.c <= 0.0;
              limits.append(one);
            }
            d["limits"] = limits;
            return d;
          },
          py::arg("values"),
          "The merit and its terms at values: merit, candela_rms_pct, lor, beam and field angles,\n"
          "max_cd_above, ugr, penalty and limits [{name, value, limit, c, within}] (c ≤ 0 within).")
      .def(
          "limits",
          [](PyMerit& self, const py::object& values) {
            const design::MeritValue v = self.evaluate({self.values_of(values)}).front();
            std::vector<double> c;
            for (const design::MeritLimitValue& l : v.limits) c.push_back(l.c);
            return py::array_t<double>(static_cast<py::ssize_t>(c.size()), c.data());
          },
          py::arg("values"),
          "The [merit] table's hard limits at values: c = (figure − limit) / limit for each (≤ 0 within),\n"
          "as numpy, in the order terms()['limits'] lists them; for scipy's constraints use -c ≥ 0.")
      .def_property_readonly(
          "names", [](const PyMerit& self) {
            py::list l;
            for (const auto& v : self.variables) l.append(v.name);
            return l;
          }, "the variables' names, in the design's order")
      .def_property_readonly(
          "x0", [](const PyMerit& self) {
            std::vector<double> x;
            for (const auto& v : self.variables) x.push_back(v.value);
            return py::array_t<double>(static_cast<py::ssize_t>(x.size()), x.data());
          }, "the variables' values in the design")
      .def_property_readonly(
          "bounds", [](const PyMerit& self) {
            py::list l;
            for (const auto& v : self.variables) l.append(py::make_tuple(v.min, v.max));
            return l;
          }, "[(min, max)] of the variables (scipy's bounds)")
      .def_readonly("photons", &PyMerit::photons, "photons of each call's trace")
      .def_property_readonly("seed", [](const PyMerit& self) { return self.options.seed; }, "the seed of every call");
  m.def("simulate", &simulate, py::arg("model"), py::kw_only(), py::arg("photons") = 1'000'000,
        py::arg("iterations") = 10, py::arg("seed") = 1, py::arg("sampler") = "sobol", py::arg("threads") = 0,
        py::arg("out") = py::none(), py::arg("on_iteration") = py::none(), py::arg("target_error") = 0.0,
        py::arg("c_step") = 5.0, py::arg("gamma_step") = 2.5, py::arg("symmetry") = "auto",
        py::arg("formats") = "all", py::arg("ies_version") = "2019", py::arg("name") = py::none(),
        py::arg("max_bounces") = 100, py::arg("cache") = true,
        "Traces a luminaire model (glTF 2.0, STEP, a design file, or a gonio.Design or gonio.Model in memory) as\n"
        "gonio simulate does: `photons` per iteration,\n"
        "`iterations` at most, stopping early at `target_error` percent (estimated RMS candela\n"
        "error) where given. With `out`, writes gonio simulate's files there (the same bytes as\n"
        "the command with the same options). on_iteration(Iteration) is called after each\n"
        "iteration; returning False stops the run (stopped_by 'cancelled'; the result holds\n"
        "what was traced). The GIL is released while tracing; Ctrl-C (KeyboardInterrupt)\n"
        "stops it within a slice of 16384 photons, writes nothing and raises.");
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
  bind_design(m);
  bind_model(m);
  bind_simulation(m);
}
