// noether._noether._Simulation: the Simulation as Python sees it (docs/python.md) — the C++
// one, with the state's derived views, Ctrl-C honoured while it integrates.
#include "bindings.hpp"
#include "python_potential.hpp"
#include "registry.hpp"
#include "state_arrays.hpp"

#include <noether/diagnostics.hpp>
#include <noether/error.hpp>
#include <noether/force_jacobian.hpp>
#include <noether/particles.hpp>
#include <noether/scene.hpp>
#include <noether/simulation.hpp>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <memory>
#include <sstream>

namespace py = pybind11;
using noether::State;
using noether::python::registry;
using noether::python::rows;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// An (n, 3) array into the columns of a 3×n matrix, checked.
void set_rows(Eigen::Matrix3Xd& m, const py::handle& value, const char* what) {
  auto a = Array::ensure(value);
  if (!a || a.ndim() != 2 || a.shape(0) != m.cols() || a.shape(1) != 3) {
    std::ostringstream msg;
    msg << what << ": expected an array of shape (" << m.cols() << ", 3)";
    throw noether::Error(msg.str());
  }
  auto v = a.unchecked<2>();
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (int k = 0; k < 3; ++k) m(k, i) = v(i, k);
}

// Ctrl-C while C++ integrates (the GIL released): every 16 steps the stepping loop calls
// RunOptions::progress; at most every 50 ms that takes the GIL and asks Python whether a signal
// is pending (PyErr_CheckSignals, which raises KeyboardInterrupt). If so the loop stops after
// the step, as `noether run` does on SIGINT, and integrate() raises it.
struct SignalWatch {
  volatile std::sig_atomic_t stop = 0;
  bool raised = false;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  void poll() {
    const auto now = std::chrono::steady_clock::now();
    if (stop || now - last < std::chrono::milliseconds(50)) return;
    last = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      raised = true;
      stop = SIGINT;
    }
  }
};

// RunOptions with `watch` wired in.
noether::RunOptions watched_options(const std::shared_ptr<SignalWatch>& watch) {
  noether::RunOptions options;
  options.interrupt = &watch->stop;
  options.progress = [w = watch.get()](double, double, double) { w->poll(); };
  return options;
}

// The Simulation as Python sees it: the C++ one, with the state's derived views.
class PySimulation {
 public:
  PySimulation(std::unique_ptr<noether::Simulation> sim, std::shared_ptr<SignalWatch> watch)
      : sim_(std::move(sim)), watch_(std::move(watch)) {}

  static PySimulation from_text(const std::string& text, const std::string& name,
                                const std::vector<std::string>& overrides, const std::optional<std::string>& output,
                                bool force, py::object potential, int threads) {
    return make(noether::parse_scene(text, name, overrides), output, force, std::move(potential), threads);
  }
  static PySimulation from_file(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                                const std::optional<std::string>& output, bool force, py::object potential,
                                int threads) {
    return make(noether::load_scene(file, overrides), output, force, std::move(potential), threads);
  }
  static PySimulation load(const std::filesystem::path& file, const std::optional<std::string>& output, bool force,
                           py::object potential, int threads) {
    auto watch = std::make_shared<SignalWatch>();
    return PySimulation(noether::Simulation::load(file, registry(), run_options(watch, output, force, threads),
                                                  python_potential(potential)),
                        watch);
  }

  static PySimulation resume(const std::filesystem::path& file, double t_end, int threads) {
    auto watch = std::make_shared<SignalWatch>();
    return PySimulation(noether::Simulation::resume(file, registry(), run_options(watch, std::nullopt, false, threads),
                                                    t_end),
                        watch);
  }

  py::dict integrate(double t) {
    noether::StopInfo stop;
    watch_->stop = 0;
    watch_->raised = false;
    {
      py::gil_scoped_release release;  // a Python potential takes it back for each evaluation
      stop = sim_->integrate(t);
    }
    if (watch_->raised) throw py::error_already_set();  // KeyboardInterrupt, the state kept
    py::dict out;
    out["t"] = sim_->time();
    out["stopped"] = !stop.reason.empty();
    out["reason"] = stop.reason;
    out["event"] = stop.event;
    return out;
  }

  double time() const { return sim_->time(); }
  const noether::System& system() const { return sim_->scene().system; }

  py::array_t<double> positions() const { return rows(sim_->state().x); }
  py::array_t<double> momenta() const { return rows(sim_->state().p); }
  py::array_t<double> velocities() const { return noether::python::velocities(system(), sim_->state()); }
  py::array_t<double> angular_momenta() const { return rows(sim_->state().Pi); }
  py::array_t<double> angular_velocities() const {  // Ω_k = J_k⁻¹ Π_k, body frame
    return noether::python::angular_velocities(system(), sim_->state());
  }
  py::array_t<double> attitudes() const { return noether::python::attitudes(sim_->state()); }
  py::array_t<double> quaternions() const {
    const State& s = sim_->state();
    py::array_t<double> out({static_cast<py::ssize_t>(s.R.size()), py::ssize_t{4}});
    auto v = out.mutable_unchecked<2>();
    for (std::size_t k = 0; k < s.R.size(); ++k) {
      const noether::Vec4 q = noether::quaternion_from_rotation(s.R[k]);
      for (int a = 0; a < 4; ++a) v(static_cast<py::ssize_t>(k), a) = q[a];
    }
    return out;
  }

  // Sets any of the state's parts (the others keep their values), checked by the core.
  void set_state(py::kwargs parts) {
    State s = sim_->state();
    s.tangent.resize(0, 0);  // a new segment: its state-transition matrix starts at the identity
    const noether::System& sys = system();
    for (auto item : parts) {
      const std::string key = item.first.cast<std::string>();
      const py::handle value = item.second;
      if (key == "t") {
        s.t = value.cast<double>();
      } else if (key == "positions") {
        set_rows(s.x, value, "positions");
      } else if (key == "momenta") {
        set_rows(s.p, value, "momenta");
      } else if (key == "velocities") {
        set_rows(s.p, value, "velocities");
        for (Eigen::Index i = 0; i < s.p.cols(); ++i) s.p.col(i) *= sys.body(static_cast<std::size_t>(i)).mass;
      } else if (key == "angular_momenta") {
        set_rows(s.Pi, value, "angular_momenta");
      } else if (key == "angular_velocities") {
        set_rows(s.Pi, value, "angular_velocities");
        for (Eigen::Index k = 0; k < s.Pi.cols(); ++k)
          s.Pi.col(k) = sys.body(sys.body_of_rigid(static_cast<std::size_t>(k))).inertia * s.Pi.col(k);
      } else if (key == "attitudes") {
        auto a = Array::ensure(value);
        if (!a || a.ndim() != 3 || static_cast<std::size_t>(a.shape(0)) != s.R.size() || a.shape(1) != 3 ||
            a.shape(2) != 3)
          throw noether::Error("attitudes: expected an array of shape (" + std::to_string(s.R.size()) + ", 3, 3)");
        auto v = a.unchecked<3>();
        for (std::size_t k = 0; k < s.R.size(); ++k)
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) s.R[k](r, c) = v(static_cast<py::ssize_t>(k), r, c);
      } else if (key == "quaternions") {
        auto a = Array::ensure(value);
        if (!a || a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != s.R.size() || a.shape(1) != 4)
          throw noether::Error("quaternions: expected an array of shape (" + std::to_string(s.R.size()) + ", 4)");
        auto v = a.unchecked<2>();
        for (std::size_t k = 0; k < s.R.size(); ++k) {
          const noether::Vec4 q(v(static_cast<py::ssize_t>(k), 0), v(static_cast<py::ssize_t>(k), 1),
                                v(static_cast<py::ssize_t>(k), 2), v(static_cast<py::ssize_t>(k), 3));
          if (!(std::abs(q.norm() - 1.0) <= 1e-10))
            throw noether::Error("quaternions: row " + std::to_string(k) + " is not a unit quaternion (norm " +
                                 std::to_string(q.norm()) + ")");
          s.R[k] = noether::rotation_from_quaternion(q);
        }
      } else {
        throw noether::Error("set_state: unknown part '" + key +
                             "' (t, positions, velocities, momenta, attitudes, quaternions, angular_velocities, "
                             "angular_momenta)");
      }
    }
    sim_->set_state(s);
  }

  py::dict diagnostics() const {  // E, T, U, momenta and ‖I − RᵀR‖ at the current state
    noether::Forces forces;
    forces.resize(system());
    sim_->potential().evaluate(sim_->state(), forces);
    const noether::Diagnostics d = noether::diagnose(system(), sim_->state(), forces.U);
    py::dict out;
    out["energy"] = d.energy;
    out["kinetic_energy_translational"] = d.kinetic_translational;
    out["kinetic_energy_rotational"] = d.kinetic_rotational;
    out["potential_energy"] = d.potential;
    out["linear_momentum"] = std::vector<double>{d.linear_momentum.x(), d.linear_momentum.y(), d.linear_momentum.z()};
    out["angular_momentum"] =
        std::vector<double>{d.angular_momentum.x(), d.angular_momentum.y(), d.angular_momentum.z()};
    out["orthogonality_error"] = d.orthogonality_error;
    return out;
  }

  // The force Jacobian K = ∂(f, M)/∂(x, θ) at the current state (docs/equations.md §20) and
  // whether it is the model's own (else central differences of the forces).
  py::tuple force_jacobian() const {
    const auto workspace = sim_->potential().make_workspace();
    const noether::ForceJacobian J = noether::force_jacobian(sim_->potential(), sim_->state(), *workspace);
    return py::make_tuple(J.K, J.analytic);  // pybind11/eigen.h: a NumPy copy
  }

  // The state-transition matrix ∂z(t)/∂z(t0) the run carries (run.stm), None when it carries none.
  py::object stm() const {
    const Eigen::MatrixXd& V = sim_->state().tangent;
    if (V.size() == 0 || !sim_->scene().run.stm) return py::none();
    return py::cast(Eigen::MatrixXd(V.leftCols(V.rows())));  // pybind11/eigen.h: a NumPy copy
  }
  // ∂z(t)/∂p for the keys of run.sensitivities (the tangent's columns after the STM's), None
  // when the run carries none; its columns are named by sensitivity_names.
  py::object sensitivities() const {
    const Eigen::MatrixXd& V = sim_->state().tangent;
    const auto P = static_cast<Eigen::Index>(sim_->sensitivity_names().size());
    if (V.size() == 0 || P == 0) return py::none();
    return py::cast(Eigen::MatrixXd(V.rightCols(P)));
  }
  std::vector<std::string> sensitivity_names() const { return sim_->sensitivity_names(); }
  // One column of sensitivities: ∂z(t)/∂p for the key `name` (as sensitivity_names writes it).
  Eigen::VectorXd sensitivity(const std::string& name) const {
    const auto& names = sim_->sensitivity_names();
    const auto found = std::find(names.begin(), names.end(), name);
    if (found == names.end()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw py::key_error("sensitivity: the run carries no sensitivity to '" + name + "'" +
                          (known.empty() ? std::string(" (it carries none: give sensitivities=[...])")
                                         : " (it carries " + known + ")"));
    }
    const Eigen::MatrixXd& V = sim_->state().tangent;
    return V.col(V.cols() - static_cast<Eigen::Index>(names.size()) + (found - names.begin()));
  }
  std::vector<std::string> stm_coordinates() const { return State::tangent_coordinates(system()); }

  // The massless particles where the run stands (docs/user-guide.md, "Particles"), the arrays of
  // /test_particles as the run would write them now; None when the scene has none.
  py::object particles() const {
    const noether::ParticleSwarm* swarm = sim_->particles();
    if (!swarm) return py::none();
    const auto n = static_cast<py::ssize_t>(swarm->size());
    py::array_t<int> fate(n), body(n);
    py::array_t<double> time(n), point({n, py::ssize_t{3}}), impact({n, py::ssize_t{3}});
    auto f = fate.mutable_unchecked<1>();
    auto b = body.mutable_unchecked<1>();
    auto t = time.mutable_unchecked<1>();
    auto p = point.mutable_unchecked<2>();
    auto v = impact.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const noether::ParticleOutcome& o = swarm->outcomes()[static_cast<std::size_t>(i)];
      f(i) = static_cast<int>(o.fate);
      b(i) = o.body;
      t(i) = o.t;
      for (py::ssize_t k = 0; k < 3; ++k) {
        p(i, k) = o.point[static_cast<Eigen::Index>(k)];
        v(i, k) = o.velocity[static_cast<Eigen::Index>(k)];
      }
    }
    Eigen::Matrix3Xd x0(3, n), v0(3, n);
    for (py::ssize_t i = 0; i < n; ++i) {
      x0.col(i) = swarm->initial_positions()[static_cast<std::size_t>(i)];
      v0.col(i) = swarm->initial_velocities()[static_cast<std::size_t>(i)];
    }
    py::dict out;
    out["position"] = rows(swarm->positions());
    out["velocity"] = rows(swarm->velocities());
    out["initial_position"] = rows(x0);
    out["initial_velocity"] = rows(v0);
    out["fate"] = fate;
    out["time"] = time;
    out["body"] = body;
    out["impact_point"] = point;
    out["impact_velocity"] = impact;
    out["fields"] = swarm->fields();
    out["surfaces"] = swarm->surfaces();
    return out;
  }

  std::string summary_json() const { return noether::format_summary_json(sim_->summary()); }
  std::string summary_text() const { return noether::format_summary(sim_->summary()); }
  std::string finish() { return noether::format_summary_json(sim_->finish()); }
  void save(const std::filesystem::path& file) const { sim_->save(file); }
  std::string scene_as_run() const { return noether::scene_as_run(sim_->scene()); }
  std::vector<std::string> scene_warnings() const { return sim_->scene().warnings; }

  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& b : system().bodies()) out.push_back(b.name);
    return out;
  }
  std::vector<std::string> rigid_names() const {
    std::vector<std::string> out;
    for (std::size_t k = 0; k < system().rigid_count(); ++k) out.push_back(system().body(system().body_of_rigid(k)).name);
    return out;
  }
  std::vector<double> masses() const {
    std::vector<double> out;
    for (const auto& b : system().bodies()) out.push_back(b.mass);
    return out;
  }
  py::array_t<double> inertias() const {
    const auto n = system().rigid_count();
    py::array_t<double> out({static_cast<py::ssize_t>(n), py::ssize_t{3}, py::ssize_t{3}});
    auto v = out.mutable_unchecked<3>();
    for (std::size_t k = 0; k < n; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          v(static_cast<py::ssize_t>(k), r, c) = system().body(system().body_of_rigid(k)).inertia(r, c);
    return out;
  }
  double G() const { return system().G(); }
  py::dict units() const {
    const auto& u = sim_->scene().units;
    py::dict out;
    out["length"] = u.of_length();
    out["mass"] = u.of_mass();
    out["time"] = u.of_time();
    out["declared"] = u.declared;
    return out;
  }
  py::dict run_settings() const {
    const auto& r = sim_->scene().run;
    py::dict out;
    out["t_end"] = r.t_end;
    out["output_every"] = r.output_every;
    return out;
  }

 private:
  static PySimulation make(noether::Scene scene, const std::optional<std::string>& output, bool force,
                           py::object potential, int threads) {
    auto watch = std::make_shared<SignalWatch>();
    return PySimulation(std::make_unique<noether::Simulation>(std::move(scene), registry(),
                                                              run_options(watch, output, force, threads),
                                                              python_potential(potential)),
                        watch);
  }
  // The run's options from the Python arguments (threads: RunOptions::threads, 0 for
  // NOETHER_THREADS, else 1), with `watch` wired in.
  static noether::RunOptions run_options(const std::shared_ptr<SignalWatch>& watch,
                                         const std::optional<std::string>& output, bool force, int threads) {
    noether::RunOptions options = watched_options(watch);
    if (output) options.output = *output;
    options.overwrite = force;
    options.threads = threads;
    return options;
  }
  // A potential written in Python (potential=), or none.
  static std::shared_ptr<const noether::Potential> python_potential(const py::object& potential) {
    if (potential.is_none()) return nullptr;
    return std::make_shared<noether::python::PythonPotential>(potential);
  }
  std::unique_ptr<noether::Simulation> sim_;
  std::shared_ptr<SignalWatch> watch_;
};

}  // namespace

void noether::python::bind_simulation(py::module_& m) {
  py::class_<PySimulation>(m, "_Simulation")
      .def_static("from_text", &PySimulation::from_text)
      .def_static("from_file", &PySimulation::from_file)
      .def_static("load", &PySimulation::load)
      .def_static("resume", &PySimulation::resume)
      .def("integrate", &PySimulation::integrate)
      .def_property_readonly("t", &PySimulation::time)
      .def_property_readonly("positions", &PySimulation::positions)
      .def_property_readonly("velocities", &PySimulation::velocities)
      .def_property_readonly("momenta", &PySimulation::momenta)
      .def_property_readonly("attitudes", &PySimulation::attitudes)
      .def_property_readonly("quaternions", &PySimulation::quaternions)
      .def_property_readonly("angular_velocities", &PySimulation::angular_velocities)
      .def_property_readonly("angular_momenta", &PySimulation::angular_momenta)
      .def("set_state", &PySimulation::set_state)
      .def("diagnostics", &PySimulation::diagnostics)
      .def("force_jacobian", &PySimulation::force_jacobian)
      .def_property_readonly("particles", &PySimulation::particles)
      .def_property_readonly("stm", &PySimulation::stm)
      .def_property_readonly("stm_coordinates", &PySimulation::stm_coordinates)
      .def_property_readonly("sensitivities", &PySimulation::sensitivities)
      .def_property_readonly("sensitivity_names", &PySimulation::sensitivity_names)
      .def("sensitivity", &PySimulation::sensitivity, py::arg("name"),
           "∂z(t)/∂p for one key of sensitivities (e.g. 'bodies.beta.mass'), in the order of stm_coordinates")
      .def("summary_json", &PySimulation::summary_json)
      .def("summary_text", &PySimulation::summary_text)
      .def("finish", &PySimulation::finish)
      .def("save", &PySimulation::save)
      .def("scene_as_run", &PySimulation::scene_as_run)
      .def_property_readonly("scene_warnings", &PySimulation::scene_warnings)
      .def_property_readonly("names", &PySimulation::names)
      .def_property_readonly("rigid_names", &PySimulation::rigid_names)
      .def_property_readonly("masses", &PySimulation::masses)
      .def_property_readonly("inertias", &PySimulation::inertias)
      .def_property_readonly("G", &PySimulation::G)
      .def_property_readonly("units", &PySimulation::units)
      .def_property_readonly("run", &PySimulation::run_settings);
}
