// Continuing a run: Simulation::resume (an output file read back, verified and copied,
// docs/reliability.md "Checksums"), Simulation::save and Simulation::load (a checkpoint file).
#include <noether/error.hpp>
#include <noether/output.hpp>
#include <noether/simulation.hpp>
#include <noether/stepping.hpp>

#include "io/h5.hpp"
#include "io/checksum.hpp"
#include "io/file_access.hpp"
#include "io/read_probe.hpp"
#include "io/run_record.hpp"
#include "io/safe_publish.hpp"
#include "run/event_watch.hpp"
#include "run/simulation_impl.hpp"
#include "run/summary_schema.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <unistd.h>

namespace noether {

namespace {

// Frames [0, last] of a recorded run replayed into the simulation's statistics (and copied
// into its output file, if it has one), a block at a time. False when interrupted.
bool replay(const io::RunRecord& run, Simulation::Impl& m, std::size_t last,
            const volatile std::sig_atomic_t* interrupt) {
  Forces forces;  // frame 0's (what the scene conserves), then U alone
  State before;  // the frame before, and how many jumps (impulses) the features had made there
  std::size_t jumps = 0;
  return run.read(0, last + 1, [&](std::size_t k, const io::RecordedFrame& f) {
    if (k == 0) forces = m.forces_at(f.state);
    forces.U = f.U;
    // A jump between two frames at its time (the state before it, then after it): the
    // statistics' references move by it, as they did in the run (RunStatistics::impulse).
    const std::size_t jumps_here = m.jumps_in(f);
    if (k > 0 && jumps_here == jumps + 1) m.jumped(before, f.state, f.U);
    jumps = jumps_here;
    before = f.state;
    const Diagnostics d = m.observer->account(f.state, forces);
    if (!m.writer) return;
    // The frame as it was written: its tangent's STM and sensitivities (the features' columns
    // are their fields'), the features' series as they were.
    State state = f.state;
    state.tangent = m.recorded_tangent(f, run.file());
    std::vector<double> series;
    try {
      series = m.recorded_series(f);
    } catch (const Error& e) {
      throw Error(run.file().string() + ": " + e.what());
    }
    m.writer->write_frame(state, d, f.work, f.wall_seconds, f.interpolated, f.integrator, series, f.features);
  }, interrupt);
}

// Where the run's step grid starts: /checkpoint/t_origin, or (a file from before it was kept)
// the time of frame 0.
double origin_of(const io::RunRecord& run) {
  if (!std::isnan(run.t_origin)) return run.t_origin;
  double t0 = 0.0;
  run.read(0, 1, [&t0](std::size_t, const io::RecordedFrame& f) { t0 = f.state.t; });
  return t0;
}

// A fixed-step method's steps from the grid's origin to t.
std::int64_t steps_to(const Simulation::Impl& m, double t) {
  const double h = m.integrator->fixed_step();
  return h > 0 && t > m.t_origin ? whole_steps(t - m.t_origin, h, "the recorded time") : 0;
}

}  // namespace

std::unique_ptr<Simulation> Simulation::resume(const std::filesystem::path& file, PluginRegistry& registry,
                                               RunOptions options, double t_end) {
  // The file is read, verified frame by frame and copied into a new file that replaces it only
  // once every recorded frame is in (docs/user-guide.md, "Continuing a run"): a damaged file is
  // refused, and neither it nor an interrupted continuation is ever half-changed.
  // Every read below is made first in a child (io/read_probe.hpp): a damaged file must not crash
  // or hang this process.
  io::read_probe(file, [&file] {
    const io::RunRecord run(file);
    run.read(0, static_cast<std::size_t>(run.frames), [](std::size_t, const io::RecordedFrame&) {});
    run.read_step_records([](const StepSeries&) {});
  }, io::read_probe_seconds(file), options.interrupt);
  const io::RunRecord run(file);
  const std::string& outcome = run.outcome;
  std::vector<std::string> overrides = run.overrides;
  const bool extend = !std::isnan(t_end);
  if (extend) {
    std::ostringstream o;
    o.precision(17);
    o << "run.t_end=" << t_end;
    overrides.push_back(o.str());
  }
  if (run.custom_potential)
    throw Error(file.string() + ": the run's potential was given in code (a Python function), not by its scene, "
                "so it cannot be continued from the file alone; save() the Simulation and load() it with the potential");
  if (outcome.rfind("failed", 0) == 0)
    throw Error(file.string() + ": the run " + outcome +
                "; continuing it would fail again — change the scene and run it afresh");
  if (outcome.rfind("stopped: ", 0) == 0 && is_event(outcome.substr(9)))
    throw Error(file.string() + ": the run ended at an event (" + outcome.substr(9) + "); there is nothing to continue");
  if (!run.checksummed)
    spdlog::warn("{} was written by a noether without checksums: its frames are continued unverified (the "
                 "continued file has them)", file.string());
  Scene scene = parse_scene(run.scene_text, run.scene_path, overrides);
  if (scene.system.size() != run.bodies || scene.system.rigid_count() != run.rigid)
    throw Error(file.string() + ": its scene (" + run.scene_path + ") no longer gives the bodies the run had");
  const std::size_t last = static_cast<std::size_t>(run.frames - 1);
  io::RecordedFrame at_last;
  run.read(last, 1, [&at_last](std::size_t, const io::RecordedFrame& f) { at_last = f; });
  const double t_last = at_last.state.t, t_origin = origin_of(run);
  if (!(scene.run.t_end > t_last)) {
    std::ostringstream why;
    why.precision(10);
    why << file.string() << ": the run is already at t = " << t_last << ", its t_end"
        << (extend ? " is not later" : "; give a later --t-end to extend it");
    throw Error(why.str());
  }

  // The run rebuilt, its recorded frames replayed into the summary and copied into the new
  // file, block by block.
  const std::optional<std::filesystem::path> no_output;
  RunOptions rebuilt = options;
  rebuilt.output = no_output;
  auto sim = std::unique_ptr<Simulation>(new Simulation(std::move(scene), registry, rebuilt));
  Impl& m = *sim->impl_;
  for (const auto& f : m.features) f->continue_from(run, last, t_last);  // (or refused: nothing written)
  m.new_segment();
  m.t_origin = t_origin;
  const Scene& sc = m.scene;
  OutputOptions output = m.output_options(true);
  char line[128];
  std::snprintf(line, sizeof line, "frame %zu at t = %.17g", last, t_last);
  output.resumed = run.resumed + (run.resumed.empty() ? "" : "\n") + line;
  m.writer = std::make_unique<H5Writer>(file, sc, output);
  if (!replay(run, m, last, options.interrupt)) {
    m.writer.reset();  // the new file is dropped; the old one was only read
    throw Error(file.string() + " was being read back when the continuation was interrupted; it is unchanged");
  }
  run.read_step_records([&m](const StepSeries& records) { m.writer->append_step_series({records}); });
  m.pair_models_before = run.pair_models;  // a tolerance exceeded before the break stays reported
  m.summary.pair_models = m.pair_models();
  m.writer->write_pair_models(m.summary.pair_models);
  m.writer->publish();

  m.summary.interpolated_frames = at_last.interpolated;
  m.steps_before = steps_to(m, t_last);
  m.restore(at_last, file);
  for (const auto& f : m.features) {  // what they keep beside their fields, in the new file from now on
    f->save_into(*m.writer, static_cast<std::int64_t>(last));
    f->keep_with(*m.writer);
  }
  m.options = std::move(options);
  m.options.output = file;
  return sim;
}
// Saving and loading ------------------------------------------------------------------------
// A saved simulation is an output file with one frame, the state where it stood, plus
// /checkpoint/summary: the summary's running values.
// Simulation::load reads it (or any output file) through the same RunRecord as --resume.
namespace {

// A saved simulation's summary rows and running values, as /checkpoint/summary holds them.
detail::SavedSummary saved_of(const io::RunRecord& run) {
  return detail::upgrade_saved_summary({run.summary_numbers, run.summary_texts});
}

}  // namespace

void Simulation::save(const std::filesystem::path& path) const {
  const Impl& m = *impl_;
  if (m.scene.text.empty())
    throw Error("save: this simulation's scene has no text to save (it was not read from YAML)");
  for (const auto& f : m.features) f->refuse_save(m.state);
  // The file is built under a hidden name and published once complete (io/safe_publish.hpp):
  // a kill while saving leaves the previous checkpoint; a link, or the simulation's own output
  // file, is refused.
  OutputOptions output = m.output_options(false);
  output.overwrite = true;
  output.defer_publish = true;
  output.expected_frames = 1;
  output.inputs.clear();
  if (m.options.output) output.inputs.push_back(*m.options.output);
  H5Writer writer(path, m.scene, output);
  const Forces forces = m.forces_at(m.state);  // U at the state saved (the frame's potential energy)
  const WorkCounters work = m.work();
  const double wall = m.wall_now();
  writer.write_frame(m.state, diagnose(m.scene.system, m.state, forces.U), work, wall, m.summary.interpolated_frames,
                     m.integrator->checkpoint(), m.series_values(m.state), m.feature_values(m.state));
  writer.flush();
  // The summary's checkpointed rows (run/summary_schema.cpp) and the statistics' running values.
  detail::SavedSummary saved = detail::save_summary(m.summary);
  m.observer->save(saved, !m.scene.forces.empty());  // the forces' balance is the state's; their largest exchange is not (33.3)
  for (const auto& f : m.features) f->save_running(saved);
  for (const auto& f : m.features) f->save_into(writer, 0);
  writer.write_pair_models(m.pair_models());  // with a tolerance exceeded so far, which load keeps
  writer.write_summary_values(saved.numbers, saved.texts);
  writer.publish();
  char outcome[96];
  std::snprintf(outcome, sizeof outcome, "saved at t = %.17g", m.state.t);
  writer.finish(work, wall, outcome);
}

std::unique_ptr<Simulation> Simulation::load(const std::filesystem::path& path, PluginRegistry& registry,
                                             RunOptions options, std::shared_ptr<const Potential> potential) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw OutputError(path.string() + ": no such file");
  // Every read made first in a child: a damaged file must not crash or hang this process.
  io::read_probe(path, [&path] {
    const io::RunRecord run(path);
    run.read(0, static_cast<std::size_t>(run.frames), [](std::size_t, const io::RecordedFrame&) {});
  }, io::read_probe_seconds(path), options.interrupt);
  const io::RunRecord run(path);
  if (run.custom_potential && !potential)
    throw Error(path.string() + " was saved from a simulation whose potential was given in code (a Python "
                                "function), not by the scene: pass the same potential to load it");
  Scene scene = parse_scene(run.scene_text, run.scene_path, run.overrides);
  if (scene.system.size() != run.bodies || scene.system.rigid_count() != run.rigid)
    throw Error(path.string() + ": its scene (" + run.scene_path + ") no longer gives the bodies the run had");
  const std::size_t last = static_cast<std::size_t>(run.frames - 1);
  io::RecordedFrame at_last;
  run.read(last, 1, [&at_last](std::size_t, const io::RecordedFrame& f) { at_last = f; });
  // The particles made where the file has them at that frame (not at the scene's start, where
  // the bodies no longer are); the features check what they keep below.
  if (!scene.particles.empty() && run.particles && run.particles->t == at_last.state.t)
    scene.particles.restored = std::make_shared<const ParticleCheckpoint>(*run.particles);
  const bool with_output = options.output.has_value();
  // A new file's summary starts at the loaded state: what the forces put in, with it (as set_state).
  if (with_output && !scene.forces.empty()) at_last.state.force_balance.setZero();
  scene.models_chosen_at = scene.initial;  // the run's models, chosen where it started
  scene.initial = at_last.state;            // frame 0 of the loaded simulation is where the file stood
  // A new output file is opened once the run stands where the file stood (below): its frame 0
  // holds the restored integrator, tangent and features, not those of a fresh start there.
  RunOptions unwritten = options;
  unwritten.output.reset();
  auto sim = std::make_unique<Simulation>(std::move(scene), registry, unwritten, std::move(potential));
  Impl& m = *sim->impl_;
  RunSummary& s = m.summary;
  for (const auto& f : m.features) f->continue_from(run, last, at_last.state.t);
  m.scene_trajectory = false;  // (its scene starts where the file stood)
  m.t_origin = origin_of(run);
  m.steps_before = steps_to(m, at_last.state.t);
  if (!with_output && run.saved()) {  // the saved summary, not the frame the constructor observed
    try {
      const detail::SavedSummary saved = saved_of(run);
      detail::restore_summary(s, saved);
      m.observer->restore(saved, !m.scene.forces.empty());
      for (const auto& f : m.features) f->restore_running(saved);
    } catch (const Error& e) {
      throw Error(path.string() + ": " + e.what() +
                  "; load it with an output file (its summary then starts there) or run the scene again");
    }
    s.interpolated_frames = at_last.interpolated;
    m.pair_models_before = run.pair_models;
    s.pair_models = m.pair_models();
  } else if (!with_output) {  // a run's file: its frames replayed into the summary, as --resume does
    m.new_segment();
    replay(run, m, last, options.interrupt);
    s.interpolated_frames = at_last.interpolated;
  }
  m.restore(at_last, path);
  if (with_output) {  // the new file, its summary from here (frame 0, with the potential's forces)
    m.writer = std::make_unique<H5Writer>(*options.output, m.scene, m.output_options(false));
    m.writer->write_pair_models(m.summary.pair_models);
    m.keep_features_with_writer();
    m.new_segment();
    m.observer->observe(m.state, m.forces_at(m.state), false);
  }
  m.options = std::move(options);
  return sim;
}
}  // namespace noether
