#include <noether/error.hpp>
#include <noether/system.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <set>
#include <sstream>

namespace noether {

void validate_inertia(const Mat3& J, const std::string& context) {
  const double scale = J.cwiseAbs().maxCoeff();
  if (!J.allFinite() || scale == 0.0)
    throw SceneError(context + ": inertia must be finite and non-zero");
  if ((J - J.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale)
    throw SceneError(context + ": inertia matrix must be symmetric");
  Eigen::SelfAdjointEigenSolver<Mat3> eig(J);
  const Vec3 lambda = eig.eigenvalues();  // ascending
  if (lambda[0] <= 0.0) {
    std::ostringstream msg;
    msg << context << ": inertia must be positive definite; its principal moments are "
        << lambda.transpose()
        << ". A body with a zero moment (an ideal rod) is not a rigid body noether can "
           "integrate: give its spheres a radius, or make it a point mass by removing 'inertia'";
    throw SceneError(msg.str());
  }
  // Triangle inequality: the largest principal moment cannot exceed the sum of the other two.
  if (lambda[2] > (lambda[0] + lambda[1]) * (1.0 + 1e-12)) {
    std::ostringstream msg;
    msg << context << ": principal moments " << lambda.transpose()
        << " violate the triangle inequality (J3 = " << lambda[2] << " > J1 + J2 = "
        << lambda[0] + lambda[1] << "); no mass distribution has this inertia";
    throw SceneError(msg.str());
  }
}

System::System(double G, std::vector<Body> bodies) : G_(G), bodies_(std::move(bodies)) {
  if (!std::isfinite(G) || G <= 0.0) {
    std::ostringstream msg;
    msg << "G must be a positive number, not " << G;
    throw SceneError(msg.str());
  }
  if (bodies_.empty()) throw SceneError("a scene needs at least one body");
  std::set<std::string> names;
  rigid_of_body_.assign(bodies_.size(), -1);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body& b = bodies_[i];
    const std::string context = "body '" + b.name + "'";
    if (b.name.empty()) throw SceneError("body " + std::to_string(i) + " has an empty name");
    if (const std::string why = name_problem(b.name); !why.empty())
      throw SceneError("body " + std::to_string(i) + " is named '" + b.name + "': " + why);
    if (!names.insert(b.name).second)
      throw SceneError("two bodies are named '" + b.name + "'; names must be unique");
    if (!std::isfinite(b.mass) || b.mass <= 0.0) {
      std::ostringstream msg;
      msg << context << ": mass must be positive, not " << b.mass;
      throw SceneError(msg.str());
    }
    if (b.rigid) {
      validate_inertia(b.inertia, context);
      b.inertia_inverse = b.inertia.inverse();
      b.inertia_nonstandard = 0.5 * b.inertia.trace() * Mat3::Identity() - b.inertia;
      rigid_of_body_[i] = static_cast<int>(body_of_rigid_.size());
      body_of_rigid_.push_back(i);
    }
  }
}

std::string System::name_problem(const std::string& name) {
  for (const char c : name)
    if (c == '/' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return "a name may not contain '/' or control characters (letters, digits, '-', '_', '.' and spaces are fine)";
  return "";
}

int System::index_of(const std::string& name) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (bodies_[i].name == name) return static_cast<int>(i);
  return -1;
}

}  // namespace noether
