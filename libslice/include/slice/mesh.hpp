#pragma once
// Closed triangle meshes for excavations of any shape (a cavern, a pit): read from OBJ or STL,
// checked (closed, manifold, outward, not self-intersecting), and asked which points lie
// inside, with CGAL's exact predicates (Side_of_triangle_mesh). CGAL stays in mesh.cpp.
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "slice/geometry.hpp"

namespace slice {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::int64_t, 3>> triangles;  // vertex indices, counter-clockwise
                                                       //   seen from outside
};

/// The largest mesh file read_mesh reads: 256 MiB, about 5 million triangles in binary STL, 2
/// to 3 million in OBJ or ASCII STL; an excavation needs thousands. Reading takes about 3 times
/// the file's size in memory, so a larger file is refused by its size, before it is read.
constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t(256) << 20;

/// Reads an OBJ (`v x y z`, `f a b c ...`: polygons are split into fans, `a/b/c` and negative
/// indices accepted, everything else ignored) or STL file (ASCII or binary; equal points are
/// welded), by its extension (.obj, .stl, any case). Throws Error naming the file and line; a
/// binary STL whose triangle count disagrees with its size is refused with both numbers.
TriangleMesh read_mesh(const std::filesystem::path& file);

/// Throws Error(where, what, fix) unless the mesh bounds a solid: at least 4 triangles, no
/// triangle without area (relative to the mesh's size), every edge shared by exactly two
/// triangles that run it in opposite directions (closed, manifold, consistently oriented),
/// no two triangles intersecting but at shared edges and corners, and oriented outward
/// (positive volume). Returns the enclosed volume.
double check_solid_mesh(const TriangleMesh& mesh, const std::string& where);

/// Which points lie strictly inside a checked mesh (points on it count as outside). Exact
/// predicates: the answer does not depend on rounding.
class MeshInside {
 public:
  explicit MeshInside(const TriangleMesh& mesh);
  ~MeshInside();
  MeshInside(MeshInside&&) noexcept;
  MeshInside& operator=(MeshInside&&) noexcept;
  bool operator()(const Vec3& x) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slice
