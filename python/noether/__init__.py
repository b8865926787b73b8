"""noether: bodies under mutual gravity — the full body problem and point masses.

The same core, plugins and output as the `noether` command (docs/python.md):

    import noether
    sim = noether.Simulation("examples/dumbbells.yaml")
    sim.integrate(10.0)
    sim.positions, sim.attitudes, sim.summary()["max_abs_energy_error"]

Scenes come from a YAML file, a dict of the same keys, or YAML text (Simulation.from_yaml);
potentials and integrators are plugins chosen by name in the scene. Errors are
noether.Error and its kinds (SceneError, PluginError, IntegrationError, OutputError), with the
messages the command prints.
"""
import functools
import json
import numbers
import os
import sys
import warnings

import numpy as _np

try:
    from ._noether import (Error, IntegrationError, OutputError, PluginError, SceneError, __version__,
                           _Simulation)
except ImportError as e:  # a compiled module for another interpreter (pyenv, a venv of another Python)
    raise ImportError(f"noether's compiled module does not load in {sys.executable} (Python "
                      f"{sys.version.split()[0]}): it is built for Debian's /usr/bin/python3, which "
                      f"tools/install-deps.sh provisions; run with /usr/bin/python3 (README, \"Python\") [{e}]") from None
from . import _noether


class ArgumentError(Error, TypeError):
    """An argument of the wrong type or kind — text where a number goes, complex values where real
    ones go, a number where a path goes — raised by noether's functions and Simulation's methods
    before anything runs or changes: a noether.Error, and a TypeError as Python's own checks are."""


class InputWarning(UserWarning):
    """A scene value that is allowed but looks like a slip (a spin faster than the body's breakup
    rate, a step longer than the scene's shortest period, a density no rock has): the message
    gives the numbers and the key. The same warnings are in summary()["warnings"]."""




def _wrong_argument(name, e):
    """The ArgumentError for what a conversion or the compiled module raised about an argument of
    `name` (a function or method): the message's first line, and for pybind11's "incompatible
    function arguments" the arguments the call takes."""
    text = str(e)
    if "incompatible function arguments" in text:
        import re
        takes = re.search(r"1\. \((?:self: [^,)]*(?:, )?)?(.*)\) ->", text)
        text = "an argument of the wrong type" + (f" (it takes {takes.group(1)})" if takes else "")
    elif "Unable to cast" in text:
        text = "an argument of the wrong type"
    error = ArgumentError(f"{name}: {text.splitlines()[0] if text else type(e).__name__}")
    error._named = True
    return error


def _caller_stacklevel():
    """warnings.warn's stacklevel of the first frame outside this package: the user's line."""
    here = os.path.dirname(os.path.abspath(__file__))
    frame, level = sys._getframe(1), 1
    while frame is not None and os.path.dirname(os.path.abspath(frame.f_code.co_filename)) == here:
        frame, level = frame.f_back, level + 1
    return level


def _checked_arguments(fn):
    """fn, raising ArgumentError (named after fn) for what Python's conversions (float("x"),
    os.fspath(3)) and the compiled module's argument checks raise about an argument: a TypeError,
    a ValueError, pybind11's bare "Unable to cast" RuntimeError. noether's own errors pass as they
    are (a Python potential's exceptions reach here as noether.IntegrationError)."""
    name = fn.__qualname__.replace(".__init__", "")

    @functools.wraps(fn)
    def checked(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except ArgumentError as e:  # one of the explicit checks: named after the outermost call
            if getattr(e, "_named", False):
                raise
            named = ArgumentError(f"{name}: {e}")
            named._named = True
            raise named from None
        except Error:
            raise
        except (TypeError, ValueError) as e:
            raise _wrong_argument(name, e) from None
        except RuntimeError as e:
            if type(e) is RuntimeError and "Unable to cast" in str(e):
                raise _wrong_argument(name, e) from None
            raise
    return checked


def _real(name, value):
    """value as a float, or ArgumentError: a real number (Python's or NumPy's; not a bool, not
    complex, not text)."""
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, _np.bool_)):
        return float(value)
    if isinstance(value, numbers.Complex):
        raise ArgumentError(f"{name}: {value!r} is complex; give a real number")
    raise ArgumentError(f"{name}: expected a real number, not {type(value).__name__} {value!r:.60}")


def _reals(name, value):
    """value as an array of float64, or ArgumentError: real numbers only — complex values are
    refused (NumPy would drop their imaginary parts with a warning), as are text, None and bools."""
    try:
        a = _np.asarray(value)
    except (TypeError, ValueError) as e:  # ragged nested lists
        raise ArgumentError(f"{name}: not an array of numbers ({e})") from None
    if a.dtype.kind == "c":
        raise ArgumentError(f"{name}: complex values; give real numbers (numpy.real(x) if the imaginary parts "
                            "are zero by construction)")
    if a.dtype.kind not in "iuf":
        raise ArgumentError(f"{name}: expected an array of real numbers, not {a.dtype} ({value!r:.60})")
    return _np.ascontiguousarray(a, dtype=_np.float64)


def _file_path(name, value, optional=False):
    """os.fspath(value) for a str or os.PathLike (None when optional), or ArgumentError."""
    if value is None and optional:
        return None
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    raise ArgumentError(f"{name}: expected a path (str or os.PathLike), not {type(value).__name__} {value!r:.60}")

from .output import Output, read
from .compare import Table, compare
from .view import View, view

__all__ = ["Simulation", "Output", "read", "output_series", "compare", "Table", "view", "View", "plugins", "observe", "fit", "stokes", "relative_equilibrium",
           "relative_periodic_orbit", "lyapunov_orbit", "Error",
           "ArgumentError", "InputWarning", "SceneError", "PluginError", "IntegrationError", "OutputError", "__version__"]


def _checked_simulation_methods(cls):
    """cls with each method and classmethod it defines wrapped by _checked_arguments."""
    for key, value in list(vars(cls).items()):
        if isinstance(value, classmethod):
            setattr(cls, key, classmethod(_checked_arguments(value.__func__)))
        elif callable(value) and (not key.startswith("_") or key == "__init__"):
            setattr(cls, key, _checked_arguments(value))
    return cls


@_checked_arguments
def observe(run, observable, times=None, line_of_sight=None, sunlight=None, tessellation=4):
    """An observable of a run's output file (docs/fitting.md): `observable` is
    "NAME:TARGET:CENTER" (position.x, position.y, position.z, sky.east, sky.north, range,
    range_rate, lightcurve.lommel_seeliger, lightcurve.lambert, conjunction.time; bodies by name),
    at every frame (conjunction.time: at every conjunction in the run) or at `times`
    (interpolated between frames, docs/equations.md eqs. 16.2 and 29.4; conjunction.time: the
    conjunction nearest to each); the sky observables, lightcurves and conjunctions need `line_of_sight` (x, y, z: from the observer towards the
    bodies), lightcurves also `sunlight` (x, y, z: from the Sun towards the bodies) and draw an
    ellipsoid with 20·4^tessellation facets. Returns (t, value), two NumPy arrays, in the scene's
    units. The frames are verified against their checksums; a time outside the run is a
    SceneError."""
    los = [] if line_of_sight is None else [float(c) for c in line_of_sight]
    sun = [] if sunlight is None else [float(c) for c in sunlight]
    return _noether.observe(os.fspath(run), observable, None if times is None else [float(t) for t in times], los,
                            sun, int(tessellation))


@_checked_arguments
def stokes(scene, body, degree=8, radius=None, normalized=True, set=None):
    """`noether shape stokes` (docs/gravity-fields.md): the Stokes coefficients of a scene's body
    about its centre of mass in its body frame, from its shape (or its field, or its inertia), to
    `degree`, at the reference radius `radius` (the scene's length unit; default the body's
    radius), fully normalized (geodesy's 4π) or not. Returns a dict: "C" and "S" as
    (degree + 1) × (degree + 1) NumPy arrays indexed [n, m] (zero above m = n), "degree",
    "mass", "gm", "reference_radius", "normalized", "polar_moment" (C/(M R²) about body z) and
    "source"."""
    return _noether.stokes(os.fspath(scene), body, int(degree), 0.0 if radius is None else float(radius),
                           bool(normalized), list(set or []))


@_checked_arguments
def fit(scene, observations, free, set=None, max_iterations=30, tolerance=1e-3):
    """`noether fit` (docs/fitting.md): the scene's keys `free` (a list, as --sensitivity takes
    them) estimated from an observation file by weighted least squares on the run's own
    sensitivities. Returns the fit as a dict — the fields of `noether fit -o FIT.json`, with
    "names", "estimate", "sigma" and "initial" (NumPy arrays, one entry per parameter component)
    and "covariance", "correlation" as NumPy matrices. Bad input raises SceneError, as the
    command exits 2; a fit that did not converge has "converged": False and says why in "stop"."""
    free = [free] if isinstance(free, str) else list(free)
    text = _noether.fit(os.fspath(scene), os.fspath(observations), free, list(set or []), int(max_iterations),
                        float(tolerance))
    result = json.loads(text)
    for key in ("estimate", "sigma", "initial"):
        result[key] = _np.array([p[key] for p in result["parameters"]])
    result["names"] = [p["name"] for p in result["parameters"]]
    for key in ("covariance", "correlation"):
        result[key] = _np.array(result[key])
    return result


def output_series():
    """Every series an output file holds per frame: a list of dicts with name (the key of
    noether.read(file)[name]), path, shape ("[frame][body][3]"), unit (in L, M, T), description,
    integer, rigid_only, optional (present when the integrator has variables of its own),
    checkpointed (read back and verified by a continuation) and needs (what a scene needs for
    the series: "", "rigid bodies", "a binary", "a binary with a rigid primary", …)."""
    return _noether.output_series()


def plugins():
    """Every plugin found (the bundled ones and those on NOETHER_PLUGIN_PATH): a list of dicts
    with name, kind ("potential" or "integrator"), description, file and params (name, type,
    default — None when required —, description)."""
    return _noether.plugins()


def _json_value(value):
    """NumPy arrays and scalars in a scene dict, as the lists and numbers they hold."""
    if hasattr(value, "tolist"):  # numpy.ndarray, numpy.float64, numpy.int64, numpy.bool_
        return value.tolist()
    raise TypeError(f"a scene value of type {type(value).__name__} ({value!r}) is not a number, string, "
                    "list or dict")


def _scene_text(scene):
    """(text, name) of a scene given as a dict: JSON is YAML, so the scene reader reads it as
    it reads a file, with the same checks and messages. NumPy arrays and scalars are taken as
    the lists and numbers they hold."""
    try:
        return json.dumps(scene, indent=1, default=_json_value), "<dict>"
    except (TypeError, ValueError) as e:
        raise SceneError(f"<dict>: {e}") from None


@_checked_arguments
def relative_equilibrium(scene, set=(), fix="separation", value=None, pair=None, align=True, tolerance=1e-6):
    """The relative equilibrium nearest to a scene's state and its stability, as
    `noether orbit equilibrium` finds them (docs/relative-equilibria.md).

      scene      a path to a YAML scene, or a dict of its keys: its state is the first guess
      set        overrides, as for Simulation
      fix        the member of the family: "separation" (of `pair`), "angular-momentum" (L·k̂)
                 or "rate" (ω); value: its value (None: the scene's own)
      pair       two body names (default: the first two bodies)
      align      turn the guess's principal axes onto k̂ and the line of centres first
      tolerance  |Re λ| ≤ tolerance × max(ω, |λ|) counts as stable

    Returns a dict: converged, residual, iterations, rate, period, axis, separation,
    angular_momentum, energy, overlapping (the bounding spheres), the state (positions,
    velocities, attitudes, angular_velocities in the body frame; where Newton ended when it did
    not converge) and, when converged, scene (YAML text of one period, for
    Simulation.from_yaml), modes (a list of dicts: frequency, period,
    growth, motion, share, in_plane), eigenvalues (complex), verdict, in_plane_verdict,
    out_of_plane_verdict, energetic_verdict, energetic_index and invariance_defect. Raises
    SceneError for a scene without one (no angular momentum, an external field)."""
    overrides = [set] if isinstance(set, str) else list(set)
    pair = list(pair) if pair is not None else []
    value = None if value is None else float(value)
    if isinstance(scene, dict):
        text, name = _scene_text(scene)
        return _noether.relative_equilibrium("", text, name, overrides, fix, value, pair, align, float(tolerance))
    if isinstance(scene, (str, os.PathLike)):
        return _noether.relative_equilibrium(os.fspath(scene), "", "", overrides, fix, value, pair, align,
                                             float(tolerance))
    raise ArgumentError("scene: a path to a YAML scene, or a dict of its keys")


@_checked_arguments
def relative_periodic_orbit(scene, set=(), period=None, turns=0, tolerance=1e-6):
    """A relative periodic orbit of a scene's own integrator near its state, and its multipliers,
    as `noether orbit refine` and `orbit stability` find them for rigid bodies
    (docs/relative-equilibria.md): a state that the integrator's map over `period` (default
    run.t_end) returns turned about the total angular momentum. With `lgvi` it is an orbit of
    the discrete map (the period a whole number of steps).

      scene      a path to a YAML scene, or a dict of its keys: its state is the first guess
      set        overrides, as for Simulation
      turns      whole turns added to the measured turn of the line of centres
      tolerance  |μ| ≤ 1 + tolerance counts as stable

    Returns a dict: period, angle (α), axis, initial_closure, closure, iterations, converged
    (closure ≤ 1e-9), integrator and, when converged, multipliers (complex, by modulus),
    max_modulus, verdict, energy_conserved (the map conserves E: projected out), energy_defect,
    invariance_defect, monodromy ("tangent map": from the integrator's, docs/equations.md eq.
    19.4; "differences": of the map) and scene (YAML text of one period, the step kept, for
    Simulation.from_yaml)."""
    overrides = [set] if isinstance(set, str) else list(set)
    period = None if period is None else float(period)
    if isinstance(scene, dict):
        text, name = _scene_text(scene)
        return _noether.relative_periodic_orbit("", text, name, overrides, period, int(turns), float(tolerance))
    if isinstance(scene, (str, os.PathLike)):
        return _noether.relative_periodic_orbit(os.fspath(scene), "", "", overrides, period, int(turns),
                                                float(tolerance))
    raise ArgumentError("scene: a path to a YAML scene, or a dict of its keys")


@_checked_arguments
def lyapunov_orbit(scene, body, degrees, set=(), tolerance=1e-6):
    """The periodic orbit of a rigid body's libration at an amplitude (degrees), grown out of the
    libration mode of the relative equilibrium nearest to the scene's state, on the scene's own
    integrator, as `noether orbit equilibrium --lyapunov BODY,DEG` finds it
    (docs/relative-equilibria.md, docs/equations.md (19.3)). With a fixed-step integrator the
    number of steps per period is held and the step follows the period.

    Returns a dict: period, linear_period (2π/ν of the mode), angle (α), initial_closure,
    closure, iterations, converged, step and steps (0 for adaptive integrators) and, when
    converged, multipliers (complex), family (the pair at 1 set apart, on a map that does not
    conserve E), verdict, monodromy ("tangent map" or "differences") and scene (YAML text of one
    period, for Simulation.from_yaml)."""
    overrides = [set] if isinstance(set, str) else list(set)
    if isinstance(scene, dict):
        text, name = _scene_text(scene)
        return _noether.lyapunov_orbit("", text, name, overrides, str(body), float(degrees), float(tolerance))
    if isinstance(scene, (str, os.PathLike)):
        return _noether.lyapunov_orbit(os.fspath(scene), "", "", overrides, str(body), float(degrees),
                                       float(tolerance))
    raise ArgumentError("scene: a path to a YAML scene, or a dict of its keys")


def _derivative_overrides(set, stm, sensitivities, chaos=False):
    """The overrides of set=, stm=, sensitivities= and chaos= (as `noether run --set/--stm/
    --sensitivity/--chaos`)."""
    if isinstance(sensitivities, str):
        sensitivities = [sensitivities]
    return (([set] if isinstance(set, str) else list(set)) + (["run.stm=true"] if stm else [])
            + [f"run.sensitivities+={key}" for key in sensitivities] + (["run.chaos=true"] if chaos else []))


@_checked_simulation_methods
class Simulation:
    """A run held open: integrate to a time, read or set the state, integrate on.

    Simulation(scene, set=(), output=None, force=False, potential=None, stm=False, sensitivities=(),
               chaos=False)
      scene     a path to a YAML scene file, or a dict with the keys of one (docs/user-guide.md)
      set       overrides as for `noether run --set`: ["integrator.step=1e-3", ...]
      output    an HDF5 file to write as the command does (frames at run.output_every and at
                every time integrate() stops); None: no file
      force     replace an existing output file
      potential a Python callable f(positions, attitudes) -> (U, forces, moments) used instead
                of the scene's potential plugins (prototyping only: it is slow; docs/python.md)
      stm       carry the state-transition matrix of the integrator's map (run.stm, `noether run
                --stm`): sim.stm, docs/derivatives.md
      sensitivities  keys of the bodies' initial states ("bodies.moon.velocity", …) or parameters of
                     the dynamics ("bodies.moon.mass", "G", …; run.sensitivities,
                `noether run --sensitivity`): sim.sensitivities, docs/derivatives.md
      chaos     compute MEGNO and the fast Lyapunov indicator from a deviation vector the tangent
                map carries (run.chaos, `noether run --chaos`): sim.chaos, docs/derivatives.md
      threads   threads inside each evaluation of the potential (`noether run --threads`); None
                takes NOETHER_THREADS, else 1. The results are the same bit for bit for any number.

    The state properties return copies (NumPy arrays) of the state where the simulation stands;
    assigning one (sim.positions = x) or calling set_state(...) replaces that part, checked, and
    starts a new segment (the summary's references are taken there).
    """

    def __init__(self, scene, set=(), output=None, force=False, potential=None, stm=False, sensitivities=(),
                 chaos=False, threads=None):
        overrides = _derivative_overrides(set, stm, sensitivities, chaos)
        if isinstance(scene, _Simulation):  # from load()
            self._sim = scene
        elif isinstance(scene, dict):
            text, name = _scene_text(scene)
            self._sim = _Simulation.from_text(text, name, overrides, _path(output), force, potential, _threads(threads))
        elif isinstance(scene, (str, os.PathLike)):
            self._sim = _Simulation.from_file(os.fspath(scene), overrides, _path(output), force, potential,
                                              _threads(threads))
        else:
            raise ArgumentError("scene: a path to a YAML scene, or a dict of its keys; "
                                "for YAML text use Simulation.from_yaml(text)")
        for warning in self._sim.scene_warnings:
            warnings.warn(warning, InputWarning, stacklevel=_caller_stacklevel())

    @classmethod
    def from_yaml(cls, text, set=(), output=None, force=False, potential=None, name="<yaml>", stm=False,
                  sensitivities=(), chaos=False, threads=None):
        """A simulation of a scene given as YAML text (relative shape paths: from the working
        folder)."""
        overrides = _derivative_overrides(set, stm, sensitivities, chaos)
        return cls(_Simulation.from_text(text, name, overrides, _path(output), force, potential, _threads(threads)))

    @classmethod
    def load(cls, path, output=None, force=False, potential=None, threads=None):
        """A simulation saved with save(), or the run of an output file at its last complete
        frame: it continues as the saved one would have (bit for bit with fixed-step
        integrators; an output file's frames are replayed into the summary). With output, frames
        go to a new file whose frame 0 is the loaded state. A simulation saved with a Python
        potential needs it again: potential=."""
        return cls(_Simulation.load(_file_path("path", path), _path(output), force, potential, _threads(threads)))

    @classmethod
    def resume(cls, path, t_end=None, threads=None):
        """Continues the run recorded in an output file (as `noether run --resume`): from its
        last complete frame, appending to the file; t_end extends it. integrate(sim.run["t_end"])
        then finish() completes it."""
        return cls(_Simulation.resume(_file_path("path", path), float("nan") if t_end is None else _real("t_end", t_end),
                                      _threads(threads)))

    # Running ---------------------------------------------------------------------------------
    def integrate(self, t):
        """Integrates to time t (frames at the scene's output times and at t). Returns a dict:
        t reached, stopped (bool), reason and event ("collision", "close approach", …) when an
        event stopped it before t. t equal to the current time does nothing."""
        t = _real("t", t)
        if t == self._sim.t:
            return {"t": self._sim.t, "stopped": False, "reason": "", "event": ""}
        return self._sim.integrate(t)

    def summary(self):
        """The run summary so far as a dict (the keys of `noether run --summary json`)."""
        return json.loads(self._sim.summary_json())

    def summary_text(self):
        """The summary as `noether run` prints it."""
        return self._sim.summary_text()

    def diagnostics(self):
        """Energy, its parts, the total momenta and max ‖I − RᵀR‖ at the current state."""
        return self._sim.diagnostics()

    def force_jacobian(self):
        """(K, analytic): the force Jacobian K = ∂(f, M)/∂(x, θ) at the current state, a
        (3n + 3m)² array — positions of all bodies, then attitudes of the rigid ones perturbed in
        their body frames (docs/equations.md §20) — and whether it is the model's own (True) or
        central differences of its forces (False)."""
        return self._sim.force_jacobian()

    @property
    def particles(self):
        """The scene's massless particles where the run stands (docs/user-guide.md, "Particles"):
        a dict of position and velocity (inertial; a landed particle's at its landing),
        initial_position, initial_velocity, fate (0 in flight, 1 landed, 2 escaped), time (of
        the landing or escape; NaN in flight), body (landed on, an index in surfaces: the bodies,
        then the prescribed bodies; -1 none), impact_point and impact_velocity (body frame),
        fields and surfaces — the arrays /test_particles is written from;
        None when the scene has no particles."""
        return self._sim.particles

    @property
    def stm(self):
        """The state-transition matrix ∂z(t)/∂z(t0) of the integrator's own map since the start
        (or the last set_state), a (6n + 6m)² array in the order of z = (x, θ, γ, Π)
        (docs/equations.md eq. 21.1; names in stm_coordinates); None unless the simulation
        carries it (stm=True)."""
        return self._sim.stm

    @property
    def chaos(self):
        """The chaos indicators where the simulation stands (chaos=True), a dict: megno (⟨Y⟩, → 2
        on a regular orbit, ≈ λ t / 2 on a chaotic one), megno_y (Y), fli (log10 of the
        deviation's largest growth), lyapunov (ln ‖δ‖ / t), t (the step they stand at),
        overflowed; None unless asked for (docs/derivatives.md, "Chaos indicators")."""
        return self.summary()["chaos"]

    @property
    def sensitivities(self):
        """∂z(t)/∂p: how the state where the simulation stands moves with each key asked for
        (sensitivities=...: keys of the bodies' initial states, masses, G, semi-axes), a
        (6n + 6m) × P array, rows in the
        order of z (stm_coordinates), columns named by sensitivity_names, per unit of each key
        as the scene gives it; None unless asked for."""
        return self._sim.sensitivities

    @property
    def sensitivity_names(self):
        """The keys of the columns of sensitivities, one per component ("bodies.moon.velocity.0",
        "bodies.moon.orbit.e", "bodies.alpha.attitude.x", "bodies.moon.mass", "G"): the
        initial state's keys first, then the parameters of the dynamics."""
        return self._sim.sensitivity_names

    def sensitivity(self, name):
        """∂z(t)/∂p for one key of sensitivity_names (sim.sensitivity("bodies.beta.mass")), a
        vector in the order of stm_coordinates; for a key whose components are carried
        ("impulses.0.delta_v": .0, .1, .2) a matrix of those columns, in order; KeyError for a key
        the run does not carry."""
        if not isinstance(name, str):
            raise ArgumentError(f"name: a key of sensitivity_names (str), not {type(name).__name__}")
        names = self._sim.sensitivity_names
        if name not in names:
            parts = [n for n in names if n.startswith(name + ".")]
            if parts:
                return _np.column_stack([self._sim.sensitivity(n) for n in parts])
        return self._sim.sensitivity(name)

    @property
    def stm_coordinates(self):
        """The names of the rows (and columns) of stm: "alpha.position.x", "alpha.attitude.x"
        (θ, the right perturbation R exp(S(θ))), "alpha.momentum.x", "alpha.angular_momentum.x"
        (Π, body frame)."""
        return self._sim.stm_coordinates

    def finish(self):
        """Writes the outcome to the output file and closes it; returns the summary dict."""
        return json.loads(self._sim.finish())

    def save(self, path):
        """Saves the simulation where it stands to an output file with one frame (the scene, the
        exact state, the work, the summary's running values in /checkpoint/summary), for
        Simulation.load(), Simulation.resume() or noether.read()."""
        self._sim.save(_file_path("path", path))

    def set_state(self, **parts):
        """Replaces parts of the state: t, positions, velocities, momenta, attitudes (rotation
        matrices), quaternions (w, x, y, z), angular_velocities (body frame), angular_momenta
        (body frame Π = J Ω), each an array of real numbers of the part's shape (t a real number).
        What is refused raises noether.Error and changes nothing: attitudes that are not
        rotations, non-finite values, two bodies at the same position, bodies inside each other
        when the run stops at collisions (as the scene's initial state is refused), an array of
        the wrong shape, and — as noether.ArgumentError — complex values or text."""
        self._sim.set_state(**{key: _real(key, value) if key == "t" else _reals(key, value)
                               for key, value in parts.items()})

    # The state (copies) -----------------------------------------------------------------------
    t = property(lambda self: self._sim.t, lambda self, v: self.set_state(t=v), doc="time")
    positions = property(lambda self: self._sim.positions, lambda self, v: self.set_state(positions=v),
                         doc="x_i, inertial frame, (n, 3)")
    velocities = property(lambda self: self._sim.velocities, lambda self, v: self.set_state(velocities=v),
                          doc="v_i = γ_i/m_i, inertial frame, (n, 3)")
    momenta = property(lambda self: self._sim.momenta, lambda self, v: self.set_state(momenta=v),
                       doc="γ_i = m_i v_i, inertial frame, (n, 3) (the state's own variable: exact)")
    attitudes = property(lambda self: self._sim.attitudes, lambda self, v: self.set_state(attitudes=v),
                         doc="R_k, body to inertial frame, rigid bodies, (m, 3, 3)")
    quaternions = property(lambda self: self._sim.quaternions, lambda self, v: self.set_state(quaternions=v),
                           doc="R_k as unit quaternions (w, x, y, z), (m, 4)")
    angular_velocities = property(lambda self: self._sim.angular_velocities,
                                  lambda self, v: self.set_state(angular_velocities=v),
                                  doc="Ω_k = J_k⁻¹ Π_k, body frame, (m, 3)")
    angular_momenta = property(lambda self: self._sim.angular_momenta,
                               lambda self, v: self.set_state(angular_momenta=v),
                               doc="Π_k, body frame, (m, 3) (the state's own variable: exact)")

    # The scene ---------------------------------------------------------------------------------
    names = property(lambda self: self._sim.names, doc="body names, in the order of every body axis")
    rigid_names = property(lambda self: self._sim.rigid_names, doc="names of the rigid bodies (attitude axis)")
    masses = property(lambda self: self._sim.masses)
    inertias = property(lambda self: self._sim.inertias, doc="J_k, body frame, (m, 3, 3)")
    G = property(lambda self: self._sim.G)
    units = property(lambda self: self._sim.units, doc="the scene's units: length, mass, time, declared")
    run = property(lambda self: self._sim.run, doc="the scene's t_end and output_every")

    def scene_as_run(self):
        """The scene as run (after the overrides), as YAML."""
        return self._sim.scene_as_run()

    def __repr__(self):
        return f"<noether.Simulation t={self.t:.10g}, bodies {self.names}>"


def _path(p):
    return None if p is None else os.fspath(p)


def _threads(threads):
    """Simulation(threads=): RunOptions::threads; None is 0, NOETHER_THREADS or else 1."""
    if threads is None:
        return 0
    if isinstance(threads, bool) or not isinstance(threads, numbers.Integral) or threads < 1:
        raise SceneError(f"threads must be a positive whole number (or None: NOETHER_THREADS, else 1), not {threads!r}")
    return int(threads)
