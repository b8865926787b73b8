// Observables (docs/equations.md §27), the trajectory they are sampled from (eq. 16.2) and the
// observation files they are read from (docs/fitting.md).
#include <noether/conjunction.hpp>
#include <noether/error.hpp>
#include <noether/observations.hpp>
#include <noether/orbital_elements.hpp>
#include <noether/trajectory.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <unistd.h>

using namespace noether;
using Eigen::Vector3d;

namespace {

// Every observable's gradients against central differences of its value.
TEST(Observables, GradientsAgreeWithDifferences) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u01(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Vector3d r(3 * u01(random), 2 * u01(random), u01(random) + 2), u(u01(random), u01(random), u01(random));
    for (const auto& name : observable_names()) {
      Observable o;
      o.kind = observable_kind(name);
      if (o.is_lightcurve() || o.is_event_time()) {  // not functions of r and u: refused by evaluate
        EXPECT_THROW(evaluate(o, r, u), Error);
        continue;
      }
      o.line_of_sight = Vector3d(u01(random), u01(random), u01(random)).normalized();
      const ObservableValue at = evaluate(o, r, u);
      const double h = 1e-6;
      for (int i = 0; i < 3; ++i) {
        Vector3d e = Vector3d::Zero();
        e[i] = h;
        const double dr = (evaluate(o, r + e, u).value - evaluate(o, r - e, u).value) / (2 * h);
        const double du = (evaluate(o, r, u + e).value - evaluate(o, r, u - e).value) / (2 * h);
        EXPECT_NEAR(at.d_r[i], dr, 1e-9) << name;
        EXPECT_NEAR(at.d_u[i], du, 1e-9) << name;
      }
    }
  }
}

// The sky plane (27.2): (ê, n̂, ℓ) orthonormal and right-handed; looking along
// +x from the origin (right ascension 0, declination 0), north is +z and east +y — the direction
// of increasing right ascension; looking along z, north is +y.
TEST(Observables, SkyPlaneIsTheObserversNorthAndEast) {
  const SkyPlane x = sky_plane(Vector3d(2, 0, 0));
  EXPECT_LT((x.north - Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_LT((x.east - Vector3d::UnitY()).norm(), 1e-15);
  const SkyPlane z = sky_plane(Vector3d(0, 0, -1));
  EXPECT_LT((z.north - Vector3d::UnitY()).norm(), 1e-15);
  const SkyPlane any = sky_plane(Vector3d(0.3, -0.2, 0.9));
  EXPECT_NEAR(any.east.dot(any.north), 0, 1e-15);
  EXPECT_NEAR(any.east.dot(any.line_of_sight), 0, 1e-15);
  EXPECT_NEAR(any.north.dot(any.line_of_sight), 0, 1e-15);
  EXPECT_NEAR(any.east.cross(any.north).dot(any.line_of_sight), 1, 1e-15);
  EXPECT_GT(any.north.z(), 0);
  EXPECT_THROW(sky_plane(Vector3d::Zero()), SceneError);
  Observable rate;
  rate.kind = Observable::Kind::range_rate;
  EXPECT_TRUE(std::isnan(evaluate(rate, Vector3d::Zero(), Vector3d::UnitX()).value));
}

// A Keplerian orbit (e = 0.3, μ = 1, period 2π) recorded at frames Δ apart: sampled at the
// frames, the trajectory returns them; between them its error falls as Δ⁴ (eq. 16.2's order):
// halving Δ divides the worst position error by 16 ± 25 %.
TEST(Observables, TrajectoryIsExactAtFramesAndFourthOrderBetween) {
  auto kepler = [](double t) {
    OrbitalElements el;
    el.a = 1, el.e = 0.3, el.i = 0.4, el.Omega = 0.2, el.omega = 1.1;
    el.nu = true_from_mean_anomaly(t, el.e);
    return state_from_elements(el, 1.0);
  };
  auto recorded = [&](double delta) {
    Trajectory tr;
    tr.names = {"star", "planet"};
    tr.masses = {1, 1e-9};
    for (double t = 0; t <= 2 * M_PI + 1e-12; t += delta) {
      const RelativeState s = kepler(t);
      Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 2), v = Eigen::Matrix3Xd::Zero(3, 2);
      x.col(1) = s.r, v.col(1) = s.v;
      tr.append(t, x, v);
    }
    return tr;
  };
  auto worst_between = [&](const Trajectory& tr) {
    double worst = 0;
    Eigen::Matrix3Xd x, v;
    for (std::size_t k = 0; k + 1 < tr.frames(); ++k) {
      const double t = 0.5 * (tr.times()[k] + tr.times()[k + 1]);
      tr.sample(t, x, v);
      worst = std::max(worst, (x.col(1) - kepler(t).r).norm());
    }
    return worst;
  };
  const Trajectory coarse = recorded(0.1), fine = recorded(0.05);
  Eigen::Matrix3Xd x, v;
  coarse.sample(coarse.times()[7], x, v);
  EXPECT_EQ((x.col(1) - kepler(coarse.times()[7]).r).norm(), 0.0);
  const double e1 = worst_between(coarse), e2 = worst_between(fine);
  EXPECT_NEAR(e1 / e2, 16, 4) << e1 << " " << e2;
  EXPECT_LT(e1, 1e-5);
  EXPECT_THROW(coarse.sample(-1e-9, x, v), SceneError);
  EXPECT_THROW(coarse.sample(coarse.t_last() + 1e-9, x, v), SceneError);
  EXPECT_THROW(coarse.body("plante"), SceneError);
}

// Two frames at one time (an impulse's before and after): sampling at that time gives the later.
TEST(Observables, AtAnImpulsesTimeTheTrajectoryIsAfterIt) {
  Trajectory tr;
  tr.names = {"a", "b"};
  tr.masses = {1, 1};
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 2), v = Eigen::Matrix3Xd::Zero(3, 2), after = v;
  after(0, 1) = 1;
  tr.append(0, x, v);
  tr.append(1, x, v);
  tr.append(1, x, after);
  tr.append(2, x + after, after);
  Eigen::Matrix3Xd xs, vs;
  tr.sample(1, xs, vs);
  EXPECT_EQ(vs(0, 1), 1);
  tr.sample(1.5, xs, vs);  // between the jump's later frame and the next: uniform motion
  EXPECT_NEAR(xs(0, 1), 0.5, 1e-15);
  EXPECT_NEAR(vs(0, 1), 1, 1e-15);
  EXPECT_THROW(tr.append(0.5, x, v), Error);
}

struct ObservationFile {
  std::filesystem::path path;
  explicit ObservationFile(const std::string& text)
      : path(std::filesystem::temp_directory_path() / ("noether-observations-" + std::to_string(::getpid()) + ".csv")) {
    std::ofstream(path) << text;
  }
  ~ObservationFile() { std::filesystem::remove(path); }
};

std::string error_of(const std::string& text) {
  const ObservationFile f(text);
  try {
    read_observations(f.path, {"didymos", "dimorphos"});
  } catch (const SceneError& e) {
    return std::string(e.what()).substr(f.path.string().size());
  }
  return "accepted";
}

// The reader: columns in any order, comments, the sky's line of sight normalised; what it
// writes reads back to the same rows.
TEST(Observations, ReadAndWriteBack) {
  const ObservationFile f(
      "# a comment\n"
      "sigma, value, t, target, center, observable, los_x, los_y, los_z, note\n"
      "0.5, 1200, 0, dimorphos, didymos, position.x, , , , first\n"
      "1, -3.5, 60, dimorphos, didymos, sky.north, 0, 0, 2, \n");
  const auto rows = read_observations(f.path, {"didymos", "dimorphos"});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].observable.kind, Observable::Kind::position_x);
  EXPECT_EQ(rows[0].observable.target, 1u);
  EXPECT_EQ(rows[0].sigma, 0.5);
  EXPECT_EQ(rows[1].line, 4u);
  EXPECT_EQ(rows[1].observable.line_of_sight, Vector3d(0, 0, 1));
  std::ostringstream out;
  write_observations(out, rows, {"didymos", "dimorphos"});
  const ObservationFile again(out.str());
  const auto back = read_observations(again.path, {"didymos", "dimorphos"});
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(back[k].t, rows[k].t);
    EXPECT_EQ(back[k].value, rows[k].value);
    EXPECT_EQ(back[k].sigma, rows[k].sigma);
    EXPECT_EQ(back[k].observable.kind, rows[k].observable.kind);
    EXPECT_EQ(back[k].observable.line_of_sight, rows[k].observable.line_of_sight);
  }
}

// Each bad file refused with its line and column.
TEST(Observations, BadRowsAreRefusedByLineAndColumn) {
  const std::string header = "t,observable,target,center,value,sigma\n";
  EXPECT_EQ(error_of(header + "0,range,dimorphos,didymos,1,0\n"), ":2: column 'sigma': must be positive (got 0)");
  EXPECT_EQ(error_of(header + "0,range,dimorphos,didymos,1,-1\n"), ":2: column 'sigma': must be positive (got -1)");
  EXPECT_EQ(error_of(header + "0,range,dimorphos,didymos,1,\n"), ":2: column 'sigma': empty");
  EXPECT_EQ(error_of(header + "0,range,dimorphos,dydimos,1,1\n"),
            ":2: column 'center': no body 'dydimos' in the run (its bodies: didymos, dimorphos)");
  EXPECT_EQ(error_of(header + "0,range,dimorphos,dimorphos,1,1\n"),
            ":2: target and center are the same body ('dimorphos')");
  EXPECT_EQ(error_of(header + "1 h,range,dimorphos,didymos,1,1\n"), ":2: column 't': '1 h' is not a finite number");
  EXPECT_EQ(error_of(header + "0,range,dimorphos,didymos,nan,1\n"), ":2: column 'value': 'nan' is not a finite number");
  EXPECT_NE(error_of(header + "0,rng,dimorphos,didymos,1,1\n").find(":2: column 'observable': unknown observable 'rng'"),
            std::string::npos);
  EXPECT_EQ(error_of(header + "0,sky.east,dimorphos,didymos,1,1\n"),
            ":2: sky.east needs the line of sight: columns los_x, los_y, los_z (from the observer towards the bodies)");
  EXPECT_EQ(error_of("t,observable,target,value,sigma\n0,range,dimorphos,1,1\n"),
            ":1: the header has no column 'center' (an observation file's header names t, observable, target, center, "
            "value, sigma; docs/fitting.md)");
  EXPECT_EQ(error_of(header + "0,range,dimorphos\n"), ":2: the row has 3 cells; column 'center' is cell 4");
  EXPECT_EQ(error_of(header), ": the file holds no observation");
  const std::string lc = "t,observable,target,center,value,sigma,los_x,los_y,los_z\n";
  EXPECT_EQ(error_of(lc + "0,lightcurve.lambert,dimorphos,didymos,1,1,1,0,0\n"),
            ":2: lightcurve.lambert needs the sunlight's direction: columns sun_x, sun_y, sun_z (from the Sun towards "
            "the bodies)");
  EXPECT_EQ(error_of("t,observable,target,center,value,sigma,los_x,los_y,los_z,sun_x,sun_y,sun_z\n"
                     "0,lightcurve.lambert,dimorphos,didymos,1,1,1,0,0,0,0,0\n"),
            ":2: columns sun_x, sun_y, sun_z: the sunlight's direction is zero");
}

// A lightcurve row may name one body twice (its lightcurve alone); its directions read back.
TEST(Observations, LightcurveRowsReadAndWriteBack) {
  const ObservationFile f(
      "t,observable,target,center,value,sigma,los_x,los_y,los_z,sun_x,sun_y,sun_z\n"
      "0,lightcurve.lommel_seeliger,didymos,didymos,2.5e5,100,-2,0,0,0,-1,0\n"
      "60,position.x,dimorphos,didymos,1200,1,,,,,,\n");
  const auto rows = read_observations(f.path, {"didymos", "dimorphos"});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_TRUE(rows[0].observable.is_lightcurve());
  EXPECT_EQ(rows[0].observable.line_of_sight, Vector3d(-1, 0, 0));
  EXPECT_EQ(rows[0].observable.sunlight, Vector3d(0, -1, 0));
  std::ostringstream out;
  write_observations(out, rows, {"didymos", "dimorphos"});
  const ObservationFile again(out.str());
  const auto back = read_observations(again.path, {"didymos", "dimorphos"});
  EXPECT_EQ(back[0].observable.sunlight, rows[0].observable.sunlight);
  EXPECT_EQ(back[0].value, rows[0].value);
  EXPECT_FALSE(back[1].observable.is_lightcurve());
  EXPECT_THROW(observable_from_spec("lightcurve.lambert:didymos:didymos", {"didymos"}, {1, 0, 0}), SceneError);
  EXPECT_THROW(observable_from_spec("range:didymos:didymos", {"didymos"}), SceneError);
  EXPECT_NO_THROW(observable_from_spec("lightcurve.lambert:didymos:didymos", {"didymos"}, {1, 0, 0}, {1, 0, 0}));
}

// Attitudes between frames (eq. 29.4) for a body that spins about its own z while its z precesses
// about the scene's z: R(t) = Rz(ω1 t) Rx(β) Rz(ω2 t), Ω = Rz(ω2 t)ᵀ Rx(β)ᵀ ω1 ẑ + ω2 ẑ. Exact
// at the frames, fourth order between them (the error 16× smaller at half the spacing), and
// frames too far apart for the spin refused.
TEST(Observables, AttitudesBetweenFramesAreFourthOrder) {
  const double w1 = 2e-4, w2 = 7e-4, beta = 0.4;
  auto R_at = [&](double t) {
    return Mat3(Eigen::AngleAxisd(w1 * t, Vector3d::UnitZ()) * Eigen::AngleAxisd(beta, Vector3d::UnitX()) *
                Eigen::AngleAxisd(w2 * t, Vector3d::UnitZ()));
  };
  auto omega_at = [&](double t) {
    const Mat3 B(Eigen::AngleAxisd(beta, Vector3d::UnitX())), C(Eigen::AngleAxisd(w2 * t, Vector3d::UnitZ()));
    return Vector3d(C.transpose() * B.transpose() * (w1 * Vector3d::UnitZ()) + w2 * Vector3d::UnitZ());
  };
  auto worst_error = [&](double dt) {
    Trajectory tr;
    tr.names = {"moon"};
    for (int k = 0; k <= static_cast<int>(3600 / dt); ++k) {
      const double t = k * dt;
      tr.append(t, Eigen::Matrix3Xd::Zero(3, 1), Eigen::Matrix3Xd::Zero(3, 1));
      tr.append_attitudes({R_at(t)}, omega_at(t));
    }
    EXPECT_LT((tr.attitudes(dt)[0] - R_at(dt)).norm(), 1e-15);
    double worst = 0;
    for (double t = 0.37 * dt; t < 3600; t += dt)
      worst = std::max(worst, log_so3(R_at(t).transpose() * tr.attitudes(t)[0]).norm());
    return worst;
  };
  const double e300 = worst_error(300), e150 = worst_error(150);
  EXPECT_LT(e300, 1e-5);
  EXPECT_NEAR(e300 / e150, 16.0, 2.0);
  Trajectory fast;
  fast.names = {"moon"};
  for (double t : {0.0, 4000.0}) {
    fast.append(t, Eigen::Matrix3Xd::Zero(3, 1), Eigen::Matrix3Xd::Zero(3, 1));
    fast.append_attitudes({R_at(t)}, omega_at(t));
  }
  try {
    fast.attitudes(2000);
    ADD_FAILURE() << "frames 4000 s apart for a spin of 9e-4 rad/s were interpolated";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("'moon' turns by"), std::string::npos) << e.what();
  }
}

}  // namespace

namespace {

// A circular orbit of radius a and rate ω in the xy plane, phase φ: x(t) = a (cos(ωt + φ),
// sin(ωt + φ), 0) about a center at rest, frames every dt, with the derivatives with respect to
// (φ, ω).
Trajectory circular_orbit(double a, double omega, double phi, double dt, double t_end) {
  Trajectory tr;
  tr.names = {"primary", "moon"};
  tr.masses = {1, 1e-3};
  for (double t = 0; t <= t_end + 1e-9; t += dt) {
    const double th = omega * t + phi;
    Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Zero(3, 2), v = Eigen::Matrix3Xd::Zero(3, 2);
    x.col(1) = a * Vector3d(std::cos(th), std::sin(th), 0);
    v.col(1) = a * omega * Vector3d(-std::sin(th), std::cos(th), 0);
    Eigen::MatrixXd dx = Eigen::MatrixXd::Zero(6, 2), dv = Eigen::MatrixXd::Zero(6, 2);
    dx.block<3, 1>(3, 0) = a * Vector3d(-std::sin(th), std::cos(th), 0);      // ∂x/∂φ
    dx.block<3, 1>(3, 1) = t * dx.block<3, 1>(3, 0);                           // ∂x/∂ω
    dv.block<3, 1>(3, 0) = -a * omega * Vector3d(std::cos(th), std::sin(th), 0);  // ∂v/∂φ
    dv.block<3, 1>(3, 1) = v.col(1) / omega + t * dv.block<3, 1>(3, 0);          // ∂v/∂ω
    tr.append(t, x, v, dx, dv);
  }
  return tr;
}

}  // namespace

// Conjunctions (docs/equations.md §30) of a circular orbit seen along ℓ = (cos β, sin β, 0) from the
// observer: the moon is nearest the primary on the sky at ωt + φ = β + kπ — the angles where it
// is behind (k even) or in front of it (k odd). Their times to 1e-9 of the frame spacing, and the
// derivatives dt/dφ = −1/ω, dt/dω = −t/ω (30.2) against the closed form. The times' error is the
// interpolant's (16.2) between frames 600 s apart: about 2e-4 m of position over 0.18 m/s.
TEST(Observables, ConjunctionsOfACircularOrbitAreAtTheirAngles) {
  const double a = 1200, omega = 2 * M_PI / 42958, phi = 0.3, beta = 1.1;
  const Trajectory tr = circular_orbit(a, omega, phi, 600, 3 * 86400);
  const Vector3d ell(std::cos(beta), std::sin(beta), 0.0);
  const auto all = conjunctions(tr, 1, 0, ell);
  ASSERT_EQ(all.size(), 12u);  // two an orbit, 6.03 orbits
  for (std::size_t k = 0; k < all.size(); ++k) {
    const double expected = (beta + static_cast<double>(k) * M_PI - phi) / omega;
    EXPECT_NEAR(all[k].t, expected, 5e-5) << k;  // measured ≤ 1.1e-5 s
    EXPECT_EQ(all[k].target_in_front, k % 2 == 1) << k;
    EXPECT_LT(all[k].separation, 1e-6 * a);
    ASSERT_EQ(all[k].dt_dp.size(), 2);
    EXPECT_NEAR(all[k].dt_dp[0], -1 / omega, 1e-6 / omega) << k;
    EXPECT_NEAR(all[k].dt_dp[1], -expected / omega, 1e-6 * expected / omega) << k;
  }
  // The nearest one to a time; refused when the run ends nearer than it.
  EXPECT_EQ(nearest_conjunction(tr, 1, 0, ell, all[3].t + 5000).t, all[3].t);
  EXPECT_THROW(nearest_conjunction(tr, 1, 0, ell, 3 * 86400 - 100), SceneError);
  EXPECT_THROW(nearest_conjunction(tr, 1, 0, Vector3d(0, 0, 1), 1000), SceneError);  // face-on: none
}
