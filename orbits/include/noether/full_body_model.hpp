#pragma once
// The full body problem of a scene, for the orbit tools: its bodies (rigid or point masses), its
// potential made by name as `noether run` makes it, and the plugin registry its integrators come
// from; with the conserved quantities of docs/equations.md §3 about the barycentre.
#include <noether/potential.hpp>
#include <noether/registry.hpp>
#include <noether/scene.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>

#include <memory>
#include <vector>

namespace noether {

struct FullBodyModel {
  System system;
  std::shared_ptr<const Potential> potential;
  std::vector<PluginConfig> potentials;      // the scene's `potential:` entries
  std::shared_ptr<PluginRegistry> registry;  // for integrator plugins
  // The workspace forces() evaluates with: one per model, so a model's warnings (a series used
  // inside its bodies' bounding spheres) are given once. The orbit tools are single-threaded;
  // copies of a model share it.
  std::shared_ptr<Workspace> workspace;

  static FullBodyModel from_scene(const Scene& scene, PluginRegistry& registry);

  std::size_t n() const { return system.size(); }
  std::size_t rigid() const { return system.rigid_count(); }
  double total_mass() const;
  // U, f_i and M_k at `state`, evaluated with `workspace`.
  Forces forces(const State& state) const;
  Vec3 barycentre(const State& state) const;           // Σ m_i x_i / Σ m_i
  Vec3 barycentre_velocity(const State& state) const;  // Σ γ_i / Σ m_i
  // E = Σ ‖γ_i‖²/2m_i + Σ ½ Π_kᵀ J_k⁻¹ Π_k + U.
  double energy(const State& state) const;
  // L = Σ (x_i − c) × (γ_i − m_i v_c) + Σ R_k Π_k, about the barycentre c in its own frame.
  Vec3 angular_momentum(const State& state) const;
};

}  // namespace noether
