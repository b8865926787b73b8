#pragma once
// Test configurations of two bodies (R: B's centre of mass minus A's, in A's frame; C: B's
// frame → A's frame), evaluated from the initial conditions of the papers:
// Hou, Scheeres & Xin 2017 §5.1–5.2; Fahnestock et al. 2006 Table 2 scenarios 1, 2, 4;
// Ho et al. 2021 (SIANS 1999KW4); the GUBAS example (Davis & Scheeres 2020).
#include "shapes.hpp"

#include <noether/solid.hpp>

#include <memory>
#include <string>
#include <vector>

namespace noether::test {

struct Configuration {
  std::string name;
  std::shared_ptr<const Solid> A, B;
  Vec3 R;
  Mat3 C;
};

inline Mat3 rows(std::initializer_list<std::initializer_list<double>> r) {
  Mat3 m;
  int i = 0;
  for (const auto& row : r) {
    int j = 0;
    for (double v : row) m(i, j++) = v;
    ++i;
  }
  return m;
}

inline Configuration hou_octahedra() {
  return {"hou_oct", make_polyhedron(shipped_mesh("hou2017_A.obj"), 2000, false),
          make_polyhedron(shipped_mesh("hou2017_B.obj"), 2000, false),
          Vec3(4.199557712835e+00, -2.575384224018e+00, 8.550503583142e-01),
          rows({{8.594469678684e-01, 4.886058147592e-01, 1.503837331804e-01},
                {-5.037980617469e-01, 8.594469678684e-01, 8.682408883347e-02},
                {-8.682408883347e-02, -1.503837331804e-01, 9.848077530122e-01}})};
}

inline std::vector<Configuration> fahnestock_octahedra() {
  auto B2 = make_polyhedron(shipped_mesh("fahnestock2006_B2.obj"), 2500, true);
  auto B1 = make_polyhedron(shipped_mesh("fahnestock2006_B1.obj"), 2500, true);
  return {{"fahn_oct_1", B2, B1, Vec3(-1.399754796238e+00, 2.436371521215e+00, -6.582740006176e-03),
           rows({{6.424602799698e-01, 7.599995062762e-01, 9.821170562199e-02},
                 {-7.605673549436e-01, 6.167072959552e-01, 2.030010091345e-01},
                 {9.371279131048e-02, -2.051167023321e-01, 9.742407562657e-01}})},
          {"fahn_oct_2", B2, B1, Vec3(0, 6, 0), rows({{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}})},
          {"fahn_oct_4", B2, B1, Vec3(-0.5, 1.8, 1.1), Mat3::Identity()}};
}

inline Configuration kw4_ellipsoids() {
  const double VA = 4.0 / 3.0 * M_PI * 766 * 747.5 * 673.5, VB = 4.0 / 3.0 * M_PI * 285 * 231.5 * 174.5;
  return {"kw4_ell", make_ellipsoid(Vec3(766, 747.5, 673.5), 2.353e12 / VA),
          make_ellipsoid(Vec3(285, 231.5, 174.5), 1.35e11 / VB),
          Vec3(-1.967873485084e+03, -1.431329871029e+03, 7.522499202866e+02),
          rows({{1, 0, 0}, {0, -9.982947757948e-01, -5.837414342758e-02}, {0, 5.837414342758e-02, -9.982947757948e-01}})};
}

inline Configuration didymos_gubas() {
  const double rho = 2203.111036687207;
  return {"gubas_example",
          make_polyhedron(read_vertex_facet_csv(source_path("examples/shapes/Didymos_A_vert_met.csv"),
                                                source_path("examples/shapes/Didymos_A_facet.csv"), 1.0),
                          rho, true),
          make_ellipsoid(Vec3(103.16, 79.35, 66.13), rho), Vec3(1200, 0, 0), Mat3::Identity()};
}

inline Configuration kw4_polyhedra() {
  return {"kw4", make_polyhedron(shipped_mesh("a66391_1999kw4_primary.obj", 1000), 1970, true),
          make_polyhedron(shipped_mesh("a66391_1999kw4_secondary.obj", 1000), 2810, true),
          Vec3(-1.383998608715e+03, -2.151135994096e+03, -2.025592629418e+02),
          rows({{-5.393803000168e-01, 8.241676837856e-01, -1.726746100539e-01},
                {-8.383537169523e-01, -5.448172873749e-01, 1.836215264578e-02},
                {-7.894261983268e-02, 1.546665845650e-01, 9.848077530122e-01}})};
}

}  // namespace noether::test
