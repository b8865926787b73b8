#pragma once
// View: a run's output file as one self-contained HTML page that shows the bodies moving in 3-D
// — their shapes (polyhedra, ellipsoids, sphere clusters, point masses as dots), attitudes,
// trails, a time slider — with three.js, embedded at build time from Debian's libjs-three, so
// that the page needs no server and no network (docs/visualisation.md).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace noether {

struct ViewOptions {
  // At most this many frames go into the page (≥ 2): a longer run is decimated to frames taken
  // evenly by index, the first and the last always among them (docs/visualisation.md, "Size").
  std::size_t max_frames = 5000;
  std::string title;  // "": the file's name
  // The page's parameters when its address gives none (docs/visualisation.md, "Parameters"):
  // "view=frame:alpha&axes=1"; the address's own override them. SceneError for a key the page
  // does not know or a view of no such body.
  std::string params;
  // With an ensemble's file (noether ensemble -o ENS.h5): the samples whose runs the page shows
  // together — ENS-sample-I.h5 beside it, which `noether ensemble --trajectories K` writes for
  // the first K —; empty: each such run there is, from sample 0, at most 8.
  std::vector<std::size_t> samples;
};

// What view_html made, for the command to report.
struct ViewReport {
  std::size_t frames_in_file = 0, frames_shown = 0;  // of the first run
  std::vector<std::filesystem::path> runs;           // every run shown
  std::size_t bytes = 0;                             // the page's size
  // Things the page shows differently from the run, also shown in the page: a run killed before
  // its end, a rigid body drawn as its inertia ellipsoid because its scene's cluster could not
  // be read, …
  std::vector<std::string> notes;
};

// Whether this build has three.js to embed (false: built without libjs-three).
bool view_available();

// The page for `runs` (outputs of `noether run`, or saved simulations): the first drawn opaque,
// the others translucent at the same frames (each until its last), all watched from the first's
// frame. An ensemble's file alone stands for its samples' runs (ViewOptions::samples).
// OutputError for a file that is not a run's output or is damaged, runs of other bodies or other
// frame times; Error when this build has no three.js (view_available()); SceneError for
// max_frames < 2, --samples without an ensemble, parameters the page does not know.
std::string view_html(const std::vector<std::filesystem::path>& runs, const ViewOptions& options = {},
                      ViewReport* report = nullptr);
std::string view_html(const std::filesystem::path& run_file, const ViewOptions& options = {},
                      ViewReport* report = nullptr);

// view_html written to `page` as noether writes every output file (docs/user-guide.md, "Output
// files"): an existing page only with `force`, never through a link or onto a run, built under a
// hidden name and renamed into place.
ViewReport write_view(const std::vector<std::filesystem::path>& runs, const std::filesystem::path& page,
                      const ViewOptions& options, bool force);

}  // namespace noether
