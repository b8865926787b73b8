// HDF5 output: the layout of docs/user-guide.md, and a run killed with SIGKILL half way leaves a
// file h5dump reads, every series of one length, its first /frames_complete frames complete.
#include "test_support.hpp"

#include <noether/diagnostics.hpp>
#include <noether/output.hpp>
#include <noether/simulation.hpp>
#include <noether/euler_angles.hpp>
#include <noether/lie.hpp>

#include "io/checksum.hpp"
#include "io/safe_publish.hpp"
#include "io/superblock.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <bit>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <sys/wait.h>
#include <thread>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

using namespace noether;
namespace fs = std::filesystem;

namespace {

std::vector<hsize_t> dims(hid_t file, const char* path) {
  hid_t d = H5Dopen2(file, path, H5P_DEFAULT);
  EXPECT_GE(d, 0) << path;
  if (d < 0) return {};
  hid_t space = H5Dget_space(d);
  std::vector<hsize_t> out(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, out.data(), nullptr);
  H5Sclose(space);
  H5Dclose(d);
  return out;
}

std::vector<double> read_doubles(hid_t file, const char* path) {
  const auto n = dims(file, path);
  std::size_t count = 1;
  for (auto v : n) count *= v;
  std::vector<double> out(count);
  hid_t d = H5Dopen2(file, path, H5P_DEFAULT);
  if (count) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Dclose(d);
  return out;
}

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / (name + "-" + std::to_string(getpid()) + ".h5");
}

}  // namespace

TEST(Output, LayoutAndContents) {
  const fs::path file = temp_file("noether-layout");
  auto registry = test::bundled_plugins();
  RunOptions options;
  options.output = file;
  const RunSummary s = run_scene(test::dumbbell_scene({"run.t_end=1"}), registry, options);
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(dims(f, "/particles/bodies/position/value"), (std::vector<hsize_t>{101, 2, 3}));
  EXPECT_EQ(dims(f, "/particles/bodies/orientation/value"), (std::vector<hsize_t>{101, 2, 4}));
  EXPECT_EQ(dims(f, "/observables/energy/time"), (std::vector<hsize_t>{101}));
  const auto energy = read_doubles(f, "/observables/energy/value");
  EXPECT_DOUBLE_EQ(energy.front(), s.initial.energy);
  const auto time = read_doubles(f, "/particles/bodies/velocity/time");
  EXPECT_NEAR(time.back(), 1.0, 1e-12);
  const auto q = read_doubles(f, "/particles/bodies/orientation/value");
  for (std::size_t i = 0; i < q.size(); i += 4)
    EXPECT_NEAR(std::hypot(std::hypot(q[i], q[i + 1]), std::hypot(q[i + 2], q[i + 3])), 1.0, 1e-14);
  const auto v = read_doubles(f, "/particles/bodies/velocity/value");
  EXPECT_NEAR(v[1], 0.67, 1e-15);  // alpha's initial v_y
  EXPECT_TRUE(H5Lexists(f, "/work", H5P_DEFAULT) > 0);
  std::int64_t complete = -1;
  hid_t counter = H5Dopen2(f, "/frames_complete", H5P_DEFAULT);
  H5Dread(counter, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &complete);
  H5Dclose(counter);
  EXPECT_EQ(complete, 101);  // a finished run's series hold exactly the complete frames
  H5Fclose(f);
  fs::remove(file);
}

TEST(Output, SigkillLeavesAReadableFile) {
  const fs::path file = temp_file("noether-killed");
  fs::remove(file);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string scene = test::source_path("examples/dumbbells.yaml");
    const int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, STDOUT_FILENO);
    dup2(devnull, STDERR_FILENO);
    execl(NOETHER_EXECUTABLE, "noether", "run", scene.c_str(), "-o", file.c_str(), "--set",
          "run.t_end=100000", "--no-progress", static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  ASSERT_EQ(kill(child, SIGKILL), 0);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";

  const std::string h5dump = "h5dump -H " + file.string() + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(h5dump.c_str()), 0) << "h5dump cannot read the killed run's file";

  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  // Every series has one length (allocated up front); /frames_complete counts the frames that
  // are complete, and those are real frames.
  std::int64_t complete = -1;
  hid_t counter = H5Dopen2(f, "/frames_complete", H5P_DEFAULT);
  ASSERT_GE(counter, 0);
  H5Dread(counter, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &complete);
  H5Dclose(counter);
  const auto time = read_doubles(f, "/particles/bodies/position/time");
  const std::size_t n = static_cast<std::size_t>(complete);
  EXPECT_GE(n, 200u) << "fewer frames than 2.5 s of running should have flushed";
  ASSERT_LE(n, time.size());
  for (std::size_t k = 0; k < n; ++k) ASSERT_NEAR(time[k], 0.01 * static_cast<double>(k), 1e-9);
  EXPECT_EQ(dims(f, "/particles/bodies/position/value")[0], time.size());
  EXPECT_EQ(dims(f, "/particles/bodies/orientation/value")[0], time.size());
  EXPECT_EQ(dims(f, "/observables/energy/value")[0], time.size());
  const auto energy = read_doubles(f, "/observables/energy/value");
  for (std::size_t k = 0; k < n; ++k) ASSERT_NEAR(energy[k], 0.44068740, 1e-6);  // real frames
  EXPECT_FALSE(H5Lexists(f, "/work", H5P_DEFAULT) > 0);     // the run never finished
  H5Fclose(f);
  fs::remove(file);
}

// The end of allocation a superblock records, rewritten in place before each flush
// (docs/reliability.md, "Kills"): HDF5 accepts the rewritten superblock (its lookup3 checksum
// verifies) and reads back the recorded end; a file it does not recognise is left unchanged.
TEST(Output, SuperblockRecordsARewrittenEndOfAllocation) {
  const fs::path file = temp_file("noether-superblock");
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_V110);
  hid_t f = H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  ASSERT_GE(f, 0);
  hid_t g = H5Gcreate2(f, "g", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(g);
  haddr_t eoa = 0;
  ASSERT_GE(H5Fget_eoa(f, &eoa), 0);
  H5Fclose(f);
  const std::uint64_t end = eoa + 65536;
  {
    const int fd = open(file.c_str(), O_RDWR);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(ftruncate(fd, static_cast<off_t>(end)), 0);
    EXPECT_TRUE(io::record_end_of_allocation(fd, end));
    close(fd);
  }
  f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, fapl);
  ASSERT_GE(f, 0) << "HDF5 refuses the rewritten superblock";
  haddr_t recorded = 0;
  H5Fget_eoa(f, &recorded);
  EXPECT_EQ(recorded, end);
  EXPECT_GT(H5Lexists(f, "g", H5P_DEFAULT), 0);
  H5Fclose(f);
  H5Pclose(fapl);
  {  // not an HDF5 file: refused, unchanged
    const int fd = open(file.c_str(), O_RDWR | O_TRUNC);
    ASSERT_EQ(write(fd, "not an HDF5 file, long enough to hold a superblock's 48 bytes", 61), 61);
    EXPECT_FALSE(io::record_end_of_allocation(fd, end));
    char back[8] = {};
    ASSERT_EQ(pread(fd, back, 7, 0), 7);
    EXPECT_STREQ(back, "not an ");
    close(fd);
  }
  fs::remove(file);
}

// A run killed while it built its file leaves .<name>.partial-<pid>; a later run that gets the
// same pid (pids are reused: CI found one after a few thousand processes) removes that stale
// file and builds its own, but never one whose writer still holds its lock.
TEST(Output, AStalePartialFileOfAReusedPidIsReplaced) {
  const fs::path path = temp_file("noether-stale-partial");
  const fs::path partial = io::partial_name(path);
  fs::remove(path);
  {
    const int fd = open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(write(fd, "stale", 5), 5);
    close(fd);
  }
  const int fd = io::create_partial(partial, path);
  ASSERT_GE(fd, 0);
  EXPECT_EQ(fs::file_size(partial), 0u) << "the stale file was not replaced";
  // Now locked by this writer (create_partial holds its lock): a second writer is refused, and
  // the file stays.
  try {
    io::create_partial(partial, path);
    ADD_FAILURE() << "a partial file whose writer holds its lock was taken over";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("File exists"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(partial));
  close(fd);
  fs::remove(partial);
}

namespace {

// Every numeric dataset of a file, by path: its bytes as 8-byte words.
std::map<std::string, std::vector<std::uint64_t>> numeric_datasets(const fs::path& path) {
  std::map<std::string, std::vector<std::uint64_t>> out;
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << path;
  H5Ovisit(
      f, H5_INDEX_NAME, H5_ITER_NATIVE,
      [](hid_t root, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        if (info->type != H5O_TYPE_DATASET) return 0;
        hid_t d = H5Dopen2(root, name, H5P_DEFAULT);
        hid_t type = H5Dget_type(d);
        const H5T_class_t cls = H5Tget_class(type);
        if ((cls == H5T_FLOAT || cls == H5T_INTEGER) && H5Tget_size(type) == 8) {
          hid_t space = H5Dget_space(d);
          std::vector<std::uint64_t> words(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
          if (!words.empty()) H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, words.data());
          H5Sclose(space);
          (*static_cast<std::map<std::string, std::vector<std::uint64_t>>*>(data))[name] = std::move(words);
        }
        H5Tclose(type);
        H5Dclose(d);
        return 0;
      },
      &out);
  H5Fclose(f);
  return out;
}

// Frame k of a sequence of 1000 states that change every series: both bodies' positions and
// momenta, both attitudes.
State varied_state(const Scene& scene, int k) {
  State s = scene.initial;
  s.t = 0.01 * k;
  s.x(0, 0) = 0.67 + 1e-3 * k;
  s.p(1, 1) = -0.99 + 1e-4 * k;
  s.p(2, 0) = 0.05 * std::sin(0.1 * k);
  s.R[0] = exp_so3(Vec3(0.0, 0.0, 0.09 * k));
  s.R[1] = exp_so3(Vec3(0.3, -0.02 * k, 0.01 * k));
  return s;
}

// Writes those 1000 frames in blocks of 7 (by count only), into series allocated for 50 frames
// and grown 5 times: in the background or in line.
void write_varied_frames(const fs::path& file, const Scene& scene, bool background) {
  OutputOptions o;
  o.block_frames = 7;
  o.block_seconds = 1e9;  // blocks by count only: the same blocks either way
  o.expected_frames = 50;
  o.background_blocks = background;
  o.overwrite = true;
  H5Writer writer(file, scene, o);
  WorkCounters work;
  for (int k = 0; k < 1000; ++k) {
    const State s = varied_state(scene, k);
    work.steps = 50 * k;
    writer.write_frame(s, diagnose(scene.system, s, -1.0 - 1e-3 * k), work, 0.0);
  }
  writer.finish(work, 0.0, "completed");
  EXPECT_EQ(writer.frames_written(), 1000u);
}

}  // namespace

// Blocks written on a thread of their own while frames keep coming (the default where HDF5 is
// thread-safe) make the file that blocks written in line make, word for word: blocks of 7
// frames, series allocated for 50 frames and grown in the background 5 times over 1000 frames.
TEST(Output, BlocksWrittenInTheBackgroundMatchBlocksWrittenInLine) {
  const Scene scene = test::dumbbell_scene();
  const fs::path background = temp_file("noether-background"), in_line = temp_file("noether-in-line");
  write_varied_frames(background, scene, true);
  write_varied_frames(in_line, scene, false);
  const auto a = numeric_datasets(background), b = numeric_datasets(in_line);
  EXPECT_GE(a.size(), 30u);
  EXPECT_EQ(a.size(), b.size());
  for (const auto& [name, words] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_EQ(words, b.at(name)) << name;
  }
  ASSERT_TRUE(a.count("frames_complete"));
  EXPECT_EQ(a.at("frames_complete"), std::vector<std::uint64_t>{1000});
  EXPECT_EQ(a.at("particles/bodies/position/value").size(), 1000u * 2 * 3);
  fs::remove(background);
  fs::remove(in_line);
}

// The quantities of the state alone (velocities, quaternions, Euler angles, the binary's
// separation…) and the checksums are computed when their block is written, on the writer's
// thread (io::FrameFill): each frame of them is still its own frame's, in blocks of 7 frames
// that do not divide the 1000: against the same functions applied to the states written.
TEST(Output, QuantitiesOfTheStateAloneBelongToTheirFrames) {
  const Scene scene = test::dumbbell_scene();
  const fs::path file = temp_file("noether-state-alone");
  write_varied_frames(file, scene, true);
  const auto words = numeric_datasets(file);
  const auto value = [&](const char* name, std::size_t i) { return std::bit_cast<double>(words.at(name).at(i)); };
  ASSERT_EQ(words.at("particles/bodies/orientation/value").size(), 1000u * 2 * 4);
  const double deg = 180.0 / std::numbers::pi;
  for (int k = 0; k < 1000; ++k) {
    const State s = varied_state(scene, k);
    const auto f = static_cast<std::size_t>(k);
    for (std::size_t j = 0; j < 2; ++j) {
      const Vec4 q = quaternion_from_rotation(s.R[j]);
      const Vec3 euler = euler_angles_321(s.R[j]) * deg;
      for (std::size_t c = 0; c < 4; ++c)
        ASSERT_EQ(value("particles/bodies/orientation/value", 8 * f + 4 * j + c), q(static_cast<Eigen::Index>(c)))
            << "frame " << k;
      for (std::size_t c = 0; c < 3; ++c) {
        const auto e = static_cast<Eigen::Index>(c);
        ASSERT_EQ(value("particles/bodies/euler_angles/value", 6 * f + 3 * j + c), euler(e)) << "frame " << k;
        ASSERT_EQ(value("particles/bodies/velocity/value", 6 * f + 3 * j + c),
                  s.p(e, static_cast<Eigen::Index>(j)) / scene.system.body(j).mass)
            << "frame " << k;
      }
    }
    ASSERT_EQ(value("observables/separation/value", f), (s.x.col(1) - s.x.col(0)).norm()) << "frame " << k;
    // /checkpoint/checksum's column 1 is the positions' (seeded with the frame's index).
    const auto& checksums = words.at("checkpoint/checksum");
    const std::size_t columns = checksums.size() / 1000;
    const std::uint64_t* x = words.at("particles/bodies/position/value").data() + 6 * f;
    ASSERT_EQ(checksums.at(columns * f + 1), io::checksum64(x, 6 * sizeof(std::uint64_t), f)) << "frame " << k;
  }
  fs::remove(file);
}

// A file built under its hidden name and then published (a continuation's, which replaces the
// run it continues) holds every frame written so far as complete when it takes the path, so a
// kill just after loses none: 300 frames, fewer than a block, read by another process (h5dump).
TEST(Output, PublishingCompletesEveryFrameSoFar) {
  const Scene scene = test::dumbbell_scene();
  const fs::path file = temp_file("noether-publish");
  fs::remove(file);
  OutputOptions o;
  o.defer_publish = true;
  o.block_seconds = 1e9;
  H5Writer writer(file, scene, o);
  State s = scene.initial;
  for (int k = 0; k < 300; ++k) {
    s.t = 0.01 * k;
    writer.write_frame(s, diagnose(scene.system, s, -1.0), WorkCounters{}, 0.0);
  }
  EXPECT_FALSE(fs::exists(file));
  writer.publish();
  ASSERT_TRUE(fs::exists(file));
  const fs::path dump = temp_file("noether-publish-dump");
  const std::string command = "HDF5_USE_FILE_LOCKING=FALSE h5dump -d /frames_complete " + file.string() + " > " +
                              dump.string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(dump);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("(0): 300"), std::string::npos) << text;
  writer.finish(WorkCounters{}, 0.0, "completed");
  fs::remove(file);
  fs::remove(dump);
}

// A run feature's own series (RunFeature::series: rows of the frame schema marked kByFeature)
// are written where the schema puts them, each from its place among the numbers the frame hands
// over — whatever order the features declared them in —, with the shape the feature declared;
// a series that is not such a row, and a frame with too few or too many numbers, are refused.
TEST(Output, AFeaturesSeriesAreTheRowsItDeclaresFilledFromItsNumbers) {
  const Scene scene = test::dumbbell_scene();
  const fs::path file = temp_file("noether-feature-series");
  OutputOptions o;
  o.overwrite = true;
  o.feature_series = {{"particle_positions", {2, 3}}, {"fli", {}}, {"megno", {}}};
  {
    H5Writer writer(file, scene, o);
    for (int k = 0; k < 3; ++k) {
      const State s = varied_state(scene, k);
      std::vector<double> numbers;
      for (int j = 0; j < 6; ++j) numbers.push_back(100.0 * k + j);  // the particles', [particle][xyz]
      numbers.push_back(10.0 * k + 0.5);                              // fli
      numbers.push_back(k + 0.25);                                    // megno
      writer.write_frame(s, diagnose(scene.system, s, -1.0), WorkCounters{}, 0.0, 0, {}, numbers);
    }
    const State s = varied_state(scene, 3);
    const std::vector<double> short_frame(7, 0.0);
    EXPECT_THROW(writer.write_frame(s, diagnose(scene.system, s, -1.0), WorkCounters{}, 0.0, 0, {}, short_frame),
                 OutputError);
    writer.finish(WorkCounters{}, 0.0, "completed");
  }
  const auto datasets = numeric_datasets(file);
  auto doubles = [&](const std::string& name) {
    std::vector<double> out;
    for (const std::uint64_t w : datasets.at(name)) out.push_back(std::bit_cast<double>(w));
    return out;
  };
  EXPECT_EQ(doubles("derivatives/megno/value"), (std::vector<double>{0.25, 1.25, 2.25}));
  EXPECT_EQ(doubles("derivatives/fli/value"), (std::vector<double>{0.5, 10.5, 20.5}));
  const std::vector<double> positions = doubles("particles/test_particles/position/value");
  ASSERT_EQ(positions.size(), 18u);  // [frame][particle][3]
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 6; ++j) EXPECT_EQ(positions[static_cast<std::size_t>(6 * k + j)], 100.0 * k + j);
  fs::remove(file);
  // Not a row a feature fills: one the run fills (energy), one the schema does not have.
  for (const char* name : {"energy", "no_such_series"}) {
    OutputOptions wrong = o;
    wrong.feature_series = {{name, {}}};
    EXPECT_THROW(H5Writer(file, scene, wrong), std::logic_error) << name;
    fs::remove(file);
  }
}

// A run that does not carry a series (the dumbbells carry no STM) writes 0 in that series'
// column of /checkpoint/checksum. Damage there is the table's: the continuation says so, and
// does not blame a series the file does not have (issue 63, item 6).
TEST(Output, DamageInAnUnusedChecksumColumnIsTheTables) {
  const fs::path file = temp_file("noether-unused-checksum");
  auto registry = test::bundled_plugins();
  RunOptions options;
  options.output = file;
  run_scene(test::dumbbell_scene({"run.t_end=0.1"}), registry, options);
  {
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    ASSERT_LT(H5Lexists(f, "/derivatives", H5P_DEFAULT), 1) << "the dumbbells should carry no derivatives";
    const std::vector<hsize_t> shape = dims(f, "/checkpoint/checksum");
    ASSERT_EQ(shape.size(), 2u);
    std::vector<std::uint64_t> sums(shape[0] * shape[1]);
    const hid_t d = H5Dopen2(f, "/checkpoint/checksum", H5P_DEFAULT);
    H5Dread(d, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, sums.data());
    std::size_t unused = shape[1];
    for (std::size_t c = 0; c < shape[1] && unused == shape[1]; ++c)
      if (sums[c] == 0 && sums[shape[1] + c] == 0) unused = c;
    ASSERT_LT(unused, shape[1]) << "no column of /checkpoint/checksum is 0";
    sums[3 * shape[1] + unused] = 1;  // frame 3
    H5Dwrite(d, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, sums.data());
    H5Dclose(d), H5Fclose(f);
  }
  try {
    Simulation::resume(file, registry, RunOptions{}, 0.2);
    ADD_FAILURE() << "a damaged checksum table was continued";
  } catch (const OutputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("frame 3 of /checkpoint/checksum is damaged: its column"), std::string::npos) << what;
    EXPECT_NE(what.find("a series this file does not hold"), std::string::npos) << what;
    EXPECT_EQ(what.find("does not match its checksum"), std::string::npos) << what;
  }
  fs::remove(file);
}
