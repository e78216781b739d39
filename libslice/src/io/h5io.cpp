#include "slice/h5io.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <future>
#include <limits>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "geometry_check.hpp"
#include "h5/h5.hpp"
#include "slice/error.hpp"
#include "slice/mesh.hpp"
#include "slice/output.hpp"
#include "slice/polytope.hpp"
#include "slice/tolerance.hpp"

namespace slice {
namespace {

namespace fs = std::filesystem;
using h5::Group;
using h5::RowWriter;

// A normal is a unit vector if ||n| - 1| <= this. Normalising in double leaves ~1e-16; 1e-9
// rejects a vector nobody normalised without rejecting rounding. Dimensionless.
constexpr double kUnitTolerance = 1e-9;

// The fix of a refused write: validation runs before the .partial is even created.
constexpr const char* kNotWritten = "nothing was written";
constexpr const char* kWriteFix =
    "check that the directory is writable and the disk is not full; nothing was written";
constexpr const char* kJointsFix = "regenerate it with slice-joints";
constexpr const char* kBlocksFix = "regenerate it with slice-cut";
constexpr const char* kGeometryFix = "regenerate it with slice-vertices";  // /geometry's writer

// Shortest text that reads back as the same double ("nan", "inf", "0.1").
std::string num(double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

std::string row_text(const double* v, std::size_t n) {
  std::string s = "(";
  for (std::size_t i = 0; i < n; ++i) s += (i ? ", " : "") + num(v[i]);
  return s + ")";
}

std::string at(const std::string& dataset, std::size_t row) {
  return dataset + " row " + std::to_string(row);
}

/// A row of a dataset, made into text only if a check fails: the checks run on every row of
/// files of millions of blocks, where building the label each time cost more than the check.
struct At {
  const char* dataset;
  std::size_t row;
  const char* suffix = "";
};
std::string text(const At& a) { return at(a.dataset, a.row) + a.suffix; }
const std::string& text(const std::string& s) { return s; }

std::string str(std::int64_t v) { return std::to_string(v); }
std::string str(std::size_t v) { return std::to_string(v); }

// "000", "001", ...: zero-padded so the groups list in set order.
std::string set_group_name(std::size_t i) {
  const std::string s = std::to_string(i);
  return s.size() < 3 ? std::string(3 - s.size(), '0') + s : s;
}

// --- validation, shared by writers (before writing) and readers (after reading) --------------

class Checker {
 public:
  Checker(std::string where, std::string fix) : where_(std::move(where)), fix_(std::move(fix)) {}
  [[noreturn]] void fail(const std::string& what) const { throw Error(where_, what, fix_); }

  template <class Label>
  void finite(double v, const Label& label) const {
    if (!std::isfinite(v)) fail(text(label) + " is " + num(v));
  }
  template <int N, class Label>
  void finite(const Eigen::Matrix<double, N, 1>& v, const Label& label) const {
    if (!v.allFinite()) fail(text(label) + " is " + row_text(v.data(), N));
  }
  template <class Label>
  void unit(const Vec3& n, const Label& label) const {
    finite(n, label);
    if (std::abs(n.norm() - 1) > kUnitTolerance)
      fail(text(label) + " is " + row_text(n.data(), 3) + ", not a unit vector (length " +
           num(n.norm()) + ")");
  }
  template <class Label>
  void non_negative(double v, const Label& label) const {
    finite(v, label);
    if (v < 0) fail(text(label) + " is " + num(v) + "; it cannot be negative");
  }
  template <class Label>
  void side(std::int64_t v, const Label& label) const {
    if (v < -1 || v > 1) fail(text(label) + " is " + str(v) + "; expected -1, 0 or 1");
  }
  template <class Label>
  void kind(JointKind k, const Label& label) const {
    if (static_cast<std::size_t>(k) >= kJointKindNames.size())
      fail(text(label) + " is " + std::to_string(static_cast<unsigned>(k)) +
           "; expected 0 (rock), 1 (construction) or 2 (boundary)");
  }

 private:
  std::string where_;
  std::string fix_;
};

void check_planes(const Checker& c, const std::string& group, const std::vector<Plane>& planes,
                  std::size_t first_row) {
  for (std::size_t i = 0; i < planes.size(); ++i) {
    c.unit(planes[i].normal, at(group + "/normal", first_row + i));
    c.finite(planes[i].d, at(group + "/d", first_row + i));
  }
}

void check_joints(const Checker& c, const JointSystem& js) {
  if (!std::isfinite(js.length_scale) || js.length_scale <= 0)
    c.fail("/domain attribute length_scale is " + num(js.length_scale) +
           "; expected a positive length");
  check_planes(c, "/domain", js.domain.planes, 0);
  // A section in (x, z) (docs/2d.md): every normal and point has y = 0.
  const auto in_section = [&](const Vec3& v, const char* dataset, std::size_t row) {
    if (js.dimension == 2 && v.y() != 0)
      c.fail(at(dataset, row) + " has y = " + num(v.y()) +
             "; a 2-D file (root attribute dimension 2) has y = 0 everywhere");
  };
  for (std::size_t i = 0; i < js.domain.planes.size(); ++i)
    in_section(js.domain.planes[i].normal, "/domain/normal", i);

  const auto sets = static_cast<std::int64_t>(js.sets.size());
  std::size_t uv_row = 0;
  for (std::size_t i = 0; i < js.joints.size(); ++i) {
    const Joint& j = js.joints[i];
    c.unit(j.plane.normal, At{"/joints/normal", i});
    in_section(j.plane.normal, "/joints/normal", i);
    in_section(j.centre, "/joints/centre", i);
    c.finite(j.plane.d, At{"/joints/d", i});
    c.finite(j.centre, At{"/joints/centre", i});
    c.finite(j.dip_deg, At{"/joints/dip", i});
    c.finite(j.dip_direction_deg, At{"/joints/dip_direction", i});
    c.kind(j.kind, At{"/joints/kind", i});
    if (j.set < -1 || j.set >= sets)
      c.fail(at("/joints/set", i) + " is " + str(std::int64_t{j.set}) +
             "; expected -1 (deterministic) or a set index below " + str(sets) +
             " (the groups of /sets)");
    c.finite(j.friction_angle_deg, At{"/joints/friction_angle", i});
    c.finite(j.cohesion, At{"/joints/cohesion", i});
    c.non_negative(j.tension, At{"/joints/tension", i});
    c.side(j.boundary_side, At{"/joints/boundary_side", i});
    if (j.kind == JointKind::boundary && j.boundary_side == 0)
      c.fail(at("/joints/boundary_side", i) + " is 0 for a boundary joint; expected -1 (keep " +
             "below) or 1 (keep above)");
    if (j.polygon_uv.size() == 1 || j.polygon_uv.size() == 2)
      c.fail("/joints/polygon_offset gives joint " + str(i) + " a polygon of " +
             str(j.polygon_uv.size()) + " vertices; expected none (persistent) or at least 3");
    for (const Vec2& uv : j.polygon_uv) c.finite(uv, At{"/joints/polygon_uv", uv_row++});
  }

  for (std::size_t i = 0; i < js.sets.size(); ++i) {
    const JointSetSpec& s = js.sets[i];
    const std::string g = "/sets/" + set_group_name(i) + " attribute ";
    c.finite(s.dip_deg, g + "dip");
    c.finite(s.dip_direction_deg, g + "dip_direction");
    c.finite(s.spacing, g + "spacing");
    c.finite(s.offset, g + "offset");
    c.finite(s.friction_angle_deg, g + "friction_angle");
    c.finite(s.cohesion, g + "cohesion");
    c.non_negative(s.tension, g + "tension");
    c.kind(s.kind, g + "kind");
    c.side(s.boundary_side, g + "boundary_side");
    if (s.kind == JointKind::boundary && s.boundary_side == 0)
      c.fail(g + "boundary_side is 0 for a boundary set; expected -1 (keep below) or 1 (above)");
    if (s.joint_count < 0)
      c.fail(g + "joint_count is " + str(s.joint_count) + "; it cannot be negative");
    c.non_negative(s.fisher_kappa, g + "fisher_kappa");
    c.non_negative(s.density, g + "density");
    if (s.count < 0) c.fail(g + "count is " + str(s.count) + "; it cannot be negative");
    c.non_negative(s.p32, g + "p32");
    c.non_negative(s.p10, g + "p10");
    c.finite(s.scanline_from, g + "scanline_from");
    c.finite(s.scanline_to, g + "scanline_to");
    for (const double v : {s.size.value, s.size.mean, s.size.sd, s.size.min, s.size.max})
      c.non_negative(v, g + "size parameters");
    c.finite(s.size.exponent, g + "size_exponent");
    c.finite(s.aspect, g + "aspect");
    if (s.sides < 0) c.fail(g + "sides is " + str(s.sides) + "; it cannot be negative");
    c.finite(s.rotation_deg, g + "rotation");
    c.non_negative(s.enlargement, g + "enlargement");
    if (s.candidates < 0)
      c.fail(g + "candidates is " + str(s.candidates) + "; it cannot be negative");
    c.non_negative(s.achieved_p32, g + "achieved_p32");
    c.non_negative(s.achieved_p10, g + "achieved_p10");
  }
  for (const double v : {js.rock.cohesion, js.rock.tension}) c.non_negative(v, "/rock attributes");
  c.finite(js.rock.friction_angle_deg, "/rock attribute friction_angle");

  std::size_t zone_row = 0;
  for (const Region& z : js.zones) {
    check_planes(c, "/zones", z.planes, zone_row);
    zone_row += z.planes.size();
  }
  for (std::size_t k = 0; k < js.zone_meshes.size(); ++k) {
    const TriangleMesh& m = js.zone_meshes[k];
    const std::string which = "/zones mesh " + str(k);
    for (const Vec3& x : m.vertices)
      if (!x.allFinite()) c.fail(which + " has a vertex that is not finite");
    for (const auto& t : m.triangles)
      for (const std::int64_t v : t)
        if (v < 0 || v >= std::int64_t(m.vertices.size()))
          c.fail(which + " has a triangle corner " + str(v) + "; expected a vertex index below " +
                 str(m.vertices.size()));
    try {
      check_solid_mesh(m, which);
    } catch (const Error& e) {
      c.fail(e.where() + " does not bound a solid: " + e.problem());  // the file's fix only
    }
    // As the scene parser refuses it: a mesh whose bounding box has no volume in the domain.
    Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
    for (const Vec3& x : m.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    std::vector<Plane> both = box_planes(lo, hi);
    both.insert(both.end(), js.domain.planes.begin(), js.domain.planes.end());
    if (!analyse_polytope(both, js.options.tolerance * js.length_scale).has_interior)
      c.fail(which + " has no volume inside /domain, so it would remove nothing");
  }

  if (static_cast<std::size_t>(js.options.order) >= kJointOrderNames.size())
    c.fail("/options attribute order is invalid (" +
           std::to_string(static_cast<int>(js.options.order)) + ")");
  c.finite(js.options.min_inscribed_diameter, "/options attribute min_inscribed_diameter");
  c.finite(js.options.max_aspect_ratio, "/options attribute max_aspect_ratio");
  c.finite(js.options.tolerance, "/options attribute tolerance");
  if (js.options.max_blocks < 1)
    c.fail("/options attribute max_blocks is " + str(js.options.max_blocks) + "; expected >= 1");
}

// How far a stored vertex may lie off its faces: slice-vertices keeps every vertex within the
// geometry tolerance of its block's half-spaces in the block frame; storing it in the global frame
// rounds each coordinate once more (half an ulp of the largest coordinate). A writer checks a run
// of blocks with the run's largest coordinate, no more than the file's: what it writes, a reader
// accepts.
double vertex_tolerance(const JointSystem& js, const std::vector<Vec3>& vertices) {
  double coord = 0;
  for (const Vec3& v : vertices) coord = std::max(coord, v.cwiseAbs().maxCoeff());
  const Tolerances tol = Tolerances::from_scale(js.length_scale, js.options.tolerance);
  return 2 * tol.geometry + 8 * std::numeric_limits<double>::epsilon() * coord;
}

// The faces of some blocks: the rows they take in /blocks/face_normal and the per-face datasets.
std::size_t face_count(std::span<const Block> blocks) {
  std::size_t faces = 0;
  for (const Block& b : blocks) faces += b.faces.size();
  return faces;
}

// Block b of the run `g` (the file's block base.block + b; its first face is the run's row
// `face_row`) against its faces: every vertex inside every face, and every vertex of a face's loop
// on that face's plane. A file whose vertices were edited, or taken from other blocks, fails here
// instead of exporting a wrong model.
void check_vertices_on_faces(const Checker& c, const Geometry& g, const Block& blk, std::size_t b,
                             std::size_t face_row, const GeometryBase& base, double tol) {
  const auto v0 = static_cast<std::size_t>(g.vertex_offset[b]);
  const auto v1 = static_cast<std::size_t>(g.vertex_offset[b + 1]);
  const auto fail = [&](std::size_t v, std::size_t f, double off, const char* how) {
    c.fail(at("/geometry/vertices", std::size_t(base.vertex) + v) + " " +
           row_text(g.vertices[v].data(), 3) + " lies " + num(off) + " " + how + " face " +
           str(base.face + face_row + f) + " of block " + str(base.block + b) + " (tolerance " +
           num(tol) + "): /geometry does not match /blocks");
  };
  for (std::size_t f = 0; f < blk.faces.size(); ++f) {
    const Face& fc = blk.faces[f];
    for (std::size_t v = v0; v < v1; ++v) {
      const double off = fc.normal.dot(g.vertices[v] - blk.origin) - fc.d;
      if (off > tol) fail(v, f, off, "outside");
    }
    const auto lo = static_cast<std::size_t>(g.face_vertex_offset[face_row + f]);
    const auto hi = static_cast<std::size_t>(g.face_vertex_offset[face_row + f + 1]);
    for (std::size_t k = lo; k < hi; ++k) {
      const std::int64_t local = g.face_vertices[k];
      const std::size_t v = v0 + std::size_t(local);  // in range: checked by the caller
      const double off = fc.normal.dot(g.vertices[v] - blk.origin) - fc.d;
      if (std::abs(off) > tol) fail(v, f, std::abs(off), "off the plane of");
    }
  }
}

// The geometry `g` of the n blocks from base.block on (all of /geometry if base is zero and n
// the block count) against the blocks it describes: CSR shapes, indices, finite and positive
// values.
void check_geometry(const Checker& c, const BlockSystem& bs, const Geometry& g,
                    const GeometryBase& base, std::size_t n, double tol) {
  SLICE_ASSERT(base.block + n <= bs.blocks.size());
  const std::size_t faces = face_count(std::span(bs.blocks).subspan(base.block, n));
  const auto rows = [&](const std::string& name, std::size_t got, std::size_t want,
                        const std::string& because) {
    if (got != want)
      c.fail("/geometry/" + name + " has " + str(got) + " rows; expected " + str(want) + " (" +
             because + ")");
  };
  const auto offsets = [&](const std::string& name, const std::vector<std::int64_t>& off,
                           std::size_t count, const std::string& what, std::size_t flat,
                           std::size_t row0, std::int64_t value0) {
    rows(name, off.size(), count + 1, what + " + 1");
    for (std::size_t i = 0; i < off.size(); ++i)
      if ((i == 0 && off[0] != 0) || (i > 0 && off[i] < off[i - 1]))
        c.fail(at("/geometry/" + name, row0 + i) + " is " + str(value0 + off[i]) +
               "; offsets start at 0 and never decrease");
    if (off.back() != static_cast<std::int64_t>(flat))
      c.fail("/geometry/" + name + " ends at " + str(value0 + off.back()) +
             " but its flat dataset has " + str(value0 + std::int64_t(flat)) + " rows");
  };
  offsets("vertex_offset", g.vertex_offset, n, "blocks", g.vertices.size(), base.block,
          base.vertex);
  offsets("face_vertex_offset", g.face_vertex_offset, faces, "faces", g.face_vertices.size(),
          base.face, base.face_vertex);
  rows("volume", g.volume.size(), n, "blocks");
  rows("centroid", g.centroid.size(), n, "blocks");
  rows("inertia", g.inertia.size(), n, "blocks");
  rows("face_area", g.face_area.size(), faces, "faces");
  rows("face_joint_fraction", g.face_joint_fraction.size(), faces, "faces");

  for (std::size_t v = 0; v < g.vertices.size(); ++v)
    c.finite(g.vertices[v], At{"/geometry/vertices", std::size_t(base.vertex) + v});
  const bool section = bs.joints.dimension == 2;
  std::size_t face = 0;
  for (std::size_t b = 0; b < n; ++b) {
    const std::size_t block = base.block + b;  // the file's row
    const Block& blk = bs.blocks[block];
    const std::int64_t nv = g.vertex_offset[b + 1] - g.vertex_offset[b];
    const std::size_t first_face = face;
    for (std::size_t f = 0; f < blk.faces.size(); ++f, ++face) {
      const std::size_t file_face = base.face + face;
      const auto lo = static_cast<std::size_t>(g.face_vertex_offset[face]);
      const auto hi = static_cast<std::size_t>(g.face_vertex_offset[face + 1]);
      // A 2-D block's face is an edge: its two ends (docs/2d.md).
      if (section ? hi - lo != 2 : hi - lo < 3)
        c.fail(at("/geometry/face_vertex_offset", file_face) + " gives face " + str(file_face) +
               " " + str(hi - lo) + " vertices; a face has " +
               (section ? "2 in a 2-D file (an edge)" : "at least 3"));
      for (std::size_t k = lo; k < hi; ++k)
        if (g.face_vertices[k] < 0 || g.face_vertices[k] >= nv)
          c.fail(at("/geometry/face_vertices", std::size_t(base.face_vertex) + k) + " is " +
                 str(g.face_vertices[k]) + "; expected an index into block " + str(block) + "'s " +
                 str(nv) + " vertices");
      c.finite(g.face_area[face], At{"/geometry/face_area", file_face});
      if (!(g.face_area[face] > 0))
        c.fail(at("/geometry/face_area", file_face) + " is " + num(g.face_area[face]) +
               "; a face has positive area");
      const double fr = g.face_joint_fraction[face];
      if (!(fr >= 0 && fr <= 1))
        c.fail(at("/geometry/face_joint_fraction", file_face) + " is " + num(fr) +
               "; expected a fraction in [0, 1]");
    }
    check_vertices_on_faces(c, g, blk, b, first_face, base, tol);
    c.finite(g.volume[b], At{"/geometry/volume", block});
    if (!(g.volume[b] > 0))
      c.fail(at("/geometry/volume", block) + " is " + num(g.volume[b]) +
             "; a block has positive volume");
    c.finite(g.centroid[b], At{"/geometry/centroid", block});
    for (const double x : g.inertia[b])
      if (!std::isfinite(x))
        c.fail(at("/geometry/inertia", block) + " is " + row_text(g.inertia[b].data(), 6));
    if (std::string why = geometry_value_problem(g, blk, b, first_face, base, tol, section);
        !why.empty())
      c.fail(why);
  }
}

// All of /geometry against the blocks.
void check_geometry(const Checker& c, const BlockSystem& bs) {
  const Geometry& g = *bs.geometry;
  check_geometry(c, bs, g, {}, bs.blocks.size(), vertex_tolerance(bs.joints, g.vertices));
}

void check_blocks(const Checker& c, const BlockSystem& bs, bool with_geometry = true) {
  check_joints(c, bs.joints);
  const auto joints = static_cast<std::int64_t>(bs.joints.joints.size());
  std::size_t face_row = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    c.finite(blk.origin, At{"/blocks/origin", b});
    const bool section = bs.joints.dimension == 2;
    if (section && blk.origin.y() != 0)
      c.fail(at("/blocks/origin", b) + " has y = " + num(blk.origin.y()) +
             "; a 2-D file (root attribute dimension 2) has y = 0 everywhere");
    for (const Face& f : blk.faces) {
      c.unit(f.normal, At{"/blocks/face_normal", face_row});
      if (section && f.normal.y() != 0)
        c.fail(at("/blocks/face_normal", face_row) + " has y = " + num(f.normal.y()) +
               "; a 2-D file (root attribute dimension 2) has y = 0 everywhere");
      c.finite(f.d, At{"/blocks/face_d", face_row});
      if (f.joint < -1 || f.joint >= joints)
        c.fail(at("/blocks/face_joint", face_row) + " is " + str(f.joint) +
               "; expected -1 (domain face) or a joint index below " + str(joints) +
               " (the rows of /joints/normal)");
      ++face_row;
    }
    c.non_negative(blk.inradius, At{"/blocks/inradius", b});
    c.finite(blk.bsphere, At{"/blocks/bsphere", b});
    c.non_negative(blk.bsphere[3], At{"/blocks/bsphere", b, " radius"});
    if (blk.cluster < -1)
      c.fail(at("/blocks/cluster", b) + " is " + str(blk.cluster) +
             "; expected -1 (none) or a cluster id");
  }
  if (with_geometry && bs.geometry) check_geometry(c, bs);
}

// --- writing ---------------------------------------------------------------------------------

void write_header(const Group& root, FileKind kind, const Provenance& prov, const JointSystem& js) {
  root.write_attribute<std::string>("schema", kSchemaName);
  root.write_attribute<std::int64_t>("schema_version", kSchemaVersion);
  root.write_attribute<std::string>("kind", to_string(kind));
  root.write_attribute<std::int64_t>("dimension", js.dimension);
  root.write_attribute("tool", prov.tool);
  root.write_attribute("tool_version", prov.version);
  root.write_attribute("command_line", prov.command_line);
  root.write_attribute("input", prov.input);
  root.write_attribute("input_sha256", prov.input_sha256);
  root.write_attribute("name", js.name);
  root.write_attribute("seed", js.seed);
}

void write_planes(const Group& g, const std::vector<Plane>& planes) {
  std::vector<double> normal, d;
  for (const Plane& p : planes) {
    normal.insert(normal.end(), p.normal.data(), p.normal.data() + 3);
    d.push_back(p.d);
  }
  g.write<double>("normal", normal, 3);
  g.write<double>("d", d);
}

// The stochastic parameters of a set and what generation achieved (DESIGN section 8), as
// attributes of its /sets group. Vectors are three scalars (_x, _y, _z). Unused parameters are 0.
void write_set_generation(const Group& sg, const JointSetSpec& s) {
  sg.write_attribute<std::string>("intensity", to_string(s.intensity));
  sg.write_attribute("fisher_kappa", s.fisher_kappa);
  sg.write_attribute("density", s.density);
  sg.write_attribute("count", s.count);
  sg.write_attribute("p32", s.p32);
  sg.write_attribute("p10", s.p10);
  sg.write_attribute<std::int64_t>("scanline_given", s.scanline_given ? 1 : 0);
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    sg.write_attribute("scanline_from_" + axis, s.scanline_from(k));
    sg.write_attribute("scanline_to_" + axis, s.scanline_to(k));
  }
  sg.write_attribute<std::string>("size_distribution", to_string(s.size.distribution));
  sg.write_attribute("size_value", s.size.value);
  sg.write_attribute("size_mean", s.size.mean);
  sg.write_attribute("size_sd", s.size.sd);
  sg.write_attribute("size_exponent", s.size.exponent);
  sg.write_attribute("size_min", s.size.min);
  sg.write_attribute("size_max", s.size.max);
  sg.write_attribute<std::string>("shape", to_string(s.shape));
  sg.write_attribute("aspect", s.aspect);
  sg.write_attribute("sides", s.sides);
  sg.write_attribute<std::string>("fit", to_string(s.fit));
  sg.write_attribute<std::int64_t>("rotation_fixed", s.rotation_fixed ? 1 : 0);
  sg.write_attribute("rotation", s.rotation_deg);
  sg.write_attribute("stream_seed", s.stream_seed);
  sg.write_attribute("enlargement", s.enlargement);
  sg.write_attribute("candidates", s.candidates);
  sg.write_attribute("achieved_p32", s.achieved_p32);
  sg.write_attribute("achieved_p10", s.achieved_p10);
}

void write_joint_groups(const Group& root, const JointSystem& js) {
  {
    const Group g = root.create_group("domain");
    g.write_attribute("length_scale", js.length_scale);
    write_planes(g, js.domain.planes);
  }
  {
    const std::size_t n = js.joints.size();
    std::vector<double> normal, d, centre, dip, dip_direction, friction, cohesion, tension, uv;
    std::vector<std::uint8_t> kind, limits;
    std::vector<std::int32_t> set;
    std::vector<std::int8_t> side;
    std::vector<std::int64_t> offset{0};
    for (auto* v : {&d, &dip, &dip_direction, &friction, &cohesion}) v->reserve(n);
    for (const Joint& j : js.joints) {
      normal.insert(normal.end(), j.plane.normal.data(), j.plane.normal.data() + 3);
      d.push_back(j.plane.d);
      centre.insert(centre.end(), j.centre.data(), j.centre.data() + 3);
      dip.push_back(j.dip_deg);
      dip_direction.push_back(j.dip_direction_deg);
      kind.push_back(static_cast<std::uint8_t>(j.kind));
      limits.push_back(j.limits ? 1 : 0);
      set.push_back(j.set);
      friction.push_back(j.friction_angle_deg);
      cohesion.push_back(j.cohesion);
      tension.push_back(j.tension);
      side.push_back(j.boundary_side);
      for (const Vec2& p : j.polygon_uv) uv.insert(uv.end(), p.data(), p.data() + 2);
      offset.push_back(offset.back() + static_cast<std::int64_t>(j.polygon_uv.size()));
    }
    const Group g = root.create_group("joints");
    g.write<double>("normal", normal, 3);
    g.write<double>("d", d);
    g.write<double>("centre", centre, 3);
    g.write<double>("dip", dip);
    g.write<double>("dip_direction", dip_direction);
    g.write<std::uint8_t>("kind", kind);
    g.write<std::int32_t>("set", set);
    g.write<double>("friction_angle", friction);
    g.write<double>("cohesion", cohesion);
    g.write<double>("tension", tension);
    g.write<std::int8_t>("boundary_side", side);
    g.write<std::uint8_t>("limits", limits);
    g.write<std::int64_t>("polygon_offset", offset);
    g.write<double>("polygon_uv", uv, 2);
  }
  {
    const Group g = root.create_group("sets");
    g.write_attribute("count", static_cast<std::int64_t>(js.sets.size()));
    for (std::size_t i = 0; i < js.sets.size(); ++i) {
      const JointSetSpec& s = js.sets[i];
      const Group sg = g.create_group(set_group_name(i));
      sg.write_attribute("name", s.name);
      sg.write_attribute("dip", s.dip_deg);
      sg.write_attribute("dip_direction", s.dip_direction_deg);
      sg.write_attribute("spacing", s.spacing);
      sg.write_attribute("offset", s.offset);
      sg.write_attribute("friction_angle", s.friction_angle_deg);
      sg.write_attribute("cohesion", s.cohesion);
      sg.write_attribute("tension", s.tension);
      sg.write_attribute<std::int64_t>("limits", s.limits ? 1 : 0);
      sg.write_attribute<std::string>("kind", to_string(s.kind));
      sg.write_attribute<std::int64_t>("boundary_side", s.boundary_side);
      sg.write_attribute("joint_count", s.joint_count);
      write_set_generation(sg, s);
    }
  }
  {
    std::vector<std::int64_t> offset{0};
    std::vector<Plane> planes;
    for (const Region& z : js.zones) {
      planes.insert(planes.end(), z.planes.begin(), z.planes.end());
      offset.push_back(static_cast<std::int64_t>(planes.size()));
    }
    const Group g = root.create_group("zones");
    g.write<std::int64_t>("offset", offset);
    write_planes(g, planes);
    if (!js.zone_meshes.empty()) {  // only then: files without meshes stay as they were
      std::vector<std::int64_t> vertex_offset{0}, triangle_offset{0}, triangles;
      std::vector<double> vertices;
      for (const TriangleMesh& m : js.zone_meshes) {
        for (const Vec3& x : m.vertices) vertices.insert(vertices.end(), x.data(), x.data() + 3);
        for (const auto& t : m.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
        vertex_offset.push_back(std::int64_t(vertices.size() / 3));
        triangle_offset.push_back(std::int64_t(triangles.size() / 3));
      }
      g.write<std::int64_t>("mesh_vertex_offset", vertex_offset);
      g.write<double>("mesh_vertices", vertices, 3);
      g.write<std::int64_t>("mesh_triangle_offset", triangle_offset);
      g.write<std::int64_t>("mesh_triangles", triangles, 3);
    }
  }
  {
    const Group g = root.create_group("options");
    g.write_attribute<std::string>("order", to_string(js.options.order));
    g.write_attribute("min_inscribed_diameter", js.options.min_inscribed_diameter);
    g.write_attribute("max_aspect_ratio", js.options.max_aspect_ratio);
    g.write_attribute("tolerance", js.options.tolerance);
    g.write_attribute<std::int64_t>("max_blocks", js.options.max_blocks);
    g.write_attribute<std::string>("fixed_faces", fixed_faces_string(js.options.fixed_faces));
    g.write_attribute<std::string>("slivers",
                                   std::string(kSliverRuleNames[std::size_t(js.options.slivers)]));
  }
  if (js.rock.given) {  // [rock]: intact rock for rock-bridge contacts (docs/3dec.md)
    const Group g = root.create_group("rock");
    g.write_attribute("friction_angle", js.rock.friction_angle_deg);
    g.write_attribute("cohesion", js.rock.cohesion);
    g.write_attribute("tension", js.rock.tension);
  }
}

// Written and read in runs of kBatch blocks, each dataset by rows: the flat arrays of a million
// blocks (about 310 MB at 1.0 m Table 3) are never held at once.
constexpr std::size_t kBatch = 1 << 16;

void write_blocks_group(const Group& root, const BlockSystem& bs) {
  const std::size_t n = bs.blocks.size();
  const std::size_t faces = face_count(bs.blocks);
  const Group g = root.create_group("blocks");
  g.write_attribute<std::int64_t>("pruned", bs.pruned ? 1 : 0);
  auto origin = g.create_rows<double>("origin", n, 3);
  auto face_offset = g.create_rows<std::int64_t>("face_offset", n + 1, 0);
  auto face_normal = g.create_rows<double>("face_normal", faces, 3);
  auto face_d = g.create_rows<double>("face_d", faces, 0);
  auto face_joint = g.create_rows<std::int64_t>("face_joint", faces, 0);
  auto inradius = g.create_rows<double>("inradius", n, 0);
  auto bsphere = g.create_rows<double>("bsphere", n, 4);
  auto flags = g.create_rows<std::uint8_t>("flags", n, 0);
  auto cluster = g.create_rows<std::int64_t>("cluster", n, 0);
  std::vector<double> o, fn, fd, ir, bsph;
  std::vector<std::int64_t> off{0}, fj, cl;
  std::vector<std::uint8_t> fl;
  std::int64_t face_row = 0;
  for (std::size_t b0 = 0; b0 < n; b0 += kBatch) {
    o.clear(), fn.clear(), fd.clear(), ir.clear(), bsph.clear(), fj.clear(), cl.clear(), fl.clear();
    if (b0 > 0) off.clear();
    for (std::size_t i = b0; i < std::min(n, b0 + kBatch); ++i) {
      const Block& b = bs.blocks[i];
      o.insert(o.end(), b.origin.data(), b.origin.data() + 3);
      for (const Face& f : b.faces) {
        fn.insert(fn.end(), f.normal.data(), f.normal.data() + 3);
        fd.push_back(f.d);
        fj.push_back(f.joint);
      }
      face_row += static_cast<std::int64_t>(b.faces.size());
      off.push_back(face_row);
      ir.push_back(b.inradius);
      bsph.insert(bsph.end(), b.bsphere.data(), b.bsphere.data() + 4);
      fl.push_back(b.flags);
      cl.push_back(b.cluster);
    }
    origin.append(o);
    face_offset.append(off);
    face_normal.append(fn);
    face_d.append(fd);
    face_joint.append(fj);
    inradius.append(ir);
    bsphere.append(bsph);
    flags.append(fl);
    cluster.append(cl);
  }
  if (n == 0) face_offset.append(off);
  for (auto* w : {&origin, &face_normal, &face_d, &inradius, &bsphere}) w->finish();
  for (auto* w : {&face_offset, &face_joint, &cluster}) w->finish();
  flags.finish();
}

// Rows [lo, hi) of a vector of Vec3 or Inertia as the doubles they hold (no copy).
template <std::size_t N, class Row>
std::span<const double> as_doubles(const std::vector<Row>& rows, std::size_t lo, std::size_t hi) {
  static_assert(sizeof(Row) == N * sizeof(double), "rows must be N packed doubles");
  return lo == hi ? std::span<const double>()
                  : std::span<const double>(reinterpret_cast<const double*>(rows.data() + lo),
                                            N * (hi - lo));
}

// The doubles of a vector of Vec3 or Inertia, to be read into.
template <std::size_t N, class Row>
double* as_doubles(std::vector<Row>& rows) {
  static_assert(sizeof(Row) == N * sizeof(double), "rows must be N packed doubles");
  return reinterpret_cast<double*>(rows.data());
}

// Writes /geometry run by run, in block order (write_blocks, BlocksFileWriter): the datasets are
// created in a fixed order, the per-block and per-face ones at their known length, vertices and
// face_vertices growing by whole chunks. So the bytes depend on the geometry and on where the runs
// start, which is why every writer cuts a held geometry into runs of kGeometryRun blocks as
// compute_geometry hands them over.
class GeometryWriter {
 public:
  GeometryWriter(const Group& root, const BlockSystem& bs)
      : g_(root.create_group("geometry")),
        faces_(face_count(bs.blocks)),
        vertex_offset_(g_.create_rows<std::int64_t>("vertex_offset", bs.blocks.size() + 1, 0)),
        // A polyhedron has at most 2F - 4 vertices and 2 (3F - 6) loop entries; a polygon F and 2F.
        vertices_(g_.create_growing_rows<double>("vertices", 3,
                                                 bs.joints.dimension == 2 ? faces_ : 2 * faces_)),
        face_vertex_offset_(g_.create_rows<std::int64_t>("face_vertex_offset", faces_ + 1, 0)),
        face_vertices_(g_.create_growing_rows<std::int64_t>(
            "face_vertices", 0, bs.joints.dimension == 2 ? 2 * faces_ : 6 * faces_)),
        volume_(g_.create_rows<double>("volume", bs.blocks.size(), 0)),
        centroid_(g_.create_rows<double>("centroid", bs.blocks.size(), 3)),
        inertia_(g_.create_rows<double>("inertia", bs.blocks.size(), 6)),
        face_area_(g_.create_rows<double>("face_area", faces_, 0)),
        face_joint_fraction_(g_.create_rows<double>("face_joint_fraction", faces_, 0)),
        bs_(bs) {
    const std::int64_t zero = 0;
    vertex_offset_.append({&zero, 1});
    face_vertex_offset_.append({&zero, 1});
  }

  /// Where the next run starts in the file.
  const GeometryBase& next() const { return next_; }

  /// Appends n blocks of `geo`, from its block `first` whose first face is its face row
  /// `first_face`: a whole geometry, or (0, 0) a run of its own.
  void append(const Geometry& geo, std::size_t first, std::size_t first_face, std::size_t n) {
    const std::size_t faces = face_count(std::span(bs_.blocks).subspan(next_.block, n));
    const std::size_t v0 = std::size_t(geo.vertex_offset[first]);
    const std::size_t v1 = std::size_t(geo.vertex_offset[first + n]);
    const std::size_t fv0 = std::size_t(geo.face_vertex_offset[first_face]);
    const std::size_t fv1 = std::size_t(geo.face_vertex_offset[first_face + faces]);
    const auto rebased = [&](const std::vector<std::int64_t>& off, std::size_t lo,
                             std::size_t count, std::int64_t base) {
      offsets_.clear();
      for (std::size_t i = lo + 1; i <= lo + count; ++i)
        offsets_.push_back(base + off[i] - off[lo]);
      return std::span<const std::int64_t>(offsets_);
    };
    vertex_offset_.append(rebased(geo.vertex_offset, first, n, next_.vertex));
    vertices_.append(as_doubles<3>(geo.vertices, v0, v1));
    face_vertex_offset_.append(
        rebased(geo.face_vertex_offset, first_face, faces, next_.face_vertex));
    face_vertices_.append(std::span(geo.face_vertices).subspan(fv0, fv1 - fv0));
    volume_.append(std::span(geo.volume).subspan(first, n));
    centroid_.append(as_doubles<3>(geo.centroid, first, first + n));
    inertia_.append(as_doubles<6>(geo.inertia, first, first + n));
    face_area_.append(std::span(geo.face_area).subspan(first_face, faces));
    face_joint_fraction_.append(std::span(geo.face_joint_fraction).subspan(first_face, faces));
    next_.block += n;
    next_.face += faces;
    next_.vertex += std::int64_t(v1 - v0);
    next_.face_vertex += std::int64_t(fv1 - fv0);
  }

  void finish() {
    SLICE_ASSERT(next_.block == bs_.blocks.size() && next_.face == faces_);
    for (auto* w : {&vertex_offset_, &face_vertex_offset_, &face_vertices_}) w->finish();
    for (auto* w :
         {&vertices_, &volume_, &centroid_, &inertia_, &face_area_, &face_joint_fraction_})
      w->finish();
  }

 private:
  Group g_;
  std::size_t faces_;
  RowWriter<std::int64_t> vertex_offset_;
  RowWriter<double> vertices_;
  RowWriter<std::int64_t> face_vertex_offset_, face_vertices_;
  RowWriter<double> volume_, centroid_, inertia_, face_area_, face_joint_fraction_;
  const BlockSystem& bs_;
  GeometryBase next_;
  std::vector<std::int64_t> offsets_;
};

// bs.geometry (checked by the caller), in the runs compute_geometry would have handed over.
void write_geometry_group(const Group& root, const BlockSystem& bs) {
  const Geometry& geo = *bs.geometry;
  GeometryWriter w(root, bs);
  for (std::size_t b0 = 0; b0 < bs.blocks.size(); b0 += kGeometryRun)
    w.append(geo, b0, w.next().face, std::min(kGeometryRun, bs.blocks.size() - b0));
  w.finish();
}

// "<out>.partial" created with its header and joint groups; `commit` closes and renames it.
struct OpenFile {
  OpenFile(const fs::path& out, FileKind kind, const Provenance& prov, const JointSystem& js,
           const WriteOptions& opt)
      : part(out), f(h5::File::create(part.path(), {out.string(), kWriteFix, opt.compress})) {
    write_header(f.root(), kind, prov, js);
    write_joint_groups(f.root(), js);
  }
  void commit() {
    f.close();
    part.commit();
  }
  PartialFile part;
  h5::File f;
};

// Validated by the caller; writes to "<out>.partial" and renames it onto `out`.
template <class Body>
void write_file(const fs::path& out, FileKind kind, const Provenance& prov, const JointSystem& js,
                const WriteOptions& opt, const Body& body) {
  OpenFile file(out, kind, prov, js, opt);
  body(file.f.root());
  file.commit();
}

// --- reading ---------------------------------------------------------------------------------

[[noreturn]] void fail(const Group& g, const std::string& what) {
  throw Error(g.context().file, what, g.context().fix);
}

// A dataset must have `want` rows, as another dataset (`because`) says.
void expect_rows(const Group& g, const std::string& name, std::size_t got, std::size_t want,
                 const std::string& because) {
  if (got != want)
    fail(g, g.member_path(name) + " has " + str(got) + " rows; expected " + str(want) + " (" +
                because + ")");
}

// CSR offsets: n + 1 entries, starting at 0, never decreasing, ending at the flat length.
void check_offsets(const Group& g, const std::string& name, const std::vector<std::int64_t>& off,
                   std::size_t n, const std::string& n_what, std::size_t flat,
                   const std::string& flat_name) {
  const std::string p = g.member_path(name);
  if (off.size() != n + 1)
    fail(g,
         p + " has " + str(off.size()) + " rows; expected " + str(n + 1) + " (" + n_what + " + 1)");
  if (off[0] != 0) fail(g, at(p, 0) + " is " + str(off[0]) + "; offsets start at 0");
  for (std::size_t i = 1; i < off.size(); ++i)
    if (off[i] < off[i - 1])
      fail(g, at(p, i) + " is " + str(off[i]) + ", less than row " + str(i - 1) + " (" +
                  str(off[i - 1]) + "); offsets never decrease");
  if (off.back() != static_cast<std::int64_t>(flat))
    fail(g,
         p + " ends at " + str(off.back()) + " but " + flat_name + " has " + str(flat) + " rows");
}

Vec3 vec3(const std::vector<double>& v, std::size_t row) {
  return {v[3 * row], v[3 * row + 1], v[3 * row + 2]};
}

std::vector<Plane> read_planes(const Group& g, const std::string& count_what) {
  const auto normal = g.read<double>("normal", 3);
  const auto d = g.read<double>("d");
  const std::size_t n = normal.size() / 3;
  expect_rows(g, "d", d.size(), n, count_what);
  std::vector<Plane> planes(n);
  for (std::size_t i = 0; i < n; ++i) planes[i] = {vec3(normal, i), d[i]};
  return planes;
}

FileHeader read_root_header(const Group& root) {
  const std::string& file = root.context().file;
  if (!root.has_attribute("schema"))
    throw Error(file, "not a rockslice file (no root attribute schema)",
                "give a file written by a rockslice tool");
  FileHeader h;
  h.schema = root.read_attribute<std::string>("schema");
  if (h.schema != kSchemaName)
    throw Error(file, "root attribute schema is \"" + h.schema + "\", not \"" + kSchemaName + "\"",
                "give a file written by a rockslice tool");
  const auto version = root.read_attribute<std::int64_t>("schema_version");
  if (version > kSchemaVersion)
    throw Error(file,
                "written by a newer rockslice (root attribute schema_version is " + str(version) +
                    "; this one reads up to " + std::to_string(kSchemaVersion) + ")",
                "upgrade rockslice");
  if (version < 1) fail(root, "root attribute schema_version is " + str(version) + "; expected 1");
  h.schema_version = static_cast<int>(version);
  const auto kind = root.read_attribute<std::string>("kind");
  if (kind == to_string(FileKind::joints))
    h.kind = FileKind::joints;
  else if (kind == to_string(FileKind::blocks))
    h.kind = FileKind::blocks;
  else
    fail(root, "root attribute kind is \"" + kind + "\"; expected \"joints\" or \"blocks\"");
  const auto dimension = root.read_attribute<std::int64_t>("dimension");
  if (dimension != 3 && dimension != 2)
    throw Error(file, "root attribute dimension is " + str(dimension),
                "expected 3, or 2 for a section in (x, z); regenerate the file");
  h.dimension = static_cast<int>(dimension);
  h.provenance.tool = root.read_attribute<std::string>("tool");
  h.provenance.version = root.read_attribute<std::string>("tool_version");
  h.provenance.command_line = root.read_attribute<std::string>("command_line");
  h.provenance.input = root.read_attribute<std::string>("input");
  h.provenance.input_sha256 = root.read_attribute<std::string>("input_sha256");
  return h;
}

void expect_kind(const Group& root, FileKind want) {
  const FileHeader h = read_root_header(root);
  if (h.kind == want) return;
  const std::string fix = want == FileKind::joints ? "give a joints file (from slice-joints)"
                                                   : "give a blocks file (from slice-cut)";
  throw Error(root.context().file,
              std::string("root attribute kind is \"") + to_string(h.kind) + "\"; expected \"" +
                  to_string(want) + "\"",
              fix);
}

// A name attribute read back into its enum.
template <class Enum>
Enum read_name(const Group& sg, const std::string& attr,
               std::optional<Enum> (*parse)(std::string_view), const std::string& expected) {
  const auto v = sg.read_attribute<std::string>(attr);
  const auto parsed = parse(v);
  if (!parsed) fail(sg, sg.attribute_label(attr) + " is \"" + v + "\"; expected " + expected);
  return *parsed;
}

// The inverse of write_set_generation. A file without these attributes (written before
// stochastic sets existed) holds regular sets only: the defaults stand.
void read_set_generation(const Group& sg, JointSetSpec& s) {
  if (!sg.has_attribute("intensity")) return;
  s.intensity = read_name<SetIntensity>(sg, "intensity", parse_set_intensity,
                                        "spacing, density, count, p32 or p10");
  s.fisher_kappa = sg.read_attribute<double>("fisher_kappa");
  s.density = sg.read_attribute<double>("density");
  s.count = sg.read_attribute<std::int64_t>("count");
  s.p32 = sg.read_attribute<double>("p32");
  s.p10 = sg.read_attribute<double>("p10");
  s.scanline_given = sg.read_attribute<std::int64_t>("scanline_given") != 0;
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    s.scanline_from(k) = sg.read_attribute<double>("scanline_from_" + axis);
    s.scanline_to(k) = sg.read_attribute<double>("scanline_to_" + axis);
  }
  s.size.distribution =
      read_name<SizeDistribution>(sg, "size_distribution", parse_size_distribution,
                                  "none, fixed, lognormal, exponential or power-law");
  s.size.value = sg.read_attribute<double>("size_value");
  s.size.mean = sg.read_attribute<double>("size_mean");
  s.size.sd = sg.read_attribute<double>("size_sd");
  s.size.exponent = sg.read_attribute<double>("size_exponent");
  s.size.min = sg.read_attribute<double>("size_min");
  s.size.max = sg.read_attribute<double>("size_max");
  s.shape = read_name<JointShape>(sg, "shape", parse_joint_shape,
                                  "square, rectangle, polygon or ellipse");
  s.aspect = sg.read_attribute<double>("aspect");
  s.sides = sg.read_attribute<std::int64_t>("sides");
  s.fit = read_name<EllipseFit>(sg, "fit", parse_ellipse_fit, "circumscribed or equal-area");
  s.rotation_fixed = sg.read_attribute<std::int64_t>("rotation_fixed") != 0;
  s.rotation_deg = sg.read_attribute<double>("rotation");
  s.stream_seed = sg.read_attribute<std::uint64_t>("stream_seed");
  s.enlargement = sg.read_attribute<double>("enlargement");
  s.candidates = sg.read_attribute<std::int64_t>("candidates");
  s.achieved_p32 = sg.read_attribute<double>("achieved_p32");
  s.achieved_p10 = sg.read_attribute<double>("achieved_p10");
}

// /zones/mesh_*: closed meshes, each with its own vertices (checked by check_joints).
std::vector<TriangleMesh> read_zone_meshes(const Group& g) {
  const auto vertex_offset = g.read<std::int64_t>("mesh_vertex_offset");
  const auto vertices = g.read<double>("mesh_vertices", 3);
  const auto triangle_offset = g.read<std::int64_t>("mesh_triangle_offset");
  const auto triangles = g.read<std::int64_t>("mesh_triangles", 3);
  if (vertex_offset.empty()) fail(g, "/zones/mesh_vertex_offset is empty; expected at least 0");
  const std::size_t meshes = vertex_offset.size() - 1;
  check_offsets(g, "mesh_vertex_offset", vertex_offset, meshes, "meshes", vertices.size() / 3,
                "/zones/mesh_vertices");
  check_offsets(g, "mesh_triangle_offset", triangle_offset, meshes, "meshes", triangles.size() / 3,
                "/zones/mesh_triangles");
  std::vector<TriangleMesh> out(meshes);
  for (std::size_t k = 0; k < meshes; ++k) {
    for (auto v = vertex_offset[k]; v < vertex_offset[k + 1]; ++v)
      out[k].vertices.push_back(vec3(vertices, std::size_t(v)));
    for (auto t = triangle_offset[k]; t < triangle_offset[k + 1]; ++t) {
      const auto i = 3 * std::size_t(t);
      out[k].triangles.push_back({triangles[i], triangles[i + 1], triangles[i + 2]});
    }
  }
  return out;
}

JointSystem read_joint_groups(const Group& root) {
  JointSystem js;
  js.dimension = read_root_header(root).dimension;
  js.name = root.read_attribute<std::string>("name");
  js.seed = root.read_attribute<std::uint64_t>("seed");
  {
    const Group g = root.open_group("domain");
    js.length_scale = g.read_attribute<double>("length_scale");
    js.domain.planes = read_planes(g, "the rows of /domain/normal");
  }
  {
    const Group g = root.open_group("joints");
    const auto normal = g.read<double>("normal", 3);
    const std::size_t n = normal.size() / 3;
    const std::string because = "the rows of /joints/normal";
    const auto d = g.read<double>("d");
    expect_rows(g, "d", d.size(), n, because);
    const auto centre = g.read<double>("centre", 3);
    expect_rows(g, "centre", centre.size() / 3, n, because);
    const auto dip = g.read<double>("dip");
    expect_rows(g, "dip", dip.size(), n, because);
    const auto dip_direction = g.read<double>("dip_direction");
    expect_rows(g, "dip_direction", dip_direction.size(), n, because);
    const auto kind = g.read<std::uint8_t>("kind");
    expect_rows(g, "kind", kind.size(), n, because);
    const auto set = g.read<std::int32_t>("set");
    expect_rows(g, "set", set.size(), n, because);
    const auto friction = g.read<double>("friction_angle");
    expect_rows(g, "friction_angle", friction.size(), n, because);
    const auto cohesion = g.read<double>("cohesion");
    expect_rows(g, "cohesion", cohesion.size(), n, because);
    const auto side = g.read<std::int8_t>("boundary_side");
    expect_rows(g, "boundary_side", side.size(), n, because);
    std::vector<double> tension(n, 0.0);  // files from before tension: 0
    if (g.exists("tension")) tension = g.read<double>("tension");
    expect_rows(g, "tension", tension.size(), n, because);
    // Files from before the limits exemption: every joint obeys the limits.
    std::vector<std::uint8_t> limits(n, 1);
    if (g.exists("limits")) {
      limits = g.read<std::uint8_t>("limits");
      expect_rows(g, "limits", limits.size(), n, because);
      for (std::size_t i = 0; i < n; ++i)
        if (limits[i] > 1)
          fail(g, "/joints/limits[" + str(i) + "] is " + str(std::int64_t{limits[i]}) +
                      "; expected 0 or 1");
    }
    const auto offset = g.read<std::int64_t>("polygon_offset");
    const auto uv = g.read<double>("polygon_uv", 2);
    check_offsets(g, "polygon_offset", offset, n, "joints", uv.size() / 2, "/joints/polygon_uv");

    js.joints.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      Joint& j = js.joints[i];
      j.plane = {vec3(normal, i), d[i]};
      j.centre = vec3(centre, i);
      j.dip_deg = dip[i];
      j.dip_direction_deg = dip_direction[i];
      j.kind = static_cast<JointKind>(kind[i]);  // range checked by check_joints
      j.set = set[i];
      j.friction_angle_deg = friction[i];
      j.cohesion = cohesion[i];
      j.tension = tension[i];
      j.boundary_side = side[i];
      j.limits = limits[i] == 1;
      for (auto k = static_cast<std::size_t>(offset[i]);
           k < static_cast<std::size_t>(offset[i + 1]); ++k)
        j.polygon_uv.emplace_back(uv[2 * k], uv[2 * k + 1]);
    }
  }
  {
    const Group g = root.open_group("sets");
    const auto count = g.read_attribute<std::int64_t>("count");
    if (count < 0 || static_cast<std::size_t>(count) != g.member_count())
      fail(g, "/sets holds " + str(g.member_count()) + " groups but its attribute count is " +
                  str(count));
    for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
      const Group sg = g.open_group(set_group_name(i));
      JointSetSpec s;
      s.name = sg.read_attribute<std::string>("name");
      s.dip_deg = sg.read_attribute<double>("dip");
      s.dip_direction_deg = sg.read_attribute<double>("dip_direction");
      s.spacing = sg.read_attribute<double>("spacing");
      s.offset = sg.read_attribute<double>("offset");
      s.friction_angle_deg = sg.read_attribute<double>("friction_angle");
      s.cohesion = sg.read_attribute<double>("cohesion");
      if (sg.has_attribute("tension")) s.tension = sg.read_attribute<double>("tension");
      if (sg.has_attribute("limits")) {  // files from before the exemption: 1
        const auto limits = sg.read_attribute<std::int64_t>("limits");
        if (limits != 0 && limits != 1)
          fail(sg, "/sets/" + set_group_name(i) + " attribute limits is " + str(limits) +
                       "; expected 0 or 1");
        s.limits = limits == 1;
      }
      const auto kind = sg.read_attribute<std::string>("kind");
      const auto parsed = parse_joint_kind(kind);
      if (!parsed)
        fail(sg, sg.attribute_label("kind") + " is \"" + kind +
                     "\"; expected \"rock\", \"construction\" or \"boundary\"");
      s.kind = *parsed;
      const auto side = sg.read_attribute<std::int64_t>("boundary_side");
      if (side < -1 || side > 1)
        fail(sg,
             sg.attribute_label("boundary_side") + " is " + str(side) + "; expected -1, 0 or 1");
      s.boundary_side = static_cast<std::int8_t>(side);
      s.joint_count = sg.read_attribute<std::int64_t>("joint_count");
      read_set_generation(sg, s);
      js.sets.push_back(std::move(s));
    }
  }
  {
    const Group g = root.open_group("zones");
    const auto offset = g.read<std::int64_t>("offset");
    if (offset.empty()) fail(g, "/zones/offset is empty; expected at least one row (0)");
    const auto planes = read_planes(g, "the rows of /zones/normal");
    check_offsets(g, "offset", offset, offset.size() - 1, "zones", planes.size(), "/zones/normal");
    for (std::size_t z = 0; z + 1 < offset.size(); ++z)
      js.zones.push_back(
          {std::vector<Plane>(planes.begin() + offset[z], planes.begin() + offset[z + 1])});
    // The four /zones/mesh_* datasets come together: some without the others is a damaged file,
    // not one without meshes (whose zone would be dropped without a word).
    const char* parts[] = {"mesh_vertex_offset", "mesh_vertices", "mesh_triangle_offset",
                           "mesh_triangles"};
    const auto n = std::count_if(std::begin(parts), std::end(parts),
                                 [&](const char* p) { return g.exists(p); });
    for (const char* p : parts)
      if (n > 0 && !g.exists(p))
        fail(g, std::string("/zones/") + p + " is missing, though /zones has other mesh_* " +
                    "datasets (a mesh zone)");
    if (n > 0) js.zone_meshes = read_zone_meshes(g);
  }
  {
    const Group g = root.open_group("options");
    const auto order = g.read_attribute<std::string>("order");
    const auto parsed = parse_joint_order(order);
    if (!parsed)
      fail(g, "/options attribute order is \"" + order +
                  "\"; expected as-given, largest-first, by-set or alternating");
    js.options.order = *parsed;
    js.options.min_inscribed_diameter = g.read_attribute<double>("min_inscribed_diameter");
    js.options.max_aspect_ratio = g.read_attribute<double>("max_aspect_ratio");
    js.options.tolerance = g.read_attribute<double>("tolerance");
    // Files written before max_blocks existed keep the default.
    if (g.has_attribute("max_blocks"))
      js.options.max_blocks = g.read_attribute<std::int64_t>("max_blocks");
    if (g.has_attribute("fixed_faces")) {  // so are files from before fixed_faces: none
      const auto faces = g.read_attribute<std::string>("fixed_faces");
      const auto bits = parse_fixed_faces(faces);
      if (!bits)
        fail(g, "/options attribute fixed_faces is \"" + faces +
                    "\"; expected face names -x, +x, -y, +y, -z, +z joined by commas");
      js.options.fixed_faces = *bits;
    }
    if (g.has_attribute("slivers")) {  // files from before the rule: join (what it did)
      const auto rule = g.read_attribute<std::string>("slivers");
      const auto k = std::find(kSliverRuleNames.begin(), kSliverRuleNames.end(), rule);
      if (k == kSliverRuleNames.end())
        fail(g, "/options attribute slivers is \"" + rule + "\"; expected join or excavate");
      js.options.slivers = static_cast<SliverRule>(k - kSliverRuleNames.begin());
    }
  }
  if (root.exists("rock")) {  // files without [rock] (and from before it) have no /rock
    const Group g = root.open_group("rock");
    js.rock = {true, g.read_attribute<double>("friction_angle"),
               g.read_attribute<double>("cohesion"), g.read_attribute<double>("tension")};
  }
  return js;
}

// Rows [lo, hi) of a dataset into `buf`.
template <class T>
void read_run(const h5::RowReader<T>& r, std::size_t lo, std::size_t hi, std::size_t width,
              std::vector<T>& buf) {
  buf.resize((hi - lo) * width);
  r.read(lo, hi - lo, buf.data());
}

std::vector<Block> read_blocks_group(const Group& root, bool& pruned) {
  const Group g = root.open_group("blocks");
  const auto pruned_value = g.read_attribute<std::int64_t>("pruned");
  if (pruned_value != 0 && pruned_value != 1)
    fail(g, "/blocks attribute pruned is " + str(pruned_value) + "; expected 0 or 1");
  pruned = pruned_value == 1;

  const auto origin = g.open_rows<double>("origin", 3);
  const std::size_t n = origin.rows();
  const std::string because = "the rows of /blocks/origin";
  const auto offset = g.read<std::int64_t>("face_offset");
  const auto face_normal = g.open_rows<double>("face_normal", 3);
  const std::size_t faces = face_normal.rows();
  check_offsets(g, "face_offset", offset, n, "blocks", faces, "/blocks/face_normal");
  const std::string face_because = "the rows of /blocks/face_normal";
  const auto face_d = g.open_rows<double>("face_d", 0);
  expect_rows(g, "face_d", face_d.rows(), faces, face_because);
  const auto face_joint = g.open_rows<std::int64_t>("face_joint", 0);
  expect_rows(g, "face_joint", face_joint.rows(), faces, face_because);
  const auto inradius = g.open_rows<double>("inradius", 0);
  expect_rows(g, "inradius", inradius.rows(), n, because);
  const auto bsphere = g.open_rows<double>("bsphere", 4);
  expect_rows(g, "bsphere", bsphere.rows(), n, because);
  const auto flags = g.open_rows<std::uint8_t>("flags", 0);
  expect_rows(g, "flags", flags.rows(), n, because);
  const auto cluster = g.open_rows<std::int64_t>("cluster", 0);
  expect_rows(g, "cluster", cluster.rows(), n, because);

  // In runs of kBatch blocks: the flat arrays are never held whole.
  std::vector<Block> blocks(n);
  std::vector<double> o, fn, fd, ir, bsph;
  std::vector<std::int64_t> fj, cl;
  std::vector<std::uint8_t> fl;
  for (std::size_t b0 = 0; b0 < n; b0 += kBatch) {
    const std::size_t b1 = std::min(n, b0 + kBatch);
    const auto f0 = static_cast<std::size_t>(offset[b0]);
    const auto f1 = static_cast<std::size_t>(offset[b1]);
    read_run(origin, b0, b1, 3, o);
    read_run(face_normal, f0, f1, 3, fn);
    read_run(face_d, f0, f1, 1, fd);
    read_run(face_joint, f0, f1, 1, fj);
    read_run(inradius, b0, b1, 1, ir);
    read_run(bsphere, b0, b1, 4, bsph);
    read_run(flags, b0, b1, 1, fl);
    read_run(cluster, b0, b1, 1, cl);
    for (std::size_t b = b0; b < b1; ++b) {
      Block& blk = blocks[b];
      const std::size_t i = b - b0;
      blk.origin = vec3(o, i);
      const auto k0 = static_cast<std::size_t>(offset[b]) - f0;
      const auto k1 = static_cast<std::size_t>(offset[b + 1]) - f0;
      blk.faces.reserve(k1 - k0);
      for (std::size_t k = k0; k < k1; ++k) blk.faces.push_back({vec3(fn, k), fd[k], fj[k]});
      blk.inradius = ir[i];
      blk.bsphere = {bsph[4 * i], bsph[4 * i + 1], bsph[4 * i + 2], bsph[4 * i + 3]};
      blk.flags = fl[i];
      blk.cluster = cl[i];
    }
  }
  return blocks;
}

// /geometry, shapes checked against the blocks before anything is indexed; values are checked
// by check_geometry.
Geometry read_geometry_group(const Group& root, const std::vector<Block>& blocks) {
  const Group g = root.open_group("geometry");
  const std::size_t n = blocks.size();
  const std::size_t faces = face_count(blocks);
  const std::string per_block = "the rows of /blocks/origin";
  const std::string per_face = "the rows of /blocks/face_normal";
  Geometry geo;
  geo.vertex_offset = g.read<std::int64_t>("vertex_offset");
  const auto vertices = g.open_rows<double>("vertices", 3);
  check_offsets(g, "vertex_offset", geo.vertex_offset, n, "blocks", vertices.rows(),
                "/geometry/vertices");
  geo.face_vertex_offset = g.read<std::int64_t>("face_vertex_offset");
  geo.face_vertices = g.read<std::int64_t>("face_vertices");
  check_offsets(g, "face_vertex_offset", geo.face_vertex_offset, faces, "faces",
                geo.face_vertices.size(), "/geometry/face_vertices");
  geo.volume = g.read<double>("volume");
  expect_rows(g, "volume", geo.volume.size(), n, per_block);
  const auto centroid = g.open_rows<double>("centroid", 3);
  expect_rows(g, "centroid", centroid.rows(), n, per_block);
  const auto inertia = g.open_rows<double>("inertia", 6);
  expect_rows(g, "inertia", inertia.rows(), n, per_block);
  geo.face_area = g.read<double>("face_area");
  expect_rows(g, "face_area", geo.face_area.size(), faces, per_face);
  geo.face_joint_fraction = g.read<double>("face_joint_fraction");
  expect_rows(g, "face_joint_fraction", geo.face_joint_fraction.size(), faces, per_face);
  // Read into the rows of Vec3 and Inertia themselves: packed doubles (as_doubles).
  geo.vertices.resize(vertices.rows());
  vertices.read(0, vertices.rows(), as_doubles<3>(geo.vertices));
  geo.centroid.resize(n);
  centroid.read(0, n, as_doubles<3>(geo.centroid));
  geo.inertia.resize(n);
  inertia.read(0, n, as_doubles<6>(geo.inertia));
  return geo;
}

}  // namespace

const char* to_string(FileKind k) { return k == FileKind::joints ? "joints" : "blocks"; }

void write_joints(const fs::path& out, const JointSystem& js, const Provenance& prov,
                  const WriteOptions& opt) {
  check_joints(Checker(out.string(), kNotWritten), js);
  write_file(out, FileKind::joints, prov, js, opt, [](const Group&) {});
}

void write_blocks(const fs::path& out, const BlockSystem& bs, const Provenance& prov,
                  const WriteOptions& opt) {
  check_blocks(Checker(out.string(), kNotWritten), bs);
  write_file(out, FileKind::blocks, prov, bs.joints, opt, [&](const Group& root) {
    write_blocks_group(root, bs);
    if (bs.geometry) write_geometry_group(root, bs);
  });
}

// The bytes of a run's arrays.
std::size_t run_bytes(const Geometry& g) {
  return g.vertices.size() * sizeof(Vec3) + g.centroid.size() * sizeof(Vec3) +
         g.inertia.size() * sizeof(Inertia) +
         (g.vertex_offset.size() + g.face_vertex_offset.size() + g.face_vertices.size()) *
             sizeof(std::int64_t) +
         (g.volume.size() + g.face_area.size() + g.face_joint_fraction.size()) * sizeof(double);
}

// The runs of /geometry the writing thread has not taken yet hold at most this many bytes (or
// one run): a sink that would pass it waits. Uncompressed, the thread keeps up once /blocks is
// written (about 7 runs of Table 3 at 1.0 m queue meanwhile); deflate is slower than the
// geometry, and without a bound the whole of it would wait in memory.
constexpr std::size_t kQueuedBytes = std::size_t(256) << 20;

struct BlocksFileWriter::Impl {
  Impl(const BlockSystem& b, std::string n) : bs(b), name(std::move(n)) {}
  const BlockSystem& bs;
  std::string name;
  std::optional<OpenFile> file;
  std::future<void> writing;  // the header, joints, /blocks, then the runs of /geometry
  std::mutex mutex;
  std::condition_variable ready;  // a run came, or no more will
  std::condition_variable taken;  // the writing thread took a run, or stopped
  std::deque<Geometry> runs;      // given by the sink, not yet taken
  std::size_t queued_bytes = 0;   // their run_bytes
  bool streamed = false;          // geometry_sink() was asked for
  bool closed = false;            // no more runs will come
  bool abandoned = false;         // destroyed unfinished: write no more
  bool stopped = false;           // the writing thread ended (its error, if any, in `writing`)

  // The writing thread: /blocks, then each run as it comes, checked against its blocks.
  void write() {
    h5::silence_thread();  // a full disk: one error line, not HDF5's 41 lines of stack
    try {
      write_all();
    } catch (...) {
      stop();
      throw;
    }
    stop();
  }

  void write_all() {
    const Group& root = file->f.root();
    write_blocks_group(root, bs);
    std::optional<GeometryWriter> geo;
    const Checker c(name, kNotWritten);
    for (;;) {
      Geometry run;
      {
        std::unique_lock lock(mutex);
        ready.wait(lock, [&] { return !runs.empty() || closed; });
        if (runs.empty()) break;
        run = std::move(runs.front());
        runs.pop_front();
        queued_bytes -= run_bytes(run);
      }
      taken.notify_one();
      if (!geo) geo.emplace(root, bs);
      const std::size_t n = run.volume.size();
      check_geometry(c, bs, run, geo->next(), n, vertex_tolerance(bs.joints, run.vertices));
      geo->append(run, 0, 0, n);
    }
    if (abandoned) return;
    if (streamed && !geo) geo.emplace(root, bs);  // no blocks: empty datasets
    if (geo) geo->finish();
    if (!streamed && bs.geometry) write_geometry_group(root, bs);  // checked by finish()
  }

  // Queues a run, waiting while the queue is full; drops it once the thread has stopped.
  void give(Geometry&& run) {
    const std::size_t bytes = run_bytes(run);
    {
      std::unique_lock lock(mutex);
      taken.wait(lock, [&] {
        return stopped || abandoned || queued_bytes == 0 || queued_bytes + bytes <= kQueuedBytes;
      });
      if (stopped || abandoned) return;
      runs.push_back(std::move(run));
      queued_bytes += bytes;
    }
    ready.notify_one();
  }

  void stop() {
    {
      std::lock_guard lock(mutex);
      stopped = true;
      runs.clear();
      queued_bytes = 0;
    }
    taken.notify_all();
  }

  void close() {
    {
      std::lock_guard lock(mutex);
      closed = true;
    }
    ready.notify_one();
  }
};

BlocksFileWriter::BlocksFileWriter(const fs::path& out, const BlockSystem& bs,
                                   const Provenance& prov, const WriteOptions& opt)
    : impl_(std::make_unique<Impl>(bs, out.string())) {
  check_blocks(Checker(out.string(), kNotWritten), bs, false);
  // A bad output path fails here, before any work; the large /blocks group is written meanwhile.
  impl_->file.emplace(out, FileKind::blocks, prov, bs.joints, opt);
  impl_->writing = std::async(std::launch::async, [&m = *impl_] { m.write(); });
}

BlocksFileWriter::~BlocksFileWriter() {
  if (!impl_->writing.valid()) return;
  {
    // Unfinished: the runs not yet written are not wanted.
    std::lock_guard lock(impl_->mutex);
    impl_->runs.clear();
    impl_->queued_bytes = 0;
    impl_->abandoned = true;
  }
  impl_->taken.notify_all();
  impl_->close();
  impl_->writing.wait();
}

GeometrySink BlocksFileWriter::geometry_sink() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->streamed = true;
  }
  return [&m = *impl_](std::size_t first, Geometry&& part) {
    (void)first;  // runs come in block order: the writer counts the blocks
    m.give(std::move(part));
  };
}

void BlocksFileWriter::finish() {
  Impl& m = *impl_;
  if (m.bs.geometry && !m.streamed) check_geometry(Checker(m.name, kNotWritten), m.bs);
  m.close();
  m.writing.get();
  m.file->commit();
}

FileHeader read_header(const fs::path& in) {
  const h5::File f =
      h5::File::open(in, {in.string(), "regenerate it with the rockslice tool that made it"});
  return read_root_header(f.root());
}

JointSystem read_joints(const fs::path& in) {
  const h5::File f = h5::File::open(in, {in.string(), kJointsFix});
  expect_kind(f.root(), FileKind::joints);
  JointSystem js = read_joint_groups(f.root());
  check_joints(Checker(in.string(), kJointsFix), js);
  return js;
}

BlockSystem read_blocks(const fs::path& in) {
  const h5::File f = h5::File::open(in, {in.string(), kBlocksFix});
  expect_kind(f.root(), FileKind::blocks);
  BlockSystem bs;
  bs.joints = read_joint_groups(f.root());
  bs.blocks = read_blocks_group(f.root(), bs.pruned);
  if (f.root().exists("geometry")) {
    try {
      bs.geometry = read_geometry_group(f.root(), bs.blocks);
    } catch (const Error& e) {  // slice-vertices wrote /geometry, not slice-cut
      if (e.fix() != kBlocksFix) throw;
      throw Error(e.where(), e.problem(), kGeometryFix);
    }
  }
  check_blocks(Checker(in.string(), kBlocksFix), bs, false);
  if (bs.geometry) check_geometry(Checker(in.string(), kGeometryFix), bs);
  return bs;
}

}  // namespace slice
