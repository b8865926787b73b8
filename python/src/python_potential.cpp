#include "python_potential.hpp"
#include "state_arrays.hpp"

#include <noether/error.hpp>

#include <pybind11/numpy.h>

#include <sstream>

namespace py = pybind11;

namespace noether::python {

PythonPotential::PythonPotential(py::object function) : function_(std::move(function)) {
  if (!PyCallable_Check(function_.ptr()))
    throw SceneError("potential: expected a callable f(positions, attitudes) -> (U, forces, moments)");
}

PythonPotential::~PythonPotential() {
  py::gil_scoped_acquire gil;
  function_ = py::object();
}

namespace {

// An (rows, 3) array of doubles from what Python returned, or an error naming it.
py::array_t<double, py::array::c_style | py::array::forcecast> rows_of_three(const py::handle& value, std::size_t rows,
                                                                             const char* what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != rows || a.shape(1) != 3) {
    std::ostringstream msg;
    msg << "the Python potential returned " << what << " that is not a (" << rows << ", 3) array of numbers";
    throw SceneError(msg.str());
  }
  return a;
}

}  // namespace

void PythonPotential::evaluate(const State& state, Forces& forces, Workspace&) const {
  py::gil_scoped_acquire gil;
  const std::size_t bodies = static_cast<std::size_t>(state.x.cols()), rigid = state.R.size();
  const auto nb = static_cast<py::ssize_t>(bodies), nr = static_cast<py::ssize_t>(rigid);
  const py::array_t<double> x = rows(state.x), R = attitudes(state);
  py::object result;
  try {
    result = function_(x, R);
  } catch (py::error_already_set& e) {
    throw IntegrationError(std::string("the Python potential raised: ") + e.what(), state.t);
  }
  py::tuple t;
  if (!py::isinstance<py::tuple>(result) || (t = result.cast<py::tuple>()).size() != 3)
    throw SceneError("the Python potential must return a tuple (U, forces, moments)");
  forces.U = t[0].cast<double>();
  const auto f = rows_of_three(t[1], bodies, "forces");
  auto fv = f.unchecked<2>();
  for (py::ssize_t i = 0; i < nb; ++i)
    for (py::ssize_t a = 0; a < 3; ++a) forces.f(a, i) = fv(i, a);
  if (nr == 0) return;
  if (t[2].is_none()) throw SceneError("the Python potential returned no moments, but the scene has rigid bodies");
  const auto M = rows_of_three(t[2], rigid, "moments");
  auto Mv = M.unchecked<2>();
  for (py::ssize_t k = 0; k < nr; ++k)
    for (py::ssize_t a = 0; a < 3; ++a) forces.M(a, k) = Mv(k, a);
}

}  // namespace noether::python
