// Bodies given by their gravity field (docs/gravity-fields.md; docs/equations.md (31.3)–(31.4)):
// the field files read back exactly as written, their units and conventions, errors by file and
// line; the inertia a field and one more number give; a scene's field body against the shape its
// coefficients came from.
#include "shapes.hpp"
#include "test_support.hpp"

#include <noether/error.hpp>
#include <noether/scene.hpp>
#include <noether/solid.hpp>
#include <noether/stokes_coefficients.hpp>
#include <noether/stokes_file.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace noether;

namespace {

std::filesystem::path scratch(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "noether-field-body-test";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

std::string read_error(const std::string& name, const std::string& text, const std::string& format) {
  try {
    read_stokes_file(scratch(name, text), format);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

// KW4 Beta as the SI ellipsoid of examples/kw4-ellipsoids.yaml.
const Vec3 kBetaAxes(285, 231.5, 174.5);
constexpr double kBetaMass = 1.35e11, kG = 6.674e-11;

std::shared_ptr<const Solid> beta() {
  return make_ellipsoid(kBetaAxes, kBetaMass / (4.0 / 3.0 * M_PI * kBetaAxes.prod()));
}

std::string field_scene(const std::string& gravity, const std::string& more = "") {
  return "units: SI\nG: 6.674e-11\nbodies:\n"
         "  - {name: alpha, mass: 2.353e12, shape: {ellipsoid: {semi_axes: [766, 747.5, 673.5]}}, position: [0, 0, 0]}\n"
         "  - {name: beta, position: [2548, 0, 0], velocity: [0, 0.25, 0], gravity: " + gravity + more + "}\n"
         "potential: {plugin: mutual-series, order: 4}\nintegrator: {plugin: lgvi, step: 60}\n"
         "run: {t_end: 600, output_every: 60}\n";
}

std::string scene_error(const std::string& text) {
  try {
    parse_scene(text, "s.yaml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

// write_icgem → read_stokes_file gives every coefficient, GM and the radius back bit for bit
// (%.17e), in both normalisations; the unnormalised file's coefficients are the normalised ones
// times N_nm (31.2).
TEST(StokesFile, IcgemRoundTripIsExact) {
  const auto alpha = make_polyhedron(test::shipped_mesh("a66391_1999kw4_primary.obj", 1000), 1970, true);
  const StokesCoefficients cs = stokes_from_integrals(alpha->integrals(10), alpha->radius, 10, true);
  for (bool normalized : {true, false}) {
    const StokesCoefficients written = truncated(cs, 10, normalized);
    std::ostringstream text;
    write_icgem(text, written, 1.234567890123456789e2, alpha->radius, "kw4-alpha", {"a comment line"});
    const StokesFile back = read_stokes_file(scratch("alpha.gfc", text.str()), "icgem");
    EXPECT_EQ(back.model, "kw4-alpha");
    EXPECT_EQ(*back.gm, 1.234567890123456789e2);
    EXPECT_EQ(*back.reference_radius, alpha->radius);
    EXPECT_EQ(*back.normalized, normalized);
    ASSERT_EQ(back.coefficients.degree, 10);
    for (int n = 0; n <= 10; ++n)
      for (int m = 0; m <= n; ++m) {
        if (n == 1) {  // the centre of mass's round-off (≤ 1e-16), read as the zero it is
          EXPECT_LT(std::abs(written.c(n, m)) + std::abs(written.s(n, m)), 1e-15);
          EXPECT_EQ(back.coefficients.c(n, m), 0.0);
          continue;
        }
        EXPECT_EQ(back.coefficients.c(n, m), written.c(n, m)) << n << " " << m;
        EXPECT_EQ(back.coefficients.s(n, m), written.s(n, m)) << n << " " << m;
        if (!normalized && n >= 2)  // (31.2) against the normalised set
          EXPECT_NEAR(written.c(n, m), cs.c(n, m) * stokes_normalization(n, m),
                      1e-15 * std::abs(cs.c(n, m) * stokes_normalization(n, m)) + 1e-300);
      }
    const StokesCoefficients again = truncated(written, 10, true);
    for (std::size_t k = 0; k < cs.C.size(); ++k) EXPECT_NEAR(again.C[k], cs.C[k], 1e-15 * std::abs(cs.C[k]) + 1e-300);
  }
}

// A PDS SHADR table (kilometres, km³/s², Fortran D exponents, no degree-0 record, CR/LF) and a
// plain table: the units converted to SI, C00 = 1 supplied, missing coefficients zero. The
// numbers are made up for the test.
TEST(StokesFile, ShadrAndTable) {
  const StokesFile shadr = read_stokes_file(
      scratch("field.tab",
              "   1.6000000000000000E+01,   4.4621000000000000E-04,   1.0E-07,    3,    3,    1,   0.0,   0.0\r\n"
              "    1,    0,  0.00000000000000000D+00,  0.00000000000000000D+00, 0.0, 0.0\r\n"
              "    2,    0, -5.2500000000000000D-02,  0.00000000000000000D+00, 1.0E-04, 0.0\r\n"
              "    2,    2,  8.2300000000000000D-02, -2.7000000000000000D-02, 1.0E-04, 1.0E-04\r\n"
              "    3,    1,  4.0000000000000000D-03,  2.0000000000000000D-03, 1.0E-04, 1.0E-04\r\n"),
      "shadr");
  EXPECT_DOUBLE_EQ(*shadr.reference_radius, 16000.0);
  EXPECT_DOUBLE_EQ(*shadr.gm, 446210.0);  // km³/s² → m³/s²
  EXPECT_TRUE(*shadr.normalized);
  EXPECT_EQ(shadr.coefficients.degree, 3);
  EXPECT_EQ(shadr.coefficients.c(0, 0), 1.0);
  EXPECT_EQ(shadr.coefficients.c(2, 0), -5.25e-2);
  EXPECT_EQ(shadr.coefficients.s(2, 2), -2.7e-2);
  EXPECT_EQ(shadr.coefficients.c(3, 3), 0.0);
  EXPECT_EQ(stokes_format_of("x/field.TAB"), "shadr");
  EXPECT_EQ(stokes_format_of("x/field.gfc"), "icgem");
  EXPECT_EQ(stokes_format_of("x/field.txt"), "");

  const StokesFile table = read_stokes_file(scratch("field.txt", "# n m C S\n2 0 -0.1 0\n2, 2, 0.03, 0.01  # a comment\n"), "table");
  EXPECT_FALSE(table.gm.has_value());
  EXPECT_FALSE(table.normalized.has_value());
  EXPECT_EQ(table.coefficients.degree, 2);
  EXPECT_EQ(table.coefficients.c(0, 0), 1.0);
  EXPECT_EQ(table.coefficients.c(2, 2), 0.03);
}

// Each bad file names its file and line, and what is wrong.
TEST(StokesFile, BadFilesAreRefusedByFileAndLine) {
  const std::string head = "begin_of_head\nmodelname x\nearth_gravity_constant 1e3\nradius 10\nmax_degree 2\nend_of_head\n";
  auto contains = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos ? ::testing::AssertionSuccess()
                                                   : ::testing::AssertionFailure() << message;
  };
  EXPECT_TRUE(contains(read_error("a.gfc", head + "gfc 0 0 1 0\ngfc 2 0 -1.0x 0\n", "icgem"), "a.gfc:8: C '-1.0x' is not"));
  EXPECT_TRUE(contains(read_error("b.gfc", head + "gfct 2 0 1e-3 0 0 0 20000101\n", "icgem"), "b.gfc:7: a time-variable term"));
  EXPECT_TRUE(contains(read_error("c.gfc", head + "gfc 2 0 1e-3 0\ngfc 2 0 2e-3 0\n", "icgem"),
                       "c.gfc:8: the coefficients of degree 2, order 0 are given twice (first on line 7)"));
  EXPECT_TRUE(contains(read_error("d.gfc", head + "gfc 2 3 1e-3 0\n", "icgem"), "d.gfc:7: order 3 is above degree 2"));
  EXPECT_TRUE(contains(read_error("e.gfc", head + "gfc 3 0 1e-3 0\n", "icgem"), "above the header's max_degree 2"));
  EXPECT_TRUE(contains(read_error("f.gfc", head + "gfc 1 1 1e-3 0\n", "icgem"), "the degree-1 coefficients"));
  EXPECT_TRUE(contains(read_error("g.gfc", "modelname x\ngfc 0 0 1 0\n", "icgem"), "no 'end_of_head'"));
  EXPECT_TRUE(contains(read_error("h.gfc", "begin_of_head\nradius 10\nmax_degree 2\nend_of_head\ngfc 0 0 1 0\n", "icgem"),
                       "no 'earth_gravity_constant'"));
  EXPECT_TRUE(contains(read_error("i.gfc", head + "gfc 0 0 1.5 0\n", "icgem"), "C(0, 0) is 1.5, not 1"));
  EXPECT_TRUE(contains(read_error("j.tab", "16, 4e-4, 0, 2, 2, 3\n", "shadr"), "j.tab:1: normalization state 3"));
  EXPECT_TRUE(contains(read_error("k.tab", "16, 4e-4, 0, 2, 2, 1, 10, 0\n", "shadr"), "reference longitude and latitude must be 0"));
  EXPECT_TRUE(contains(read_error("l.txt", "2 0 0.1\n", "table"), "l.txt:1: a row needs n m C S"));
  EXPECT_TRUE(contains(read_error("m.txt", "2 0 0.1 0.2\n", "table"), "m.txt:1: S(2, 0) is"));
  EXPECT_TRUE(contains(read_error("n.gfc", "begin_of_head\nearth_gravity_constant 1e3\nradius 10\nmax_degree 5000\n"
                                           "end_of_head\n", "icgem"),
                       "n.gfc:4: max_degree 5000 is above 2400, the highest degree noether reads"));
  try {  // a device would be read without end
    read_stokes_file("/dev/zero", "icgem");
    ADD_FAILURE() << "/dev/zero was read";
  } catch (const SceneError& e) {
    EXPECT_TRUE(contains(e.what(), "/dev/zero: the gravity-field file is not a regular file"));
  }
}

// The inertia of a body known by its field and one more number (31.4): KW4 Alpha in its mesh's
// axes (products of inertia non-zero), from its moment about z or from its inertia's trace,
// against the polyhedron's own inertia.
TEST(FieldBody, InertiaFromTheFieldAndOneNumber) {
  const auto alpha = make_polyhedron(test::shipped_mesh("a66391_1999kw4_primary.obj", 1000), 1970, false);
  ASSERT_GT(std::abs(alpha->inertia(0, 1)), 1e-6 * alpha->inertia(2, 2));
  for (bool normalized : {true, false}) {
    const StokesCoefficients cs = stokes_from_integrals(alpha->integrals(6), 1.3 * alpha->radius, 6, normalized);
    const Mat3 from_polar = inertia_of(field_integrals(cs, second_moment_trace(cs, alpha->inertia(2, 2))));
    const Mat3 from_trace = inertia_of(field_integrals(cs, 0.5 * alpha->inertia.trace()));
    EXPECT_LT((from_polar - alpha->inertia).cwiseAbs().maxCoeff(), 1e-13 * alpha->inertia.norm());
    EXPECT_LT((from_trace - alpha->inertia).cwiseAbs().maxCoeff(), 1e-13 * alpha->inertia.norm());
    // The field's integrals are the polyhedron's wherever the field fixes them: its harmonic parts
    // (the coefficients again) and degree 2 whole.
    const StokesCoefficients again = stokes_from_integrals(field_integrals(cs, 0.5 * alpha->inertia.trace()),
                                                           cs.reference_radius, 6, normalized);
    for (std::size_t k = 0; k < cs.C.size(); ++k) {
      EXPECT_NEAR(again.C[k], cs.C[k], 1e-15);
      EXPECT_NEAR(again.S[k], cs.S[k], 1e-15);
    }
  }
}

// A scene's body given by an ICGEM file of KW4 Beta's ellipsoid: its mass is the file's GM / G,
// its inertia the ellipsoid's (from polar_moment or from a consistent inertia), its radius the
// reference radius; and every inconsistent or incomplete description refused by name.
TEST(FieldBody, SceneTakesMassInertiaAndRadiusFromTheField) {
  const auto b = beta();
  const StokesCoefficients cs = stokes_from_integrals(b->integrals(4), b->radius, 4, true);
  std::ostringstream text;
  write_icgem(text, cs, kG * kBetaMass, b->radius, "beta", {});
  const std::string file = scratch("beta.gfc", text.str()).string();
  const double k = b->inertia(2, 2) / (kBetaMass * b->radius * b->radius);
  std::ostringstream polar;
  polar.precision(17);
  polar << "{stokes: " << file << ", polar_moment: " << k << "}";
  const Scene s = parse_scene(field_scene(polar.str()), "s.yaml");
  const Body& body = s.system.body(1);
  ASSERT_TRUE(body.field);
  EXPECT_TRUE(body.rigid);
  EXPECT_NEAR(body.mass, kBetaMass, 1e-15 * kBetaMass);
  EXPECT_EQ(body.radius, b->radius);
  EXPECT_LT((body.inertia - b->inertia).cwiseAbs().maxCoeff(), 1e-13 * b->inertia.norm());
  EXPECT_EQ(body.field->degree, 4);

  std::ostringstream J;
  J.precision(17);
  J << ", inertia: [" << b->inertia(0, 0) << ", " << b->inertia(1, 1) << ", " << b->inertia(2, 2) << "]";
  EXPECT_EQ(scene_error(field_scene("{stokes: " + file + "}", J.str())), "no error");
  EXPECT_NE(scene_error(field_scene("{stokes: " + file + "}", ", inertia: [1e15, 1e15, 1e15]"))
                .find("contradicts the field's degree 2"),
            std::string::npos);
  EXPECT_NE(scene_error(field_scene("{stokes: " + file + "}")).find("give the body's 'inertia' (body frame) or gravity.polar_moment"),
            std::string::npos);
  EXPECT_NE(scene_error(field_scene("{stokes: " + file + ", degree: 6, polar_moment: 0.2}")).find("degree must be 2..4"),
            std::string::npos);
  // A reference radius other than the file's overrides it (an archived file's defect), and says so.
  const Scene overridden = parse_scene(field_scene("{stokes: " + file + ", reference_radius: 300, polar_moment: 0.2}"), "s.yaml");
  ASSERT_FALSE(overridden.warnings.empty());
  EXPECT_NE(overridden.warnings.front().find("gravity.reference_radius 300 overrides the file's"), std::string::npos)
      << overridden.warnings.front();
  EXPECT_NE(scene_error(field_scene("{stokes: " + file + ", polar_moment: 0.2}", ", density: 2000")).find("cannot have a 'density'"),
            std::string::npos);
  std::string undeclared = field_scene(polar.str());
  undeclared.erase(0, undeclared.find('\n') + 1);
  EXPECT_NE(scene_error(undeclared).find("declare the scene's units"), std::string::npos);
  const std::string table = scratch("beta.txt", "2 0 -0.1 0\n2 2 0.03 0\n").string();
  EXPECT_NE(scene_error(field_scene("{stokes: " + table + ", format: table, polar_moment: 0.3}")).find("reference radius"),
            std::string::npos);
  EXPECT_NE(scene_error(field_scene("{stokes: " + table + ", reference_radius: 300, normalized: true, polar_moment: 0.3}"))
                .find("say the field file's 'format'"),
            std::string::npos);
  EXPECT_NE(scene_error(field_scene("{stokes: " + table + ", format: table, reference_radius: 300, normalized: true, "
                                    "polar_moment: 0.3}"))
                .find("a table gives no GM"),
            std::string::npos);
  // A polar moment too small for the field's degree 2: no rigid body has that inertia.
  EXPECT_NE(scene_error(field_scene("{stokes: " + file + ", polar_moment: 0.01}")).find("inertia from its field"),
            std::string::npos);
}
