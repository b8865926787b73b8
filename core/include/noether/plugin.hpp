#pragma once
// The ABI between core and plugins (docs/writing-a-plugin.md). A plugin is a MODULE shared
// library, named noether-<name>.so, that exports one C symbol, `noether_plugin_descriptor`,
// of type PluginDescriptor.
//
// Version policy: NOETHER_PLUGIN_API_VERSION changes whenever anything a header of
// noether-core declares (this folder's headers: PluginDescriptor, Potential, Integrator,
// System, State, Forces, Params and the shared mathematics) changes in a way that breaks
// binary compatibility. Plugins link libnoether-core only; the host library (scenes, registry,
// stepping loop, output) is not part of the interface (tests/abi checks both).
// Version 1: the first Potential and Integrator interfaces (an integrator ran a whole run).
// Version 2: Body::solid (a homogeneous ellipsoid or polyhedron, with its mesh) added to System.
// Version 3: Integrator is one step at a time (start/step/current/interpolate); the host's
// stepping loop owns outputs and events; Potential::needs_attitudes removed,
// Potential::position_hessian added.
// Version 4: a Potential is immutable and evaluates into a caller-owned Workspace
// (make_workspace, evaluate(state, forces, workspace), pair_models(workspace));
// Integrator::potential_evaluator; ContinuousEquations is an interface without data members.
// Version 5: Integrator::take_step_series (per-step records handed over and forgotten, streamed
// to the output) replaces step_series.
// Version 6: Integrator::checkpoint and Integrator::restore (an integrator whose
// variables are not the State — a relative frame, a two-step form — hands them to the output
// and takes them back, so a continued run is bit for bit the uninterrupted one).
// Version 7: Potential::force_jacobian (∂(f, M)/∂(x, θ), positions and attitudes,
// with a workspace) replaces Potential::position_hessian; State::tangent,
// Integrator::tangent_map_unavailable and Integrator::carry_parameters (derivatives).
// Version 8: Body::field (a body given by its Stokes coefficients) added to System.
// Version 9: forces beyond the potential — PluginKind::Force, ForceModel
// (force_model.hpp), PluginDescriptor::make_force, Integrator::add_forcing and
// State::force_balance.
// Version 10: ExactMutualOptions::method and ExactMutual's expansion (its layout changed);
// solid_harmonics.hpp added.
// Version 11: DynamicsParameter and ParameterForces carry the forces beyond the
// potential made at a parameter's stencil (their layouts changed; ParameterForces::forcing,
// with_forcing).
// Version 12: MutualSeries sums over the integrals modulo traces (its layout changed);
// harmonic_integrals.hpp (TraceReduction, HarmonicRotation) added.
// Version 13: ForceModel::pull_particles (the point masses a force's body pulls
// massless particles with) and PointPull.
// Version 14: PointPull carries the point mass's velocity and radius (particles land on it);
// PrescribedConic::velocity.
// Version 15 (current): Potential::choose_models and ForceModel::choose_models (a tolerance's
// choices made at the scene's initial state, before the model is shared), ForceModel::pair_models.
// Exported: every header of core/include/noether wraps its declarations in
// `#pragma GCC visibility push(default)` … `pop`; the library is otherwise built hidden.
// `api_version` stays the first member in every version, so a registry can
// always read it and refuse a plugin built for another version, naming both.
#include <noether/force_model.hpp>
#include <noether/integrator.hpp>
#include <noether/params.hpp>
#include <noether/potential.hpp>
#include <noether/system.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>

// Everything declared below is part of noether-core's exported interface (plugin.hpp).
#pragma GCC visibility push(default)

#define NOETHER_PLUGIN_API_VERSION 16u

namespace noether {

enum class PluginKind : std::uint32_t { Potential = 1, Integrator = 2, Force = 3 };

const char* to_string(PluginKind kind);

// One documented parameter. `default_value`: the value the host fills in when the scene omits
// the key (YAML text, read as `type` says: "1e-8", "inertial", "[0, 0, 0]"), so a plugin reads
// every documented key with at() and keeps no second copy of its defaults; or, in parentheses,
// a description of a default the plugin works out itself ("(0.9 x osculating periapsis)": the
// key is then absent unless given); nullptr for a required parameter. given() (params.hpp) tells
// a key the scene gave from one the host filled in.
struct ParamDoc {
  const char* name;
  const char* type;  // "number", "integer", "string", "bool", "list"
  const char* default_value;
  const char* description;
};

using PotentialFactory = std::unique_ptr<Potential> (*)(const System& system,
                                                        const Params& params);
using IntegratorFactory = std::unique_ptr<Integrator> (*)(
    const System& system, std::shared_ptr<const Potential> potential, const Params& params);
using ForceFactory = std::unique_ptr<ForceModel> (*)(const System& system, const Params& params);

struct PluginDescriptor {
  std::uint32_t api_version;  // must stay the first member in every API version
  PluginKind kind;
  const char* name;
  const char* description;  // one line
  const ParamDoc* params;
  std::size_t param_count;
  PotentialFactory make_potential;    // set for PluginKind::Potential
  IntegratorFactory make_integrator;  // set for PluginKind::Integrator
  ForceFactory make_force;            // set for PluginKind::Force
};

}  // namespace noether

// The symbol the registry looks up in every plugin library.
#define NOETHER_PLUGIN_SYMBOL "noether_plugin_descriptor"

// Use as:  NOETHER_PLUGIN_DESCRIPTOR = { NOETHER_PLUGIN_API_VERSION, ... };
#define NOETHER_PLUGIN_DESCRIPTOR                      \
  extern "C" __attribute__((visibility("default"))) \
  const noether::PluginDescriptor noether_plugin_descriptor

#pragma GCC visibility pop
