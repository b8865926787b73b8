#pragma once
// The frame schema: every series of an output file that holds one value per output frame — its
// path, its shape, its unit, what it is and how it is computed — as one table (kFrameSchema,
// frame_schema.cpp). It drives everything that touches frames: the writer creates the series
// and fills each frame from it (output_layout.cpp, output.cpp), a continued run reads its
// checkpointed rows back (run_record.cpp), the Python module hands it out
// (`noether.output_series()`), and the files' series, the Python reader's list and
// docs/user-guide.md's layout are tested against it (tests/python/test_output.py). Adding an
// output quantity is one row here plus the function that computes it (docs/architecture.md,
// "Where to add").
#include <noether/diagnostics.hpp>
#include <noether/integrator.hpp>
#include <noether/output.hpp>
#include <noether/state.hpp>
#include <noether/system.hpp>
#include <noether/units.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace noether::io {

// What one frame's quantities of the state alone are computed from: t, x, γ, R and Π (what the
// checkpointed series hold) and the bodies. They are computed on the block writer's thread from
// the frame as a continued run reads it back (RecordedFrame), so the run's own thread only copies
// the state.
struct StateFrame {
  const System& system;
  std::ptrdiff_t primary = -1, secondary = -1;  // the binary of a two-body-like scene (binary_pair.hpp)
  const State& state;
  // Each rigid body's axis of largest moment (the nutation angle's, eq. 17.11), found once per run
  // rather than by an eigensolver every frame.
  const std::vector<Vec3>& largest_moment_axes;
};

// What one frame is made of: the state and what the run knows about it at that moment.
struct FrameInput {
  const State& state;
  const Diagnostics& diagnostics;
  const WorkCounters& work;
  std::int64_t interpolated = 0;  // frames interpolated between the method's steps so far
  double wall_seconds = 0.0;
  const std::vector<double>& integrator;  // Integrator::checkpoint()
  std::size_t stm_columns = 0;  // the state-transition matrix's columns of State::tangent (first), 0: none
  std::size_t sensitivity_columns = 0;  // the sensitivities' columns of State::tangent (last), 0: none
  // The run features' checkpointed fields where the run stands (run/run_feature.hpp; none: empty).
  std::span<const double> features = {};
};

// The series a run feature fills (RunFeature::series: the chaos indicators, the particles'
// positions), which the writer copies from the values the run hands it with each frame.
struct ByFeature {};
inline constexpr ByFeature kByFeature{};

// How one frame of a series is computed: from what the run hands the writer (`of_run`, on the
// run's thread as the frame arrives) or from the state alone (`of_state`, when its block is
// written). The table names the function; its parameter type says which it is.
struct FrameFill {
  using OfRun = void (*)(const FrameInput& in, void* out);
  using OfState = void (*)(const StateFrame& in, void* out);
  constexpr FrameFill(OfRun f) : of_run(f) {}      // NOLINT: implicit, so that a table row names the function
  constexpr FrameFill(OfState f) : of_state(f) {}  // NOLINT: idem
  constexpr FrameFill(ByFeature) : by_feature(true) {}  // NOLINT: idem
  OfRun of_run = nullptr;
  OfState of_state = nullptr;
  bool by_feature = false;
};

// One frame read back from a file: the exact state (γ and R, not the derived v and q), U, and
// where the run stood (work, wall time, the integrator's own variables).
struct RecordedFrame {
  State state;
  double U = 0.0;
  WorkCounters work;
  std::int64_t interpolated = 0;
  double wall_seconds = 0.0;
  std::vector<double> integrator;
  // The run features' checkpointed series (the particles' positions), by their names in the
  // schema: each frame's numbers, row-major.
  std::vector<std::pair<std::string, std::vector<double>>> series;
  // The tangent's state-transition matrix and sensitivities (run.stm, run.sensitivities; empty
  // without), and the run features' checkpointed fields (run/run_feature.hpp; empty without).
  Eigen::MatrixXd stm, sensitivity;
  std::vector<double> features;
  // A feature's series read back (empty: the file has no such series).
  std::span<const double> series_named(std::string_view name) const;
  void set_series(std::string_view name, const double* values, std::size_t count);
};

// The shape of one frame of a series (the file's dataset is [frame] followed by it).
enum class Extent {
  kStepCount,        // [] int64: the integrator's step count
  kScalar,           // []
  kVector,           // [3]
  kBodyVector,       // [body][3]
  kRigidScalar,      // [rigid body]             (present when the scene has rigid bodies)
  kRigidVector,      // [rigid body][3]          (idem)
  kRigidQuaternion,  // [rigid body][4]          (idem)
  kRigidMatrix,      // [rigid body][3][3]       (idem)
  kWork,             // [5] int64: steps, evaluations, Newton iterations, rejections, interpolated
  kIntegrator,       // [width]: Integrator::checkpoint() (present when its width is not 0)
  kBinaryScalar,     // []      the binary of a two-body-like scene (present when there is one)
  kBinaryVector,     // [3]     idem
  kBinaryElements,   // [6]     idem: a, e, i, Ω, ω, ν
  kPrimaryFrame,     // [3]     idem, when the primary is rigid: a vector in its body frame
  kSecondaryAngle,   // []      idem, when the secondary is rigid
  kSecondaryVector,  // [3]     idem
  kTangent,          // [coordinate][coordinate]: the STM, State::tangent's first columns (run.stm)
  kSensitivity,      // [coordinate][parameter]: State::tangent's last columns (run.sensitivities)
  kChaos,            // []: a chaos indicator (run.chaos; filled by its feature)
  kForceBalance,     // [force][7]: State::force_balance (the scene's `forces:`)
  kParticleVector,   // [recorded particle][3]: the scene's first particles.record particles (idem)
  kRunFeatures,      // [field]: the run features' checkpointed fields (present when they have any)
};

// What decides which series a file has, and their shapes.
struct FrameLayout {
  std::size_t bodies = 0, rigid = 0, width = 0;  // width: Integrator::checkpoint()'s size
  std::size_t stm_columns = 0;          // State::tangent's columns of the STM (0: run.stm off)
  std::size_t sensitivity_columns = 0;  // its last columns (run.sensitivities)
  std::size_t forces = 0;               // forces beyond the potential (State::force_balance's columns)
  // The series the run features fill (FrameFill::by_feature), by name, with their frame shapes;
  // a series of the schema filled by a feature is present when one declares it.
  std::vector<FeatureSeries> feature_series;
  std::size_t features = 0;             // the run features' checkpointed fields (run/run_feature.hpp)
  bool binary = false, primary_rigid = false, secondary_rigid = false;
};

// The unit, as the scene's units spell it (docs/user-guide.md, "Units").
enum class Dimension { kOne, kTime, kLength, kVelocity, kMomentum, kAngularMomentum, kEnergy, kAngularVelocity, kWallSeconds, kDegrees, kMixed };

enum class Element {
  kH5md,   // an H5MD time series: <group>/{step,time,value}, step and time hard links to position's
  kPlain,  // a dataset of its own (/checkpoint)
};

struct FrameQuantity {
  const char* name;  // the Python reader's name (noether.read(...)[name])
  const char* path;  // the dataset
  Extent extent;
  Dimension unit;
  Element element;
  const char* description;
  // The column of /checkpoint/checksum holding this series' frame checksums, for the series a
  // continued run reads back (−1: not read back). Columns are part of the file format.
  int checksum_column;
  // Writes one frame into `out` (double numbers, or int64 for kStepCount and kWork); every
  // number of it, since the frame's memory is not cleared first.
  FrameFill fill;
  // The checkpointed series: puts one frame read back into the run's frame (nullptr otherwise;
  // a series filled by a feature is put into RecordedFrame::series by its name).
  void (*restore)(const void* values, std::size_t width, RecordedFrame& frame);
};

// Every series, in the order the file's groups are created.
std::span<const FrameQuantity> frame_schema();
// The series a continued run reads back, in the order of /checkpoint/checksum's columns.
std::vector<const FrameQuantity*> checkpointed_series();
inline constexpr const char* kChecksumPath = "/checkpoint/checksum";

// Whether the series is written for a scene of this layout, and its frame shape.
bool present(const FrameQuantity& q, const FrameLayout& layout);
std::vector<std::size_t> frame_shape(const FrameQuantity& q, const FrameLayout& layout);
// The layout of a scene whose integrator's checkpoint has `width` numbers and whose states carry
// a tangent of `stm_columns` + (the features' columns) + `sensitivity_columns` columns.
FrameLayout layout_of(const System& system, std::size_t width, std::size_t stm_columns = 0,
                      std::size_t sensitivity_columns = 0, std::size_t forces = 0,
                      std::vector<FeatureSeries> feature_series = {}, std::size_t features = 0);
// The declared series filled by a feature, if `layout` has it (null otherwise).
const FeatureSeries* feature_series(const FrameQuantity& q, const FrameLayout& layout);
// How many dimensions a frame of the series has (the brackets of describe_extent, less [frame]).
std::size_t frame_rank(Extent e);
bool rigid_only(const FrameQuantity& q);  // written only when the scene has rigid bodies
bool optional(const FrameQuantity& q);    // written only for an integrator with variables of its own
bool binary_only(const FrameQuantity& q); // written only for a two-body-like scene (binary_pair.hpp)
std::string requirement(const FrameQuantity& q);  // what a scene needs for it: "" (always), "rigid bodies", …
bool is_integer(const FrameQuantity& q);  // int64 values (step, work), else double
std::string unit_of(Dimension d, const Units& units);
std::string describe_extent(Extent e);  // "[frame][body][3]"

}  // namespace noether::io
