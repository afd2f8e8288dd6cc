#pragma once
// Triangle meshes of dress forms: reading OBJ and PLY, writing OBJ, closedness checks.
// Coordinates are kept as read; FormModel converts them to centimetres.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace garmcap::calib {

/// An indexed triangle mesh. `vertices[i]` is one point (x, y, z); `faces[j]` holds three
/// indices into `vertices`, counter-clockwise seen from outside. Polygons of the input files are
/// fanned into triangles.
struct TriMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;

  /// Axis-aligned bounds; both are zero for an empty mesh.
  Eigen::Vector3d minCorner() const;
  Eigen::Vector3d maxCorner() const;
  /// Multiplies every coordinate by `factor` (unit conversion).
  void scale(double factor);
  /// Appends `other` (indices shifted), used to assemble a form from closed parts.
  void append(const TriMesh& other);
};

/// Reads a Wavefront OBJ (`v` and `f` records; `vt`/`vn` indices and other records ignored;
/// negative indices resolved). Throws drafts::FileError when unreadable and drafts::ParseError
/// "<file>: line N: <reason>" when malformed (bad number, index out of range, no faces).
TriMesh readObj(const std::filesystem::path& path);

/// Reads a PLY (ascii or binary_little_endian) with `vertex` x/y/z (float or double) and a
/// `face` list of vertex indices. Throws like readObj.
TriMesh readPly(const std::filesystem::path& path);

/// readObj or readPly by extension (.obj / .ply, case-insensitive); other extensions throw.
TriMesh readMesh(const std::filesystem::path& path);

/// Writes OBJ with 4 decimals (1e-4 cm for a form in cm), atomically.
void writeObj(const std::filesystem::path& path, const TriMesh& mesh, const std::string& comment);

/// Edge-manifold check of a closed surface: the number of undirected edges not shared by exactly
/// two faces (0 for a closed mesh). Faces with repeated indices count as defects too.
std::size_t openEdgeCount(const TriMesh& mesh);

}  // namespace garmcap::calib
