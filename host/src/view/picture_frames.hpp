#pragma once
// PictureFrames: what a picture of a run needs, read from its output file alone — the frames
// chosen (evenly spaced by index, at most max_frames), each body's position and attitude at
// them, and each body's shape in its body frame. `noether view` (view.cpp) and `noether export`
// (export_vtk.cpp) draw from it. Internal to libnoether.
#include <noether/lie.hpp>
#include <noether/mesh.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace noether::detail {

// A body's shape as drawn, in its body frame and the file's length unit.
struct PictureShape {
  enum class Kind { point, sphere, field, ellipsoid, polyhedron, spheres };
  Kind kind = Kind::point;
  Mesh mesh;                                                          // polyhedron
  Vec3 semi_axes = Vec3::Zero();                                      // ellipsoid, along …
  Eigen::Quaterniond axes = Eigen::Quaterniond::Identity();           // … these axes of the body
  bool inferred = false;  // an ellipsoid of the body's mass and inertia, its shape unknown here
  std::vector<Vec3> centres;                                          // spheres
  std::vector<double> radii;
  double radius = 0.0;  // sphere (a point mass's scene radius), field (its reference radius)
  double size = 0.0;    // the distance from the centre of mass that holds the shape (0: a point)
  const char* name() const;  // "polyhedron", "ellipsoid", …
};

// An impulse of the run (the scene's `impulses`): when, and on which body.
struct PictureImpulse {
  double t = 0.0;
  std::string body;
};

struct PictureFrames {
  std::vector<std::string> names;
  std::vector<double> masses;
  std::vector<int> rigid_of_body;  // −1 for a point mass
  std::vector<PictureShape> shapes;
  std::size_t frames_in_file = 0;
  std::vector<std::uint32_t> shown;       // the file's frame of each frame kept
  std::vector<double> t;                  // [frame kept]
  std::vector<Eigen::Matrix3Xd> x;        // [frame kept] positions [3][body]
  std::vector<std::vector<Mat3>> R;       // [frame kept][rigid body] attitudes, exact
  // The recorded massless particles (particles.record; none without): their inertial positions
  // at the frames kept, [frame kept][particle][3] row-major, verified against their checksums.
  std::size_t particles = 0;
  std::vector<double> particle_x;
  std::vector<PictureImpulse> impulses;  // as the scene the file records gives them (after its --set)
  std::string unit_length = "L", unit_time = "T";
  std::vector<std::string> notes;  // what a picture shows differently from the run
};

// The run of `file` (OutputError: not a run's output — an ensemble's file named as such —, or
// damaged: its frames are verified against their checksums); SceneError for max_frames < 2.
// With `frames_wanted`, exactly those of the file's frames that it has (in that order).
PictureFrames read_picture_frames(const std::filesystem::path& file, std::size_t max_frames,
                                  const std::vector<std::uint32_t>* frames_wanted = nullptr);

// Whether `file` is an ensemble's (noether ensemble -o), not a run's.
bool is_ensemble_file(const std::filesystem::path& file);

// The shape as a closed triangle mesh in the body frame (an ellipsoid's and a sphere's with
// 20·4^level faces); an empty mesh for a point.
Mesh picture_surface(const PictureShape& shape, int level);

}  // namespace noether::detail
