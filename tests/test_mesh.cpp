// Shape files read within bounds, and surfaces that cross themselves refused by name (mesh.hpp).
#include <noether/error.hpp>
#include <noether/mesh.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "shapes.hpp"

using namespace noether;
using namespace noether::test;

namespace {

// Two meshes as one (the second's vertex indices shifted).
Mesh merged(const Mesh& a, const Mesh& b) {
  Mesh m;
  m.source = "merged";
  m.vertices.resize(3, a.vertices.cols() + b.vertices.cols());
  m.vertices << a.vertices, b.vertices;
  m.faces = a.faces;
  for (auto f : b.faces) {
    for (int& j : f) j += static_cast<int>(a.vertices.cols());
    m.faces.push_back(f);
  }
  return m;
}

Mesh shifted(Mesh m, const Vec3& by) {
  m.vertices.colwise() += by;
  return m;
}

std::string refusal(const Mesh& m) {
  try {
    validate_mesh(m);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("noether-test-mesh-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

}  // namespace

TEST(MeshSelfIntersection, ShippedAndGeneratedSurfacesDoNotCrossThemselves) {
  for (const char* file : {"a66391_1999kw4_primary.obj", "a66391_1999kw4_secondary.obj",
                           "fahnestock2006_B1.obj", "fahnestock2006_B2.obj", "hou2017_A.obj",
                           "hou2017_B.obj"}) {
    const Mesh m = shipped_mesh(file);
    EXPECT_FALSE(find_self_intersection(m)) << file;
    EXPECT_EQ(refusal(m), "") << file;
  }
  const Mesh didymos = read_vertex_facet_csv(source_path("examples/shapes/Didymos_A_vert_met.csv"),
                                             source_path("examples/shapes/Didymos_A_facet.csv"), 1.0);
  EXPECT_FALSE(find_self_intersection(didymos));
  // A flat-faced box (coplanar neighbours), a fine sphere (20,480 faces) and a thin plate far
  // from the origin (faces 1e-3 of the size apart, at 1e6 sizes from the origin).
  EXPECT_FALSE(find_self_intersection(box_mesh(Vec3(1, 2, 3))));
  EXPECT_FALSE(find_self_intersection(ellipsoid_mesh(Vec3(1, 0.8, 0.6), 5)));
  EXPECT_FALSE(find_self_intersection(shifted(box_mesh(Vec3(1, 1, 1e-3)), Vec3(2e6, 0, 0))));
  // Two bodies in one file, apart: allowed (a contact binary's lobes given separately).
  EXPECT_FALSE(find_self_intersection(merged(box_mesh(Vec3(1, 1, 1)), shifted(box_mesh(Vec3(1, 1, 1)), Vec3(2.5, 0, 0)))));
}

TEST(MeshSelfIntersection, OverlappingPiecesAreRefusedNamingTwoFaces) {
  // Two boxes that interpenetrate: each closed and outward, the union's volume positive — the
  // inertia integrals would count the overlap twice.
  const Mesh overlap = merged(box_mesh(Vec3(1, 1, 1)), shifted(box_mesh(Vec3(1, 1, 1)), Vec3(1.5, 0.3, 0.2)));
  const std::string why = refusal(overlap);
  EXPECT_NE(why.find("merged: face "), std::string::npos) << why;
  EXPECT_NE(why.find(" cross or touch: the surface intersects itself"), std::string::npos) << why;
  const auto pair = find_self_intersection(overlap);
  ASSERT_TRUE(pair);
  EXPECT_LT(pair->first, 12u);   // one face of each box
  EXPECT_GE(pair->second, 12u);
  // Boxes touching face to face (coplanar faces in contact): touching is refused.
  const Mesh touching = merged(box_mesh(Vec3(1, 1, 1)), shifted(box_mesh(Vec3(1, 1, 1)), Vec3(2, 0.5, 0.5)));
  EXPECT_TRUE(find_self_intersection(touching));
  // A tetrahedron whose tip touches another's face at one point.
  const Mesh tip = merged(tetrahedron_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)),
                          tetrahedron_mesh(Vec3(0.25, 0.25, 0), Vec3(1, 1, -1), Vec3(0, 1, -1), Vec3(1, 0, -1)));
  EXPECT_TRUE(find_self_intersection(tip));
  // The same, 1e-6 of the size apart: not touching.
  const Mesh near = merged(tetrahedron_mesh(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)),
                           tetrahedron_mesh(Vec3(0.25, 0.25, -1e-6), Vec3(1, 1, -1), Vec3(0, 1, -1), Vec3(1, 0, -1)));
  EXPECT_FALSE(find_self_intersection(near));
}

TEST(MeshPieces, EveryPointIsEnclosedAtMostOnce) {
  const Mesh outer = box_mesh(Vec3(2, 2, 2));
  Mesh inner = box_mesh(Vec3(1, 1, 1));
  // Nested, both outward: the surfaces do not meet, but the inner box would count twice.
  std::string why = refusal(merged(outer, inner));
  EXPECT_NE(why.find("merged: face 13: the piece of the surface this face belongs to lies inside another solid piece"), std::string::npos) << why;
  // The inner box reversed: a cavity, allowed, and the volume is the shell's.
  for (auto& f : inner.faces) std::swap(f[1], f[2]);
  const Mesh hollow = merged(outer, inner);
  EXPECT_EQ(refusal(hollow), "");
  EXPECT_NEAR(mesh_volume(hollow), 64.0 - 8.0, 1e-12);
  // An inward piece beside a solid one, outside it: refused.
  why = refusal(merged(outer, shifted(inner, Vec3(5, 0, 0))));
  EXPECT_NE(why.find("points inwards (a cavity) but lies inside no solid piece"), std::string::npos) << why;
  // More pieces than the bound: refused by count.
  Mesh many = box_mesh(Vec3(0.1, 0.1, 0.1));
  for (std::size_t i = 1; i <= kMaxMeshPieces; ++i)
    many = merged(many, shifted(box_mesh(Vec3(0.1, 0.1, 0.1)), Vec3(static_cast<double>(i), 0, 0)));
  why = refusal(many);
  EXPECT_NE(why.find("the mesh has 65 separate pieces; noether checks at most 64"), std::string::npos) << why;
}

TEST(MeshSelfIntersection, AVertexPushedThroughTheFarSideIsRefused) {
  // A sphere (320 faces) with one vertex pushed through the far side, to −1.3 × where it was:
  // its five faces now reach across the body and through the faces round the antipode. (An
  // octahedron's apex pushed through the opposite apex would not do: its faces all share the
  // equator, and the surface turns inside out without crossing — refused as inward.)
  Mesh m = ellipsoid_mesh(Vec3(1, 1, 1), 2);
  m.vertices.col(0) *= -1.3;
  EXPECT_TRUE(find_self_intersection(m));
  EXPECT_NE(refusal(m).find("intersects itself"), std::string::npos) << refusal(m);
}

TEST(MeshSelfIntersection, FacesFoldedOntoEachOtherAreFound) {
  // Two triangles on the edge (0, 1): folded flat onto each other, or unfolded flat.
  Mesh m;
  m.source = "fold";
  m.vertices.resize(3, 4);
  m.vertices << 0, 1, 0.5, 0.6,  //
      0, 0, 1, 0.8,              //
      0, 0, 0, 0;
  m.faces = {{0, 1, 2}, {1, 0, 3}};
  EXPECT_TRUE(find_self_intersection(m));
  m.vertices(1, 3) = -0.8;  // the other side of the shared edge: flat, not folded
  EXPECT_FALSE(find_self_intersection(m));
  m.vertices(2, 3) = 1e-3;  // and bent a little out of the plane
  EXPECT_FALSE(find_self_intersection(m));
}

TEST(MeshFiles, DevicesAndOversizedFilesAreRefusedBeforeReading) {
  try {
    read_obj("/dev/zero", 1.0);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/zero: the shape file is not a regular file"), std::string::npos) << e.what();
  }
  // A sparse file one byte over the bound: refused from its size, without reading it.
  const auto big = scratch("big.obj");
  { std::ofstream(big) << "v 0 0 0\n"; }
  std::filesystem::resize_file(big, kMaxShapeFileBytes + 1);
  try {
    read_obj(big, 1.0);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("noether reads shape files of at most 1073741824 bytes"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(big.parent_path());
}

TEST(MeshFiles, CoordinatesThatOverflowWhenScaledAreRefused) {
  const auto file = scratch("overflow.obj");
  { std::ofstream(file) << "v 0 0 0\nv 1e306 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"; }
  EXPECT_NO_THROW(read_obj(file, 1.0));
  try {
    read_obj(file, 1000.0);  // km → m
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2 is not finite in the scene's length unit"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(file.parent_path());
}

TEST(MeshFiles, MoreFacesThanTheBoundAreRefusedAtTheLineThatCrossesIt) {
  // One polygon line fanned into kMaxMeshFaces + 1 triangles (a few MB, not millions of lines).
  const auto file = scratch("fan.obj");
  {
    std::ofstream out(file);
    const std::size_t n = kMaxMeshFaces + 3;
    out << "v 1 0 0\nv 0 1 0\nv 0 0 1\n";
    out << "f";
    for (std::size_t i = 0; i < n; ++i) out << " " << 1 + i % 3;
    out << "\n";
  }
  try {
    read_obj(file, 1.0);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("fan.obj:4: more than 4194304 faces"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(file.parent_path());
}
