#include "slice/mesh.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <new>
#include <sstream>
#include <tuple>

#include "slice/error.hpp"

namespace slice {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;

constexpr const char* kMeshFix =
    "give a closed triangle mesh (OBJ or STL), its faces counter-clockwise seen from outside";
constexpr const char* kSimplifyFix =
    "simplify (decimate) the mesh, e.g. with MeshLab or Blender: an excavation's surface needs "
    "thousands of triangles, not millions";

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string at_line(const std::filesystem::path& file, std::size_t line) {
  return file.string() + ":" + std::to_string(line);
}

TriangleMesh read_obj(const std::filesystem::path& file, std::istream& in) {
  TriangleMesh m;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    std::istringstream ls(text);
    std::string tag;
    if (!(ls >> tag)) continue;
    if (tag == "v") {
      Vec3 x;
      if (!(ls >> x.x() >> x.y() >> x.z()) || !x.allFinite())
        throw Error(at_line(file, line), "a vertex needs three finite coordinates", kMeshFix);
      m.vertices.push_back(x);
    } else if (tag == "f") {
      std::vector<std::int64_t> face;
      for (std::string item; ls >> item;) {
        std::int64_t k = 0;
        try {
          k = std::stoll(item.substr(0, item.find('/')));
        } catch (const std::exception&) {
          throw Error(at_line(file, line), "face entry \"" + item + "\" is no vertex number",
                      kMeshFix);
        }
        const auto n = std::int64_t(m.vertices.size());
        const std::int64_t index = k > 0 ? k - 1 : n + k;  // negative: counted from the end
        if (k == 0 || index < 0 || index >= n)
          throw Error(at_line(file, line),
                      "face refers to vertex " + item + " of " + std::to_string(n) + " so far",
                      kMeshFix);
        face.push_back(index);
      }
      if (face.size() < 3)
        throw Error(at_line(file, line), "a face needs at least three vertices", kMeshFix);
      for (std::size_t k = 1; k + 1 < face.size(); ++k)
        m.triangles.push_back({face[0], face[k], face[k + 1]});
    }
  }
  return m;
}

/// STL has no shared vertices: equal points become one vertex.
struct Welder {
  TriangleMesh m;
  std::map<std::tuple<double, double, double>, std::int64_t> index;
  std::int64_t add(const Vec3& x) {
    const auto [it, fresh] =
        index.emplace(std::make_tuple(x.x(), x.y(), x.z()), std::int64_t(m.vertices.size()));
    if (fresh) m.vertices.push_back(x);
    return it->second;
  }
};

// Binary STL: an 80-byte header, a 4-byte triangle count, 50 bytes a triangle.
constexpr std::size_t kStlHeader = 84, kStlTriangle = 50;

// ASCII STL is text; binary STL is not (its count and floats hold bytes such as 0 that no text
// has), even when its header starts with "solid" as many exporters write it.
bool is_text(const std::string& bytes) {
  return std::none_of(bytes.begin(), bytes.end(), [](char ch) {
    const auto u = static_cast<unsigned char>(ch);
    return (u < 0x20 && !std::isspace(u)) || u == 0x7f;
  });
}

// A binary STL whose count field disagrees with its size: both numbers, as the file has them.
[[noreturn]] void bad_stl_count(const std::filesystem::path& file, std::size_t size,
                                std::uint32_t count) {
  const std::string fix =
      "the file is truncated or damaged: export the mesh again (binary STL: 84 + 50 x "
      "triangles bytes), or as OBJ";
  if (size < kStlHeader)
    throw Error(file.string(),
                "is a binary STL of " + std::to_string(size) +
                    " bytes, shorter than its 84-byte header and triangle count",
                fix);
  const std::size_t held = (size - kStlHeader) / kStlTriangle;
  const std::size_t rest = (size - kStlHeader) % kStlTriangle;
  throw Error(file.string(),
              "its binary STL header says " + std::to_string(count) + " triangles (" +
                  std::to_string(kStlHeader + kStlTriangle * std::size_t(count)) +
                  " bytes) but the file has " + std::to_string(size) +
                  " bytes: " + std::to_string(held) + " whole triangles" +
                  (rest ? " and " + std::to_string(rest) + " bytes more" : std::string()),
              fix);
}

TriangleMesh read_stl(const std::filesystem::path& file, const std::string& bytes) {
  Welder w;
  // Binary if the size matches the count (ASCII files may also start with "solid"), or if the
  // file is not text at all: then the count is wrong.
  std::uint32_t count = 0;
  if (bytes.size() >= kStlHeader) std::memcpy(&count, bytes.data() + 80, 4);
  const bool binary =
      bytes.size() >= kStlHeader && bytes.size() == kStlHeader + kStlTriangle * std::size_t(count);
  if (!binary && !is_text(bytes)) bad_stl_count(file, bytes.size(), count);
  if (binary) {
    for (std::size_t t = 0; t < count; ++t) {
      std::array<std::int64_t, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        float c[3];
        std::memcpy(c, bytes.data() + kStlHeader + kStlTriangle * t + 12 + 12 * std::size_t(k), 12);
        const Vec3 x(c[0], c[1], c[2]);
        if (!x.allFinite())
          throw Error(file.string(),
                      "triangle " + std::to_string(t + 1) + " has a non-finite point", kMeshFix);
        tri[std::size_t(k)] = w.add(x);
      }
      w.m.triangles.push_back(tri);
    }
    return w.m;
  }
  std::istringstream in(bytes);
  std::string text;
  std::vector<std::int64_t> loop;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    std::istringstream ls(text);
    std::string tag;
    if (!(ls >> tag)) continue;
    tag = lower(tag);
    if (tag == "vertex") {
      Vec3 x;
      if (!(ls >> x.x() >> x.y() >> x.z()) || !x.allFinite())
        throw Error(at_line(file, line), "a vertex needs three finite coordinates", kMeshFix);
      loop.push_back(w.add(x));
    } else if (tag == "endloop") {
      if (loop.size() != 3)
        throw Error(at_line(file, line),
                    "an STL facet has 3 vertices, not " + std::to_string(loop.size()), kMeshFix);
      w.m.triangles.push_back({loop[0], loop[1], loop[2]});
      loop.clear();
    }
  }
  return w.m;
}

}  // namespace

TriangleMesh read_mesh(const std::filesystem::path& file) {
  const std::string ext = lower(file.extension().string());
  if (ext != ".obj" && ext != ".stl")
    throw Error(file.string(), "is neither .obj nor .stl", "give an OBJ or STL file");
  // By its size, before a byte is read: a damaged or sparse file of gigabytes would otherwise
  // take seconds and gigabytes of memory to refuse.
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxMeshFileBytes)
    throw Error(file.string(),
                "is " + std::to_string(size >> 20) + " MiB, more than the " +
                    std::to_string(kMaxMeshFileBytes >> 20) + " MiB a mesh zone may have",
                kSimplifyFix);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string(), "cannot be read", "check the path");
  TriangleMesh m;
  try {
    if (ext == ".obj") {
      m = read_obj(file, in);
    } else {
      std::ostringstream all;
      all << in.rdbuf();
      m = read_stl(file, all.str());
    }
  } catch (const std::bad_alloc&) {
    throw Error(file.string(), "needs more memory to read than this machine has", kSimplifyFix);
  }
  if (m.triangles.empty()) throw Error(file.string(), "has no triangles", kMeshFix);
  return m;
}

double check_solid_mesh(const TriangleMesh& mesh, const std::string& where) {
  const auto fail = [&](const std::string& what) { throw Error(where, what, kMeshFix); };
  if (mesh.triangles.size() < 4) fail("a closed mesh needs at least 4 triangles");
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const Vec3& x : mesh.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double size = (hi - lo).norm();
  // Every directed edge once, and its reverse once: closed, manifold, consistently oriented.
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> edges;
  double volume = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 &a = mesh.vertices[std::size_t(tri[0])], &b = mesh.vertices[std::size_t(tri[1])],
               &c = mesh.vertices[std::size_t(tri[2])];
    if ((b - a).cross(c - a).norm() <= 1e-12 * size * size)
      fail("triangle " + std::to_string(t + 1) + " has no area");
    volume += a.dot(b.cross(c)) / 6;
    for (int k = 0; k < 3; ++k) {
      const auto e = std::make_pair(tri[std::size_t(k)], tri[std::size_t((k + 1) % 3)]);
      if (!edges.emplace(e, t).second)
        fail("the edge of vertices " + std::to_string(e.first + 1) + " and " +
             std::to_string(e.second + 1) +
             " is run the same way by two triangles (not manifold or not consistently oriented)");
    }
  }
  for (const auto& [e, t] : edges)
    if (!edges.count({e.second, e.first}))
      fail("the mesh is open: the edge of vertices " + std::to_string(e.first + 1) + " and " +
           std::to_string(e.second + 1) + " (triangle " + std::to_string(t + 1) +
           ") has no neighbour");
  Surface s;
  std::vector<Surface::Vertex_index> v;
  for (const Vec3& x : mesh.vertices) v.push_back(s.add_vertex(Point(x.x(), x.y(), x.z())));
  for (const auto& tri : mesh.triangles)
    if (s.add_face(v[std::size_t(tri[0])], v[std::size_t(tri[1])], v[std::size_t(tri[2])]) ==
        Surface::null_face())
      fail("CGAL could not build a surface from the triangles (not manifold at a vertex)");
  if (CGAL::Polygon_mesh_processing::does_self_intersect(s)) fail("the mesh intersects itself");
  if (volume <= 0)
    fail("the mesh is inside out (its faces go clockwise seen from outside: negative volume)");
  return volume;
}

struct MeshInside::Impl {
  explicit Impl(const TriangleMesh& mesh) {
    std::vector<Surface::Vertex_index> v;
    for (const Vec3& x : mesh.vertices) v.push_back(surface.add_vertex(Point(x.x(), x.y(), x.z())));
    for (const auto& tri : mesh.triangles)
      surface.add_face(v[std::size_t(tri[0])], v[std::size_t(tri[1])], v[std::size_t(tri[2])]);
    side = std::make_unique<CGAL::Side_of_triangle_mesh<Surface, Kernel>>(surface);
  }
  Surface surface;  // the side functor keeps a pointer to it (and builds its AABB tree)
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Surface, Kernel>> side;
};

MeshInside::MeshInside(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>(mesh)) {}
MeshInside::~MeshInside() = default;
MeshInside::MeshInside(MeshInside&&) noexcept = default;
MeshInside& MeshInside::operator=(MeshInside&&) noexcept = default;

bool MeshInside::operator()(const Vec3& x) const {
  return (*impl_->side)(Point(x.x(), x.y(), x.z())) == CGAL::ON_BOUNDED_SIDE;
}

}  // namespace slice
