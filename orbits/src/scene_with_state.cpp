#include <noether/scene_with_state.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace noether {

namespace {

Params number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return Params::scalar(buf);
}

Params vector(const Vec3& v) { return Params::sequence({number(v.x()), number(v.y()), number(v.z())}); }

}  // namespace

std::string scene_with_state(const Scene& scene, const State& state, double t_end, int frames,
                             const std::string& description) {
  static const char* state_keys[] = {"position", "velocity", "attitude", "angular_velocity", "angular_momentum",
                                     "orbit", "relative_to"};
  Scene out = scene;
  std::vector<std::pair<std::string, Params>> root;
  for (const auto& [key, value] : scene.root.entries()) {
    if (key == "barycentric" || key == "description") continue;
    if (key != "bodies") {
      root.emplace_back(key, value);
      continue;
    }
    std::vector<Params> bodies;
    for (std::size_t i = 0; i < value.items().size(); ++i) {
      std::vector<std::pair<std::string, Params>> body;
      for (const auto& [k, v] : value.items()[i].entries()) {
        bool is_state = false;
        for (const char* s : state_keys) is_state |= k == s;
        if (!is_state) body.emplace_back(k, v);
      }
      const auto j = static_cast<Eigen::Index>(i);
      const Body& b = scene.system.body(i);
      body.emplace_back("position", vector(state.x.col(j)));
      body.emplace_back("velocity", vector(state.p.col(j) / b.mass));
      if (b.rigid) {
        const int r = scene.system.rigid_index(i);
        const Mat3& R = state.R[static_cast<std::size_t>(r)];
        body.emplace_back("attitude", Params::map({{"matrix", Params::sequence({vector(R.row(0)), vector(R.row(1)),
                                                                                  vector(R.row(2))})}}));
        body.emplace_back("angular_velocity", vector(b.inertia_inverse * state.Pi.col(r)));
      }
      bodies.push_back(Params::map(std::move(body)));
    }
    root.emplace_back("bodies", Params::sequence(std::move(bodies)));
  }
  root.insert(root.begin(), {"description", Params::scalar(description)});
  Params run = scene.root.has("run") ? scene.root.at("run") : Params::map({});
  run.set("t_end", number(t_end));
  run.set("output_every", number(t_end / frames));
  for (auto& [key, value] : root) {
    if (key == "run") value = run;
    if (key == "integrator") value = scene.integrator.params;  // as the caller may have changed it (a step)
    // A fixed step: the nearest shorter one that puts a whole number of steps in every frame.
    if (key == "integrator" && value.is_map() && value.has("step")) {
      const double per_frame = std::max(1.0, std::ceil(t_end / frames / value.at("step").as_double() - 1e-9));
      value.set("step", number(t_end / (frames * per_frame)));
    }
  }
  out.root = Params::map(std::move(root));
  return scene_as_run(out);
}

int frames_keeping_step(const Scene& scene, double t_end) {
  const int target = static_cast<int>(std::clamp(std::round(t_end / scene.run.output_every), 1.0, 1e4));
  if (!scene.integrator.params.has("step")) return target;
  const double steps = t_end / scene.integrator.params.at("step").as_double();
  const long N = std::lround(steps);
  if (N < 1 || std::abs(steps - static_cast<double>(N)) > 1e-9 * steps) return target;
  for (long f = std::min<long>(target, N); f > 1; --f)
    if (N % f == 0) return static_cast<int>(f);
  return 1;
}

}  // namespace noether
