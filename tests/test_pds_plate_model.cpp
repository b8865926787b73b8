// Plate shape models as the PDS archives them (scene/pds_plate_model.cpp; docs/gravity-fields.md
// "Archived shapes"): 433 Eros' NEAR MSI models from ../shared/data read as archived — 0-based
// offsets, kilometres from the label, the archive's body-fixed frame —, their volumes the
// archive's README's, the homogeneous body's centre of mass ~50 m off the archive's origin, and
// its degree-2 field against NEAR15A's (Eros is nearly homogeneous: Miller et al. 2002); a bad
// offset refused by row; a unit contradicting the label refused.
#include "test_support.hpp"

#include <noether/body_stokes.hpp>
#include <noether/pds3_label.hpp>
#include <noether/pds_plate_model.hpp>
#include <noether/scene.hpp>
#include <noether/stokes_file.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace noether;

namespace {

std::string eros_scene(const std::string& shape, const std::string& more = "") {
  return "units: SI\nbodies:\n  - {name: eros, density: 2670, position: [0, 0, 0], shape: {polyhedron: {file: " + shape +
         more + "}}}\npotential: {plugin: point-mass}\nintegrator: {plugin: lgvi, step: 1}\n"
         "run: {t_end: 1, output_every: 1}\n";
}

}  // namespace

// Volumes 2491.6 and 2526.0 km³ (the README's; Thomas et al. 2002: 2503 ± 25), the centre of
// mass of the homogeneous body 52 m from the 7790-plate model's origin, its axes the archive's
// (frame mesh by default), and C20, C22, S22 at 16 km against NEAR15A's: 1708 plates within
// 0.5 % (measured 0.05, 0.3, 0.3 %), 7790 within 1.5 % (1.0, 1.3, 0.1 %).
TEST(PdsPlateModel, ErosAsArchived) {
  const std::string near = test::shared_data("fields/n15acoeff.lbl");
  if (near.empty() || test::shared_data("eros/eros007790.lbl").empty())
    GTEST_SKIP() << test::absent_data("eros/eros007790.lbl");
  const StokesCoefficients published = read_stokes_file(near, "pds").coefficients;
  struct Model {
    const char* file;
    std::size_t vertices, faces;
    double volume_km3, tolerance;
  };
  for (const Model& m : {Model{"eros/eros001708.lbl", 856, 1708, 2491.6, 0.005},
                         Model{"eros/eros007790.tab", 3897, 7790, 2526.0, 0.015}}) {
    SCOPED_TRACE(m.file);
    const std::string file = test::shared_data(m.file);
    const PdsPlateModel model = read_pds_plate_model(pds3_label_of(file), 1.0);
    EXPECT_EQ(model.mesh.vertices.cols(), static_cast<Eigen::Index>(m.vertices));
    EXPECT_EQ(model.mesh.faces.size(), m.faces);
    EXPECT_EQ(model.unit_in_metres, 1000.0);
    const Scene scene = parse_scene(eros_scene(file), "eros.yaml");
    const Body& eros = scene.system.body(0);
    ASSERT_TRUE(eros.solid);
    EXPECT_NEAR(eros.solid->volume / 1e9, m.volume_km3, 0.05);
    EXPECT_LT(eros.solid->offset.norm(), 100.0);  // the archive's origin: the centre of mass to ~50 m
    EXPECT_TRUE(eros.solid->rotation.isIdentity(0.0));
    const StokesCoefficients cs = body_stokes(scene, "eros", 2, 16000.0, true).coefficients;
    EXPECT_NEAR(cs.c(2, 0) / published.c(2, 0), 1.0, m.tolerance);
    EXPECT_NEAR(cs.c(2, 2) / published.c(2, 2), 1.0, m.tolerance);
    EXPECT_NEAR(cs.s(2, 2) / published.s(2, 2), 1.0, m.tolerance);
  }
  const Scene fine = parse_scene(eros_scene(test::shared_data("eros/eros007790.lbl")), "eros.yaml");
  EXPECT_NEAR(fine.system.body(0).solid->offset.norm(), 52.2, 0.1);
}

// A plate that points past the vertex table is refused by its row; a scene's units that
// contradict the label's are refused; a principal frame may still be asked for.
TEST(PdsPlateModel, ItsErrorsNameTheRow) {
  const std::string label = test::shared_data("eros/eros001708.lbl");
  if (label.empty()) GTEST_SKIP() << test::absent_data("eros/eros001708.lbl");
  const auto dir = std::filesystem::temp_directory_path() / "noether-pds-plates";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(label, dir / "eros001708.lbl", std::filesystem::copy_options::overwrite_existing);
  std::ifstream in(test::shared_data("eros/eros001708.tab"), std::ios::binary);
  std::string table((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Row 857 (the first plate, 46-byte records): its last offset, 97, made 856.
  const std::size_t row = 856 * 46;
  ASSERT_EQ(table.substr(row, 1), "f");
  table.replace(row + 40, 4, " 856");  // bytes 41–44 of the row: the third item's last four
  std::ofstream(dir / "eros001708.tab", std::ios::binary) << table;
  try {
    read_pds_plate_model(dir / "eros001708.lbl", 1.0);
    ADD_FAILURE() << "an offset past the vertices loaded";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("eros001708.tab:857: vertex offset '856' is not one of 0..855"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
  EXPECT_NE(test::scene_error(eros_scene(label, ", units: m")).find("units 'm' contradict"), std::string::npos);
  const Scene principal = parse_scene(eros_scene(label, ", frame: principal"), "eros.yaml");
  EXPECT_FALSE(principal.system.body(0).solid->rotation.isIdentity(1e-3));
}
