// noether._noether's functions for the commands (docs/python.md): the plugins and the output's
// series, compare, fit, stokes, observe and view, each as `noether <command>` computes it.
#include "bindings.hpp"
#include "registry.hpp"

#include <noether/body_stokes.hpp>
#include <noether/compare.hpp>
#include <noether/conjunction.hpp>
#include <noether/error.hpp>
#include <noether/fit.hpp>
#include <noether/observations.hpp>
#include <noether/output_schema.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/view.hpp>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

namespace py = pybind11;
using noether::python::registry;

namespace {

// The output file's series (noether/output_schema.hpp), as dicts, in the scene's units.
py::list output_series_dicts() {
  py::list out;
  for (const auto& s : noether::output_series()) {
    py::dict d;
    d["name"] = s.name;
    d["path"] = s.path;
    d["shape"] = s.shape;
    d["unit"] = s.unit;
    d["description"] = s.description;
    d["integer"] = s.integer;
    d["rigid_only"] = s.rigid_only;
    d["optional"] = s.optional;
    d["checkpointed"] = s.checkpointed;
    d["needs"] = s.needs;
    out.append(d);
  }
  return out;
}

py::list plugin_dicts() {
  std::vector<std::string> failures;
  const auto found = registry().load_all(failures);
  py::list out;
  for (const auto& p : found) {
    py::dict d;
    d["name"] = p.name;
    d["kind"] = std::string(noether::to_string(p.kind));
    d["description"] = p.description;
    d["file"] = p.file.string();
    py::list params;
    for (const auto& q : p.params) {
      py::dict e;
      e["name"] = q.name;
      e["type"] = q.type;
      e["default"] = q.default_value ? py::object(py::str(q.default_value)) : py::object(py::none());
      e["description"] = q.description;
      params.append(e);
    }
    d["params"] = params;
    out.append(d);
  }
  for (const auto& f : failures) PyErr_WarnEx(PyExc_RuntimeWarning, f.c_str(), 1);
  return out;
}

py::dict compare_dict(const std::string& text, const std::string& name, const std::vector<std::string>& overrides,
                      const std::vector<std::string>& runs, const std::vector<std::string>& models,
                      const std::string& reference_model, const std::string& spec_file, int repeats,
                      double max_wall_seconds) {
  const noether::Scene scene = noether::parse_scene(text, name, overrides);
  const noether::CompareSpec spec =
      noether::make_compare_spec(scene, runs, models, reference_model, spec_file, repeats, max_wall_seconds);
  noether::CompareResult result;
  {
    py::gil_scoped_release release;
    result = noether::compare(scene, registry(), spec);
  }
  py::dict out;
  out["reference"] = result.reference;
  out["reference_error"] = result.reference_error;
  out["reference_error_note"] = result.reference_error_note;
  out["reference_seconds"] = result.reference_seconds;
  out["text"] = noether::format_compare(result);
  py::list rows;
  for (const auto& r : result.rows) {
    py::dict d;
    d["family"] = r.family;
    d["label"] = r.label;
    d["ok"] = r.ok;
    d["error"] = r.error;
    for (const std::string& column : noether::compare_columns()) d[column.c_str()] = r.value(column);
    rows.append(d);
  }
  out["rows"] = rows;
  return out;
}

}  // namespace

void noether::python::bind_commands(py::module_& m) {
  m.def("plugins", &plugin_dicts, "every plugin found: name, kind, description, parameters");
  m.def("output_series", &output_series_dicts, "every series of an output file: name, path, shape, unit, description");
  m.def("compare", &compare_dict);
  m.def("compare_columns", [] {
    py::list out;
    for (const std::string& c : noether::compare_columns()) out.append(c);
    return out;
  }, "the numeric columns of a comparison, in order");
  // noether.fit (docs/fitting.md): the fit as its JSON text (the package parses it).
  m.def("fit", [](const std::string& scene, const std::string& observations, const std::vector<std::string>& free,
                  const std::vector<std::string>& overrides, int max_iterations, double tolerance) {
    noether::FitOptions options;
    options.free = free;
    options.max_iterations = max_iterations;
    options.tolerance = tolerance;
    noether::FitResult result;
    {
      py::gil_scoped_release release;  // runs of the scene: other Python threads may go on
      result = noether::fit(scene, overrides, observations, options, registry());
    }
    return noether::fit_json(result);
  });
  // noether.stokes (docs/gravity-fields.md): a body's Stokes coefficients, as noether shape stokes.
  m.def("stokes", [](const std::string& scene, const std::string& body, int degree, double radius, bool normalized,
                     const std::vector<std::string>& overrides) {
    const noether::BodyStokes s = noether::body_stokes(noether::load_scene(scene, overrides), body, degree, radius, normalized);
    const noether::StokesCoefficients& cs = s.coefficients;
    const auto size = static_cast<py::ssize_t>(cs.degree + 1);
    py::array_t<double> C({size, size}), S({size, size});
    auto c = C.mutable_unchecked<2>();
    auto sn = S.mutable_unchecked<2>();
    for (int n = 0; n <= cs.degree; ++n)
      for (int m = 0; m <= cs.degree; ++m) {
        c(n, m) = m <= n ? cs.c(n, m) : 0.0;
        sn(n, m) = m <= n ? cs.s(n, m) : 0.0;
      }
    py::dict out;
    out["C"] = C;
    out["S"] = S;
    out["degree"] = cs.degree;
    out["mass"] = cs.mass;
    out["gm"] = s.gm;
    out["reference_radius"] = cs.reference_radius;
    out["normalized"] = cs.normalized;
    out["polar_moment"] = s.polar_moment;
    out["source"] = s.source;
    return out;
  });
  // noether.observe (docs/fitting.md): an observable of a run's file at its frames or at given times.
  m.def("observe", [](const std::filesystem::path& run, const std::string& spec, std::optional<std::vector<double>> times,
                      const std::vector<double>& line_of_sight, const std::vector<double>& sunlight, int tessellation) {
    noether::Observation o;
    o.observable = noether::observable_from_spec(spec, noether::read_trajectory_names(run), line_of_sight, sunlight);
    const noether::Trajectory trajectory =
        noether::read_trajectory(run, noether::TrajectoryShapes{o.observable.is_lightcurve(), tessellation});
    std::vector<double> t;
    if (times) {
      t = *times;
    } else if (o.observable.is_event_time()) {  // every event in the run
      for (const auto& c : noether::conjunctions(trajectory, o.observable.target, o.observable.center,
                                                 o.observable.line_of_sight))
        t.push_back(c.t);
    } else {  // every frame; an impulse's two frames once (the value after it)
      for (double tk : trajectory.times())
        if (t.empty() || tk != t.back()) t.push_back(tk);
    }
    std::vector<double> values;
    for (double tk : t) {
      o.t = tk;
      values.push_back(noether::observe(trajectory, o).value);
    }
    return py::make_tuple(py::array_t<double>(static_cast<py::ssize_t>(t.size()), t.data()),
                          py::array_t<double>(static_cast<py::ssize_t>(values.size()), values.data()));
  });
  // noether.view (docs/visualisation.md, "In Python and Jupyter"): the page `noether view` writes.
  m.def("view_html", [](const std::vector<std::filesystem::path>& runs, std::size_t max_frames, const std::string& title,
                        const std::string& params, const std::vector<std::size_t>& samples) {
    noether::ViewOptions options;
    options.max_frames = max_frames;
    options.title = title;
    options.params = params;
    options.samples = samples;
    noether::ViewReport report;
    std::string html = noether::view_html(runs, options, &report);
    return py::make_tuple(py::bytes(html), report.frames_in_file, report.frames_shown, report.notes);
  });
}
