#pragma once
// The driver's commands, one file each: run.cpp (run, plugins), compare.cpp, ensemble.cpp,
// orbit.cpp (orbit and its subcommands), check_potential.cpp, observe.cpp, fit.cpp, shape.cpp, view.cpp, export.cpp. Each file registers its command
// and options (add_*_command); main() parses and runs the one chosen. Each command returns the
// process exit code; noether::Error escapes to main().
#include <noether/potential_check.hpp>

#include <noether/scene.hpp>

#include <complex>
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace noether::app {

// The command the user chose, ready to run: returns the exit code.
using Command = std::function<int()>;
// Each adds its subcommand, with its options, to `app`; when the user chooses it, `chosen`
// becomes the call that runs it.
void add_run_command(CLI::App& app, Command& chosen);
void add_plugins_command(CLI::App& app, Command& chosen);
void add_compare_command(CLI::App& app, Command& chosen);
void add_ensemble_command(CLI::App& app, Command& chosen);
void add_orbit_command(CLI::App& app, Command& chosen);
void add_check_potential_command(CLI::App& app, Command& chosen);
void add_observe_command(CLI::App& app, Command& chosen);
void add_fit_command(CLI::App& app, Command& chosen);
void add_shape_command(CLI::App& app, Command& chosen);
void add_view_command(CLI::App& app, Command& chosen);
void add_export_command(CLI::App& app, Command& chosen);

// One line per solid body: its shape, mass, density and, for a mesh, where its centre of
// mass was in the file and by how much it was rotated onto its principal axes.
void print_shapes(const noether::Scene& scene, std::ostream& out);

// SIGINT/SIGTERM stop the run after the current step: summary printed, output complete,
// exit 128 + the signal (130, 143).
// A wall-time budget (seconds, 0: none) stops the run like an event: exit 0, stop reason in the
// summary and the output, a note on stderr.
// With `resume` (an output file) instead of a scene: continues that run, appending to it;
// `resume_t_end` (NaN: the recorded t_end) extends it. `threads`: RunOptions::threads.
int run(const std::string& scene_file, const std::string& output,
        const std::vector<std::string>& overrides, bool progress, bool force, bool json = false,
        double max_wall_time = 0.0, const std::string& resume = {},
        double resume_t_end = std::numeric_limits<double>::quiet_NaN(), int threads = 0);
int list_plugins();

// noether ensemble: exit 0 when every sample ran (completed or stopped by an event), 3 when
// some failed (each recorded with its message), 2 for a bad specification (before any run).
struct EnsembleCommand {
  std::string output;
  std::size_t samples = 0;
  std::uint64_t seed = 1;
  unsigned threads = 0;
  std::string pair;
  std::size_t trajectories = 0;
  bool resume = false, force = false;
  std::string from_fit;  // a fit's JSON: its keys drawn jointly from its estimate and covariance
};
int ensemble(const std::string& scene_file, const std::vector<std::string>& overrides,
             const std::vector<std::string>& vary, const EnsembleCommand& command);

// The folder of the helper scripts (plot_compare.py, plot_orbit.py): <prefix>/share/noether
// when installed, the source tree's tools/ in a build.
std::string script_dir();
// Runs a helper script with Debian's /usr/bin/python3 (the PATH's python3 where there is none)
// and an argument vector (no shell); false when it cannot be run or fails. `shown` is the
// command, for messages.
bool run_plot_script(const std::string& script, const std::vector<std::string>& args, std::string& shown);
// The data file drawn into a picture: PNG with the extension .csv (next to it).
std::string csv_beside(const std::string& png);
// run_plot_script(script, args) drawing `png`: prints "plot: PNG", or a note on stderr naming the
// command and the data kept (`data`) when the picture cannot be drawn. False then.
bool draw_plot(const std::string& script, const std::vector<std::string>& args, const std::string& png,
               const std::string& data);
// Writes a spectrum (complex values, each with a label) to csv_beside(png) and draws it with
// plot_spectrum.py: `kind` "multipliers" (unit circle) or "eigenvalues" (divided by `scale`, with
// the imaginary axis). Prints "plot: PNG"; a picture that cannot be drawn is a note on stderr
// (the CSV stays); a CSV that cannot be written throws OutputError.
void plot_spectrum(const std::string& png, const std::vector<std::complex<double>>& values,
                   const std::vector<std::string>& labels, const std::string& kind, double scale,
                   double tolerance, const std::string& title);

int compare(const std::string& scene_file, const std::vector<std::string>& overrides,
            const std::vector<std::string>& runs, const std::vector<std::string>& models,
            const std::string& reference_model, const std::string& spec_file, int repeats,
            std::string csv, std::string h5, std::string png, bool plot, double max_wall_time = 0.0);

struct OrbitOptions {
  std::string scene;
  std::vector<std::string> overrides;
  double period = 0;  // 0: the scene's run.t_end
  double rtol = 1e-13, tolerance = 1e-6;
  int first_order = 0;
  std::string output;
  // find
  std::vector<double> masses;
  int bodies = 3, modes = 15, points = 0, starts = 20;
  bool bodies_given = false;  // --bodies on the command line (refused with --scene)
  unsigned seed = 1;
  bool choreography = false, refine = true;
  double max_residual = 1e-2;
  std::string out_dir = ".";
  // equilibrium
  std::string fix = "separation";  // separation | angular-momentum | rate
  double value = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> pair;   // two body names or indices
  std::vector<double> sweep;       // from, to, count
  std::string sweep_key;           // a scene key the sweep varies instead (the family member held)
  bool align = true;
  int angle_turns = 0;  // whole turns added to the measured α (stability of rigid bodies)
  std::string plot;     // stability, equilibrium: the picture (PNG; its data as the .csv beside it)
  std::vector<std::string> libration;  // equilibrium -o: NAME, DEG: that body turned about k̂
  std::vector<std::string> lyapunov;   // equilibrium: NAME, DEG: the Lyapunov orbit of NAME's libration
};
int orbit_find(OrbitOptions options);
int orbit_verify(const OrbitOptions& options);
int orbit_stability(const OrbitOptions& options);
int orbit_refine(const OrbitOptions& options);
int orbit_equilibrium(const OrbitOptions& options);
// orbit stability on a scene with rigid bodies (the scene orbit_stability read): a relative
// periodic orbit of its integrator's map.
int orbit_rigid_stability(const OrbitOptions& options, noether::Scene scene);
// orbit verify / refine on a scene with rigid bodies: closure up to a turn about k̂; shooting.
int orbit_rigid_verify(const OrbitOptions& options, noether::Scene scene);
int orbit_rigid_refine(const OrbitOptions& options, noether::Scene scene);

int check_potential(const std::string& scene_file, const std::vector<std::string>& overrides,
                    const noether::PotentialCheckOptions& options);

}  // namespace noether::app
