#include "garmcap/calib/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "../common/temp_folder.h"
#include "garmcap/calib/slicer.h"
#include "garmcap/drafts/file_io.h"

namespace garmcap::calib {
namespace {

namespace fs = std::filesystem;

// One folder for the binary's files, removed when it exits.
fs::path meshTempDir() {
  static const garmcap::testing::TempFolder folder("garmcap_calib_mesh");
  return folder.path();
}

const char* kTetraObj =
    "# tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\n"
    "f 1/1 3/1 2/1\nf 1 2 4\nf -4 -1 -2\nf 2 3 4\n";

TEST(Mesh, ReadsObjWithTextureIndicesAndNegativeIndices) {
  const fs::path p = meshTempDir() / "tetra.obj";
  drafts::writeFileAtomic(p, kTetraObj);
  const TriMesh m = readMesh(p);
  EXPECT_EQ(m.vertices.size(), 4u);
  ASSERT_EQ(m.faces.size(), 4u);
  EXPECT_EQ(m.faces[2], Eigen::Vector3i(0, 3, 2));
  EXPECT_EQ(openEdgeCount(m), 0u);
}

TEST(Mesh, ObjErrorsNameFileAndLine) {
  const fs::path p = meshTempDir() / "bad.obj";
  drafts::writeFileAtomic(p, "v 0 0 0\nv 1 0 0\nv 0 1 x\n");
  try {
    readObj(p);
    FAIL() << "no exception";
  } catch (const drafts::ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj: line 3"), std::string::npos) << e.what();
  }
  drafts::writeFileAtomic(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
  EXPECT_THROW(readObj(p), drafts::ParseError);
}

TEST(Mesh, ReadsAsciiAndBinaryPly) {
  const fs::path a = meshTempDir() / "tetra_ascii.ply";
  drafts::writeFileAtomic(a,
                          "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 4\n"
                          "property list uchar int vertex_indices\nend_header\n"
                          "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const TriMesh ma = readMesh(a);
  EXPECT_EQ(ma.faces.size(), 4u);
  EXPECT_EQ(openEdgeCount(ma), 0u);

  std::string bin =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\n"
      "property double y\nproperty double z\nelement face 4\n"
      "property list uchar uint vertex_indices\nend_header\n";
  const double v[12] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 2};
  bin.append(reinterpret_cast<const char*>(v), sizeof v);
  const std::uint32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& face : f) {
    bin.push_back(3);
    bin.append(reinterpret_cast<const char*>(face), sizeof face);
  }
  const fs::path b = meshTempDir() / "tetra_bin.ply";
  drafts::writeFileAtomic(b, bin);
  const TriMesh mb = readMesh(b);
  ASSERT_EQ(mb.vertices.size(), 4u);
  EXPECT_DOUBLE_EQ(mb.vertices[3].z(), 2.0);
  EXPECT_EQ(openEdgeCount(mb), 0u);
}

// Found by fuzz_mesh: a face index of 1e72 was converted to long (undefined), and an element
// declaring 10^18 entries kept the reader looping. Both are corrupt headers, refused by name.
TEST(Mesh, PlyCountsAndIndicesTheFileCannotHoldAreRefused) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\n";
  const std::string verts = "0 0 0\n1 0 0\n0 1 0\n";
  const std::string faceHead =
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {head + faceHead + verts + "3 0 1 1e72\n", "vertex index"},
      {head + faceHead + verts + "3 0 1 -2\n", "vertex index"},
      {head + faceHead + verts + "3 0 1 0.5\n", "vertex index"},
      {head + faceHead + verts + "1e12 0 1 2\n", "list count"},
      {"ply\nformat ascii 1.0\nelement vertex 1000000000000000000\nproperty float x\n"
       "end_header\n0\n",
       "more than the file holds"},
      {"ply\nformat ascii 1.0\nelement vertex many\nend_header\n", "not 'element NAME COUNT'"},
  };
  const fs::path p = meshTempDir() / "corrupt.ply";
  for (const auto& [text, expected] : cases) {
    drafts::writeFileAtomic(p, text);
    try {
      readMesh(p);
      ADD_FAILURE() << "no exception for: " << text;
    } catch (const drafts::ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  // An element without properties (a comment-like block some exporters write) holds nothing.
  drafts::writeFileAtomic(
      p, head + "element material 1000000000000\n" + faceHead + verts + "3 0 1 2\n");
  EXPECT_EQ(readMesh(p).faces.size(), 1u);
}

TEST(Mesh, OpenMeshHasOpenEdges) {
  const fs::path p = meshTempDir() / "open.obj";
  drafts::writeFileAtomic(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n");
  EXPECT_EQ(openEdgeCount(readObj(p)), 3u);
}

// A closed prism with a regular n-gon section: every slice is that polygon.
TriMesh prism(int n, double radius, double h) {
  TriMesh m;
  for (int k = 0; k < 2; ++k) {
    for (int i = 0; i < n; ++i) {
      const double t = 2 * std::numbers::pi * i / n;
      m.vertices.emplace_back(radius * std::cos(t), k * h, radius * std::sin(t));
    }
  }
  m.vertices.emplace_back(0, 0, 0);
  m.vertices.emplace_back(0, h, 0);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.faces.emplace_back(i, j, n + j);
    m.faces.emplace_back(i, n + j, n + i);
    m.faces.emplace_back(2 * n, j, i);
    m.faces.emplace_back(2 * n + 1, n + i, n + j);
  }
  return m;
}

TEST(Slicer, SliceOfPrismIsItsPolygon) {
  for (int n : {3, 8, 50}) {
    const TriMesh m = prism(n, 10.0, 5.0);
    ASSERT_EQ(openEdgeCount(m), 0u);
    // A plane through the top ring returns it exactly (vertices on the plane count as above).
    for (double y : {0.3, 2.5, 4.99, 5.0}) {
      const auto loops = sliceMesh(m, y);
      ASSERT_EQ(loops.size(), 1u) << "n " << n << " y " << y;
      EXPECT_NEAR(polygonPerimeter(loops[0]), 2 * n * 10.0 * std::sin(std::numbers::pi / n), 1e-9);
      EXPECT_NEAR(polygonPerimeter(convexHull(loops)), polygonPerimeter(loops[0]), 1e-9);
    }
    EXPECT_TRUE(sliceMesh(m, 5.01).empty());
    EXPECT_TRUE(sliceMesh(m, 0.0).empty());  // the bottom ring counts as above: nothing below
  }
}

TEST(Slicer, HullBridgesConcavityAndSeparatesComponents) {
  TriMesh two = prism(4, 1.0, 2.0);
  TriMesh other = prism(4, 1.0, 2.0);
  for (auto& v : other.vertices)
    v.x() += 5;
  two.append(other);
  const auto loops = sliceMesh(two, 1.0);
  ASSERT_EQ(loops.size(), 2u);
  // Hull of two unit diamonds 5 apart: four diamond edges plus two bridging edges of 5.
  EXPECT_NEAR(polygonPerimeter(convexHull(loops)), 4 * std::sqrt(2.0) + 2 * 5.0, 1e-9);
  const Eigen::Vector2d origin(0, 0);
  EXPECT_NE(pointInPolygon(loops[0], origin), pointInPolygon(loops[1], origin));
}

}  // namespace
}  // namespace garmcap::calib
