// slice-stability on real files, against closed forms and invariants: a block on a plane (Hoek &
// Bray's plane failure, FoS = (c A + (W cos a - U) tan phi) / (W sin a), with water, a
// pseudo-static earthquake and support), Hoek & Bray's tetrahedral wedge of Itasca's 3DEC "Sliding
// Wedge" verification (planes 40/130 and 60/220), a pyramid that falls from a roof, a block hanging
// by its tension (FoS = t A / W), Goodman's three sets 30/90, 60/45 and 20/330 over a flat roof
// (only joint pyramid 101 is removable: Brady & Brown, Rock Mechanics for Underground Mining, 3rd
// ed., section 9.2.3, after Goodman 1989), successive failure, and the same answers when the scene
// is turned, moved or scaled and on any number of threads; bad input. Every scene goes through the
// real tools; /stability and /contacts are read with h5py (Debian's python3), the rest of the file
// with the library's reader (the output is a copy of geom.h5 plus those groups).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "slice/h5io.hpp"
#include "support/pipeline.hpp"
#include "support/support.hpp"

using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;
using slice::Vec3;
using test::run_tool;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRho = 2650, kG = 9.81;  // the tool's default density; g along -z
constexpr double kRhoWater = 1000;
double rad(double deg) { return deg * kPi / 180; }
double tand(double deg) { return std::tan(rad(deg)); }

/// The upward unit normal of a plane (docs/scenes.md, "Angles").
Vec3 upward_normal(double dip, double dd) {
  return {std::sin(rad(dip)) * std::sin(rad(dd)), std::sin(rad(dip)) * std::cos(rad(dd)),
          std::cos(rad(dip))};
}

std::string num(double x) {
  std::ostringstream s;
  s << std::setprecision(17) << x;
  return s.str();
}
std::string point(const Vec3& p) {
  std::ostringstream s;
  s << std::setprecision(17) << '[' << p.x() << ", " << p.y() << ", " << p.z() << ']';
  return s.str();
}

// --- running the tools ---------------------------------------------------------------------------

/// slice-joints -> slice-cut --prune -> slice-vertices on a scene text, written to
/// tmp/<stem>.toml; returns the path of <stem>-geom.h5 (<stem>-blocks.h5 stays beside it).
std::string geometry_of(const test::TempDir& tmp, const std::string& scene,
                        const std::string& stem = "scene") {
  const std::string toml = (tmp / (stem + ".toml")).string(),
                    joints = (tmp / (stem + "-joints.h5")).string(),
                    blocks = (tmp / (stem + "-blocks.h5")).string(),
                    geom = (tmp / (stem + "-geom.h5")).string();
  test::write_text(toml, scene);
  for (const auto& [tool, args] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"slice-joints", {toml, "-o", joints}},
           {"slice-cut", {joints, "--prune", "-o", blocks}},
           {"slice-vertices", {blocks, "-o", geom}}}) {
    const auto r = run_tool(tool, args);
    INFO(tool << ": " << r.err);
    REQUIRE(r.exit_code == 0);
  }
  return geom;
}

/// One dataset as h5py reads it: numpy's dtype name, the shape, the values flat in row order as
/// doubles (every integer here is far below 2^53; inf and nan kept).
struct Dataset {
  std::string dtype;
  std::vector<std::size_t> shape;
  std::vector<double> v;
};

/// Every dataset of /stability and /contacts of an HDF5 file, by "group/name".
std::map<std::string, Dataset> read_groups(const test::TempDir& tmp, const std::string& file) {
  const std::string script = R"(import h5py, json, math, sys
out = {}
with h5py.File(sys.argv[1], 'r') as f:
    for group in ('stability', 'contacts'):
        if group not in f:
            continue
        for name, ds in f[group].items():
            if not isinstance(ds, h5py.Dataset):
                continue
            a = ds[()]
            data = [x if not isinstance(x, float) or math.isfinite(x) else repr(x)
                    for x in a.reshape(-1).tolist()]
            out[group + '/' + name] = {'dtype': str(a.dtype), 'shape': list(a.shape), 'data': data}
with open(sys.argv[2], 'w') as f:
    json.dump(out, f)
)";
  const auto json = tmp / "datasets.json";
  test::fs::remove(json);
  REQUIRE(test::run_shell("/usr/bin/python3 -c " + test::shell_quote(script) + " " +
                          test::shell_quote(file) + " " + test::shell_quote(json)) == 0);
  const auto j = nlohmann::json::parse(test::read_bytes(json));
  std::map<std::string, Dataset> out;
  for (const auto& [name, d] : j.items()) {
    Dataset ds;
    ds.dtype = d["dtype"].get<std::string>();
    for (const auto& s : d["shape"]) ds.shape.push_back(s.get<std::size_t>());
    for (const auto& x : d["data"]) {
      if (!x.is_string()) {
        ds.v.push_back(x.get<double>());
      } else {
        const auto s = x.get<std::string>();
        ds.v.push_back(s == "inf"    ? kInf
                       : s == "-inf" ? -kInf
                                     : std::numeric_limits<double>::quiet_NaN());
      }
    }
    out[name] = std::move(ds);
  }
  return out;
}

/// A row of /contacts.
struct Contact {
  std::int64_t a = -1, b = -1, face_a = -1, face_b = -1, joint = -1;
  double area = 0, fraction = 0;
  Vec3 centroid = Vec3::Zero(), normal = Vec3::Zero();  // normal: a's outward
  bool free = false;
};

/// /stability, per block, and /contacts.
struct Stability {
  std::vector<int> removable, mode, generation;
  std::vector<double> fos;
  std::vector<Vec3> direction;
  std::vector<std::array<std::int64_t, 2>> planes;
  std::vector<Contact> contacts;
};

/// A dataset of the contract, its dtype and shape checked: (rows) or (rows, cols).
const Dataset& column(const std::map<std::string, Dataset>& m, const std::string& name,
                      const std::string& dtype, std::size_t rows, std::size_t cols = 0) {
  INFO("dataset /" << name);
  const auto it = m.find(name);
  REQUIRE(it != m.end());
  CHECK(it->second.dtype == dtype);
  const std::vector<std::size_t> shape =
      cols ? std::vector<std::size_t>{rows, cols} : std::vector<std::size_t>{rows};
  REQUIRE(it->second.shape == shape);
  return it->second;
}

Stability stability_datasets(const std::map<std::string, Dataset>& m, std::size_t blocks) {
  Stability s;
  const auto& removable = column(m, "stability/removable", "uint8", blocks);
  const auto& mode = column(m, "stability/mode", "uint8", blocks);
  const auto& fos = column(m, "stability/fos", "float64", blocks);
  const auto& direction = column(m, "stability/direction", "float64", blocks, 3);
  const auto& generation = column(m, "stability/generation", "int32", blocks);
  const auto& planes = column(m, "stability/planes", "int64", blocks, 2);
  for (std::size_t b = 0; b < blocks; ++b) {
    s.removable.push_back(static_cast<int>(removable.v[b]));
    s.mode.push_back(static_cast<int>(mode.v[b]));
    s.fos.push_back(fos.v[b]);
    s.direction.emplace_back(direction.v[3 * b], direction.v[3 * b + 1], direction.v[3 * b + 2]);
    s.generation.push_back(static_cast<int>(generation.v[b]));
    s.planes.push_back({static_cast<std::int64_t>(planes.v[2 * b]),
                        static_cast<std::int64_t>(planes.v[2 * b + 1])});
  }
  const auto it = m.find("contacts/pairs");
  REQUIRE(it != m.end());
  REQUIRE(it->second.shape.size() == 2);
  const std::size_t c = it->second.shape[0];
  const auto& pairs = column(m, "contacts/pairs", "int64", c, 2);
  const auto& faces = column(m, "contacts/faces", "int64", c, 2);
  const auto& area = column(m, "contacts/area", "float64", c);
  const auto& centroid = column(m, "contacts/centroid", "float64", c, 3);
  const auto& normal = column(m, "contacts/normal", "float64", c, 3);
  const auto& joint = column(m, "contacts/joint", "int64", c);
  const auto& fraction = column(m, "contacts/fraction", "float64", c);
  const auto& is_free = column(m, "contacts/free", "uint8", c);
  for (std::size_t k = 0; k < c; ++k) {
    Contact x;
    x.a = static_cast<std::int64_t>(pairs.v[2 * k]);
    x.b = static_cast<std::int64_t>(pairs.v[2 * k + 1]);
    x.face_a = static_cast<std::int64_t>(faces.v[2 * k]);
    x.face_b = static_cast<std::int64_t>(faces.v[2 * k + 1]);
    x.area = area.v[k];
    x.centroid = Vec3(centroid.v[3 * k], centroid.v[3 * k + 1], centroid.v[3 * k + 2]);
    x.normal = Vec3(normal.v[3 * k], normal.v[3 * k + 1], normal.v[3 * k + 2]);
    x.joint = static_cast<std::int64_t>(joint.v[k]);
    x.fraction = fraction.v[k];
    x.free = is_free.v[k] != 0;
    s.contacts.push_back(x);
  }
  return s;
}

/// What slice-stability wrote: the blocks (its copy of geom.h5, read and checked by the
/// library) and the new datasets.
struct Model {
  slice::BlockSystem bs;
  Stability st;
  std::vector<std::size_t> face_offset;  // B + 1: the blocks' rows in /blocks/face_*
  std::string path;

  std::size_t blocks() const { return bs.blocks.size(); }
  bool removed(std::int64_t b) const {
    return (bs.blocks[static_cast<std::size_t>(b)].flags & slice::kRemoved) != 0;
  }
  /// Neither removed, boundary nor fixed: a block that may move.
  bool movable(std::size_t b) const {
    return !removed(std::int64_t(b)) && !slice::is_fixed(bs.blocks[b]);
  }
  double volume(std::size_t b) const { return bs.geometry->volume[b]; }
  const Vec3& centroid(std::size_t b) const { return bs.geometry->centroid[b]; }
  double face_area(std::size_t b, std::size_t k) const {
    return bs.geometry->face_area[face_offset[b] + k];
  }
};

/// What a block touches: a row of /contacts seen from the block.
struct Touch {
  std::size_t row = 0;
  std::size_t face = 0;  // the block's own face (index into its faces)
  Vec3 normal;           // the block's outward normal
  std::int64_t other = -1;
  bool free = false;
  double area = 0;
  std::int64_t joint = -1;
};

std::vector<Touch> touches(const Model& m, std::size_t b) {
  std::vector<Touch> out;
  const auto bi = static_cast<std::int64_t>(b);
  for (std::size_t k = 0; k < m.st.contacts.size(); ++k) {
    const Contact& c = m.st.contacts[k];
    if (c.a != bi && c.b != bi) continue;
    const bool is_a = c.a == bi;
    const auto face = static_cast<std::size_t>(is_a ? c.face_a : c.face_b) - m.face_offset[b];
    out.push_back(
        {k, face, is_a ? c.normal : Vec3(-c.normal), is_a ? c.b : c.a, c.free, c.area, c.joint});
  }
  return out;
}

/// The options of a run, and what the contract checks need of them.
struct Run {
  std::vector<std::string> args;  // e.g. {"--free-faces", "+z,+x"}
  std::string free_faces;         // the --free-faces value among them ("" for none)
  double fos_target = 1;
};

/// The domain-face name of an axis-aligned outward normal ("" if it is none).
std::string box_face(const Vec3& n) {
  const char* names[3][2] = {{"-x", "+x"}, {"-y", "+y"}, {"-z", "+z"}};
  for (int i = 0; i < 3; ++i)
    if (std::abs(std::abs(n[i]) - 1) < 1e-12) return names[i][n[i] > 0 ? 1 : 0];
  return "";
}

bool names_face(const std::string& list, const std::string& face) {
  std::stringstream s(list);
  for (std::string x; std::getline(s, x, ',');)
    if (x == face) return true;
  return false;
}

/// The contract's rules that hold for every block and contact of any run.
void check_contract(const Model& m, const Run& run) {
  const std::size_t nb = m.blocks();
  const double L = m.bs.joints.length_scale;
  const auto& st = m.st;
  const auto joints = static_cast<std::int64_t>(m.bs.joints.joints.size());
  // Contacts: a is a kept block; b another block (a < b unless b is removed) or -1, the domain;
  // the faces are theirs and face each other; a face of a kept block is tiled by its contacts.
  std::vector<double> covered(m.face_offset.back(), 0.0);
  std::vector<bool> exposed(nb, false);
  for (std::size_t k = 0; k < st.contacts.size(); ++k) {
    const Contact& c = st.contacts[k];
    INFO("contact " << k << ": blocks " << c.a << ", " << c.b << ", faces " << c.face_a << ", "
                    << c.face_b << ", joint " << c.joint);
    REQUIRE(c.a >= 0);
    REQUIRE(c.a < std::int64_t(nb));
    REQUIRE(c.b >= -1);
    REQUIRE(c.b < std::int64_t(nb));
    const auto a = static_cast<std::size_t>(c.a);
    CHECK_FALSE(m.removed(c.a));
    REQUIRE(c.face_a >= std::int64_t(m.face_offset[a]));
    REQUIRE(c.face_a < std::int64_t(m.face_offset[a + 1]));
    const auto& fa = m.bs.blocks[a].faces[static_cast<std::size_t>(c.face_a) - m.face_offset[a]];
    CHECK((c.normal - fa.normal).norm() < 1e-12);
    CHECK(c.joint == fa.joint);
    CHECK(c.area > 0);
    CHECK(std::isfinite(c.area));
    CHECK(c.fraction > 0);
    CHECK(c.fraction <= 1);
    // The centroid lies on the face's plane.
    CHECK(std::abs(fa.normal.dot(c.centroid - m.bs.blocks[a].origin) - fa.d) < 1e-9 * L);
    covered[static_cast<std::size_t>(c.face_a)] += c.area;
    if (c.b == -1) {
      CHECK(c.face_b == -1);
      CHECK(c.joint == -1);
      const auto name = box_face(c.normal);
      CHECK(c.free == (!name.empty() && names_face(run.free_faces, name)));
    } else {
      const auto b = static_cast<std::size_t>(c.b);
      CHECK(c.free == m.removed(c.b));
      if (!m.removed(c.b)) CHECK(c.a < c.b);
      REQUIRE(c.face_b >= std::int64_t(m.face_offset[b]));
      REQUIRE(c.face_b < std::int64_t(m.face_offset[b + 1]));
      const auto& fb = m.bs.blocks[b].faces[static_cast<std::size_t>(c.face_b) - m.face_offset[b]];
      CHECK((c.normal + fb.normal).norm() < 1e-12);
      CHECK(fb.joint == c.joint);
      if (!m.removed(c.b)) covered[static_cast<std::size_t>(c.face_b)] += c.area;
    }
    if (c.free) exposed[a] = true;
  }
  // (Faces on construction joints are left out: inside a cluster they need not be contacts.)
  // One check for all faces, naming the worst.
  std::size_t uncovered = 0, worst_block = 0, worst_face = 0;
  double worst = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    if (m.removed(std::int64_t(b))) continue;
    for (std::size_t k = 0; k < m.bs.blocks[b].faces.size(); ++k) {
      const auto j = m.bs.blocks[b].faces[k].joint;
      if (j >= 0 &&
          m.bs.joints.joints[static_cast<std::size_t>(j)].kind == slice::JointKind::construction)
        continue;
      const double area = m.face_area(b, k), off = std::abs(covered[m.face_offset[b] + k] - area);
      if (!(off <= 1e-9 * area + 1e-9 * L * L)) ++uncovered;
      if (!(off <= worst)) worst = off, worst_block = b, worst_face = k;
    }
  }
  INFO("faces whose contacts do not add up to their area: "
       << uncovered << "; the worst, face " << worst_face << " of block " << worst_block
       << " (area " << m.face_area(worst_block, worst_face) << "), by " << worst);
  CHECK(uncovered == 0);
  // A cluster is exposed when any member is.
  std::map<std::int64_t, bool> cluster_exposed;
  for (std::size_t b = 0; b < nb; ++b)
    if (m.bs.blocks[b].cluster >= 0) cluster_exposed[m.bs.blocks[b].cluster] |= exposed[b];
  for (std::size_t b = 0; b < nb; ++b)
    if (m.bs.blocks[b].cluster >= 0) exposed[b] = cluster_exposed[m.bs.blocks[b].cluster];

  for (std::size_t b = 0; b < nb; ++b) {
    INFO("block " << b << ": mode " << st.mode[b] << ", removable " << st.removable[b] << ", fos "
                  << st.fos[b] << ", direction " << st.direction[b].transpose() << ", generation "
                  << st.generation[b] << ", planes " << st.planes[b][0] << " " << st.planes[b][1]);
    REQUIRE(st.mode[b] >= 0);
    REQUIRE(st.mode[b] <= 5);
    CHECK((st.removable[b] == 0 || st.removable[b] == 1));
    CHECK(st.generation[b] >= -1);
    for (const auto j : st.planes[b]) {
      CHECK(j >= -1);
      CHECK(j < joints);
    }
    if (!m.movable(b)) {
      CHECK(st.mode[b] == 0);
      CHECK(st.generation[b] == -1);
    }
    CHECK(st.removable[b] == (st.mode[b] >= 2 ? 1 : 0));
    if (st.mode[b] <= 2) {
      CHECK(st.fos[b] == kInf);
      CHECK(st.direction[b].isZero(0));
      CHECK(st.planes[b][0] == -1);
      CHECK(st.planes[b][1] == -1);
    } else {
      CHECK(std::abs(st.direction[b].norm() - 1) < 1e-12);
      CHECK(std::isfinite(st.fos[b]));
      CHECK(st.fos[b] >= 0);
    }
    if (st.mode[b] == 3) {
      CHECK(st.planes[b][0] == -1);
      CHECK(st.planes[b][1] == -1);
    }
    if (st.mode[b] == 4) CHECK(st.planes[b][1] == -1);
    // "fails" = a mode of motion with FoS below the target, in the round it fails in.
    if (st.generation[b] >= 0) {
      CHECK(st.mode[b] >= 3);
      CHECK(st.fos[b] < run.fos_target);
    } else if (st.mode[b] >= 3) {
      CHECK(st.fos[b] >= run.fos_target);
    }
    // Exposed at the start: a mode of its own; never exposed: nothing fails at once.
    if (m.movable(b) && exposed[b]) CHECK(st.mode[b] >= 1);
    if (!exposed[b]) CHECK(st.generation[b] != 0);
  }
  // A cluster's members carry the cluster's values.
  std::map<std::int64_t, std::size_t> first;
  for (std::size_t b = 0; b < nb; ++b) {
    const auto c = m.bs.blocks[b].cluster;
    if (c < 0 || m.removed(std::int64_t(b))) continue;
    const auto [it, fresh] = first.emplace(c, b);
    if (fresh) continue;
    const std::size_t f = it->second;
    INFO("cluster " << c << ": blocks " << f << " and " << b);
    CHECK(st.mode[b] == st.mode[f]);
    CHECK(st.removable[b] == st.removable[f]);
    CHECK(st.generation[b] == st.generation[f]);
    CHECK((st.fos[b] == st.fos[f] || (std::isnan(st.fos[b]) && std::isnan(st.fos[f]))));
    CHECK((st.direction[b].array() == st.direction[f].array()).all());
    CHECK(st.planes[b] == st.planes[f]);
  }
}

/// Runs slice-stability on geom.h5 into tmp/<out>, checks exit 0 and the contract's rules;
/// returns what it wrote.
Model stability_of(const test::TempDir& tmp, const std::string& geom, const Run& run,
                   const std::string& out_name = "stab.h5") {
  const std::string out = (tmp / out_name).string();
  std::vector<std::string> args = {geom, "-o", out};
  args.insert(args.end(), run.args.begin(), run.args.end());
  const auto r = run_tool("slice-stability", args);
  std::string line;
  for (const auto& a : run.args) line += " " + a;
  INFO("slice-stability" << line << ": " << r.err);
  REQUIRE(r.exit_code == 0);
  Model m;
  m.path = out;
  m.bs = slice::read_blocks(out);  // a copy of geom.h5 plus /contacts and /stability
  REQUIRE(m.bs.geometry);
  m.face_offset.push_back(0);
  for (const auto& b : m.bs.blocks) m.face_offset.push_back(m.face_offset.back() + b.faces.size());
  m.st = stability_datasets(read_groups(tmp, out), m.blocks());
  check_contract(m, run);
  return m;
}

/// The blocks that may move.
std::vector<std::size_t> movable_blocks(const Model& m) {
  std::vector<std::size_t> out;
  for (std::size_t b = 0; b < m.blocks(); ++b)
    if (m.movable(b)) out.push_back(b);
  return out;
}

/// The area of block b's contacts on joint j.
double area_on(const Model& m, std::size_t b, std::int64_t j) {
  double a = 0;
  for (const auto& t : touches(m, b))
    if (t.joint == j) a += t.area;
  return a;
}

std::set<std::int64_t> plane_set(const std::array<std::int64_t, 2>& p) { return {p[0], p[1]}; }

// --- limit equilibrium, independently of the tool
// -------------------------------------------------

/// A face a body presses on: its outward unit normal, tan(phi), c A [N], the joint.
struct Bearing {
  Vec3 m;
  double tan_phi = 0;
  double cohesion_force = 0;
  std::int64_t joint = -1;
};

/// Goodman & Shi's removability: some direction d != 0 with d . m <= 0 on every face. In 3-D the
/// cone of such d, if not {0}, holds -m of a face (all faces parallel) or an edge m_i x m_j.
bool removable(const std::vector<Bearing>& faces) {
  std::vector<Vec3> candidates;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    candidates.push_back(-faces[i].m);
    for (std::size_t j = i + 1; j < faces.size(); ++j) {
      const Vec3 e = faces[i].m.cross(faces[j].m);
      if (e.norm() < 1e-9) continue;
      candidates.push_back(e.normalized());
      candidates.push_back(-e.normalized());
    }
  }
  if (faces.empty()) return true;
  for (const auto& d : candidates)
    if (std::all_of(faces.begin(), faces.end(),
                    [&](const Bearing& f) { return f.m.dot(d) <= 1e-9; }))
      return true;
  return false;
}

struct Motion {
  bool removable = false;
  int mode = 1;
  Vec3 direction = Vec3::Zero();
  std::set<std::int64_t> planes{-1};
  double fos = kInf;
  int found = 0;  // modes that fit: more than one would make the scene ambiguous
};

/// Londe's and Goodman & Shi's modes under the resultant r: falls (leaves every face), slides on
/// one face (pressed on it, leaving the others) or on two (pressed on both, along their line);
/// FoS by limit equilibrium: one plane (c A + N tan phi) / S, two planes (c_A A_A + c_B A_B + N_A
/// tan phi_A + N_B tan phi_B) / (r along the line), N from equilibrium across the line.
Motion limit_equilibrium(const std::vector<Bearing>& faces, const Vec3& r) {
  Motion mo;
  mo.removable = removable(faces);
  if (!mo.removable) return mo;
  mo.mode = 2;
  const double w = r.norm(), tol = 1e-9;
  const Vec3 u = r / w;
  if (std::all_of(faces.begin(), faces.end(),
                  [&](const Bearing& f) { return u.dot(f.m) < -tol; })) {
    mo.mode = 3;
    mo.direction = u;
    mo.fos = 0;  // no tension in the scenes checked with this
    mo.found = 1;
    return mo;
  }
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const double n = u.dot(faces[i].m);
    if (n <= tol) continue;
    const Vec3 s = u - n * faces[i].m;
    if (s.norm() <= tol) continue;
    const Vec3 d = s.normalized();
    bool leaves = true;
    for (std::size_t k = 0; k < faces.size(); ++k)
      if (k != i && d.dot(faces[k].m) > tol) leaves = false;
    if (!leaves) continue;
    ++mo.found;
    mo.mode = 4;
    mo.direction = d;
    mo.planes = {faces[i].joint, -1};
    mo.fos = (faces[i].cohesion_force + w * n * faces[i].tan_phi) / (w * s.norm());
  }
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (std::size_t j = i + 1; j < faces.size(); ++j) {
      Vec3 t = faces[i].m.cross(faces[j].m);
      if (t.norm() < 1e-9) continue;
      t.normalize();
      if (t.dot(u) < 0) t = -t;
      Eigen::Matrix3d a;
      a << faces[i].m, faces[j].m, t;
      const Vec3 x = a.colPivHouseholderQr().solve(u);  // u = N_i m_i + N_j m_j + S t
      if (x[0] <= tol || x[1] <= tol || x[2] <= tol) continue;
      bool leaves = true;
      for (std::size_t k = 0; k < faces.size(); ++k)
        if (k != i && k != j && t.dot(faces[k].m) > tol) leaves = false;
      if (!leaves) continue;
      ++mo.found;
      mo.mode = 5;
      mo.direction = t;
      mo.planes = {faces[i].joint, faces[j].joint};
      mo.fos = (faces[i].cohesion_force + faces[j].cohesion_force +
                w * (x[0] * faces[i].tan_phi + x[1] * faces[j].tan_phi)) /
               (w * x[2]);
    }
  return mo;
}

// --- scenes
// ---------------------------------------------------------------------------------------

/// A block on a plane of dip 30 dipping east: the domain [0, 12] x [0, 4] x [0, 8], the plane
/// through (6, 2, 5), so z = 8 at x = 6 - 3 / tan 30 and z = 5 - 6 tan 30 = 1.536 at x = 12; the
/// rock below it touches the base and is fixed. With --free-faces +z,+x,-y,+y the block above
/// touches nothing but the plane. `cluster`: a vertical construction joint at x = 9 cuts it into
/// two blocks that move as one.
std::string plane_scene(double phi, double cohesion, bool cluster = false) {
  std::ostringstream s;
  s << "[scene]\nname = \"plane\"\n[domain]\nbox = { min = [0, 0, 0], max = [12, 4, 8] }\n"
    << "[options]\nfixed_faces = [\"-z\"]\n"
    << "[[joints]]\ndip = 30\ndip_direction = 90\npoint = [6, 2, 5]\nfriction_angle = " << num(phi)
    << "\ncohesion = " << num(cohesion) << "\n";
  if (cluster)
    s << "[[joints]]\ndip = 90\ndip_direction = 90\npoint = [9, 2, 4]\nkind = \"construction\"\n";
  return s.str();
}
constexpr double kPlaneDip = 30;
const std::string kPlaneFree = "+z,+x,-y,+y";

/// The block on that plane in closed form: its length in plan l = 6 + 3 / tan a (from z = 8 down
/// to x = 12), width 4.
struct PlaneBlock {
  double a = rad(kPlaneDip);
  double l = 6 + 3 / std::tan(a);
  double volume = 4 * 0.5 * l * l * std::tan(a);  // a right prism on the triangle l by l tan a
  double area = 4 * l / std::cos(a);              // the contact on the plane
  double z_low = 5 - 6 * std::tan(a);             // its lowest edge (x = 12)
  double z_centroid = (8 + z_low) / 2;            // the contact's centroid
  double area_east = 4 * (8 - z_low);             // the free face x = 12
  double area_top = 4 * l;                        // the free face z = 8
  Vec3 down_dip = Vec3(std::cos(a), 0, -std::sin(a));
  Vec3 outward = -upward_normal(kPlaneDip, 90);  // the block's, on the plane
};

/// Itasca's 3DEC "Sliding Wedge" verification (Hoek & Bray): planes A (40/130) and B (60/220)
/// through (10, 10, 12) in a 20 m cube, both boundary joints keeping what lies below them; the
/// wedge above both is the one block that moves. Run with every face but the base free.
std::string wedge_scene(double phi_a, double phi_b, double c_a, double c_b) {
  std::ostringstream s;
  s << "[scene]\nname = \"wedge\"\n[domain]\nbox = { min = [0, 0, 0], max = [20, 20, 20] }\n"
    << "[options]\norder = \"as-given\"\n";
  const std::array<std::array<double, 4>, 2> planes = {
      {{40, 130, phi_a, c_a}, {60, 220, phi_b, c_b}}};
  int stage = 1;
  for (const auto& p : planes)
    s << "[[joints]]\ndip = " << num(p[0]) << "\ndip_direction = " << num(p[1])
      << "\npoint = [10, 10, 12]\nkind = \"boundary\"\nkeep = \"below\"\nfriction_angle = "
      << num(p[2]) << "\ncohesion = " << num(p[3]) << "\nstage = " << stage++ << "\n";
  return s.str();
}

/// A block hanging from a fixed block above it by the tension t of the joint between them: the
/// domain [0, 4]^3, the joint z = 2; run with every face but the top free.
std::string hanging_scene(double tension) {
  std::ostringstream s;
  s << "[scene]\nname = \"hanging\"\n[domain]\nbox = { min = [0, 0, 0], max = [4, 4, 4] }\n"
    << "[options]\nfixed_faces = [\"+z\"]\n"
    << "[[joints]]\ndip = 0\ndip_direction = 0\npoint = [2, 2, 2]\ntension = " << num(tension)
    << "\n";
  return s.str();
}

/// A similarity of the plan: turn by `turn_deg` about the vertical through the origin (clockwise
/// seen from above, as azimuths turn: a dip direction gains turn_deg), scale, then shift.
struct Frame {
  double turn_deg = 0;
  double scale = 1;
  Vec3 shift = Vec3::Zero();

  Vec3 vector(const Vec3& v) const {
    const double c = std::cos(rad(turn_deg)), s = std::sin(rad(turn_deg));
    return {c * v.x() + s * v.y(), -s * v.x() + c * v.y(), v.z()};
  }
  Vec3 back(const Vec3& v) const {
    const double c = std::cos(rad(turn_deg)), s = std::sin(rad(turn_deg));
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
  }
  Vec3 point(const Vec3& p) const { return scale * vector(p) + shift; }
  double azimuth(double az) const { return std::fmod(az + turn_deg + 360, 360.0); }
};

/// Half-spaces n . x <= d of a box, in a frame, as a TOML array of tables.
std::string box_planes(const Frame& f, const Vec3& lo, const Vec3& hi) {
  std::string s = "[";
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {-1, 1}) {
      Vec3 n = Vec3::Zero();
      n[axis] = side;
      const double d = side > 0 ? hi[axis] : -lo[axis];
      const Vec3 nf = f.vector(n);
      if (s.size() > 1) s += ", ";
      s += "{ normal = ";
      s += point(nf);
      s += ", d = ";
      s += num(f.scale * d + nf.dot(f.shift));
      s += " }";
    }
  return s + "]";
}

/// Goodman's three sets (Brady & Brown's example: 30/90, 60/45, 20/330), regular at 2 m, over an
/// opening: the domain [0, 20] x [0, 20] x [0, 14], a horizontal rock joint z = 7 for the roof
/// and the zone [5, 15] x [5, 15] x [3, 7] below it removed (its walls and floor are as rough as
/// the blocks). `cohesion`: of J1, J2, J3 [Pa, before scaling]; friction 40, 35, 35 (the roof
/// joint 30, no cohesion). In the frame f: dip directions turned, lengths and cohesion scaled (so
/// c / (rho g L) and every FoS stay), points shifted.
std::string goodman_scene(const Frame& f, const std::array<double, 3>& cohesion = {0, 0, 0}) {
  std::ostringstream s;
  s << "[scene]\nname = \"goodman-roof\"\n[domain]\nplanes = "
    << box_planes(f, Vec3(0, 0, 0), Vec3(20, 20, 14)) << "\n";
  const std::array<std::array<double, 4>, 3> sets = {
      {{30, 90, 0.3, 40}, {60, 45, 0.7, 35}, {20, 330, 1.1, 35}}};  // dip, dd, offset, phi
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& [dip, dd, offset, phi] = sets[i];
    const double ddf = f.azimuth(dd);
    // The planes n . x = offset + k spacing move to n' . x' = scale (offset + k spacing) + n' . t.
    s << "[[sets]]\nname = \"J" << i + 1 << "\"\ndip = " << num(dip)
      << "\ndip_direction = " << num(ddf) << "\nspacing = " << num(2 * f.scale)
      << "\noffset = " << num(f.scale * offset + upward_normal(dip, ddf).dot(f.shift))
      << "\nfriction_angle = " << num(phi) << "\ncohesion = " << num(f.scale * cohesion[i]) << "\n";
  }
  s << "[[joints]]\ndip = 0\ndip_direction = 0\npoint = " << point(f.point(Vec3(10, 10, 7)))
    << "\nfriction_angle = 30\n"
    << "[[zones]]\nplanes = " << box_planes(f, Vec3(5, 5, 3), Vec3(15, 15, 7)) << "\n";
  return s.str();
}

std::string data_scene(const std::string& name) {
  return test::read_bytes(test::test_data_path("stability/" + name));
}

void check_direction(const Vec3& got, const Vec3& want, double tol = 1e-9) {
  INFO("direction " << got.transpose() << ", expected " << want.transpose());
  CHECK((got - want).norm() < tol);
}

}  // namespace

TEST_CASE("slice-stability answers --help and --version", "[tools][stability]") {
  CHECK(run_tool("slice-stability", {"--help"}).exit_code == 0);
  CHECK_THAT(run_tool("slice-stability", {"--version"}).out, Catch::Contains("rockslice"));
}

TEST_CASE("a block on a plane slides down the dip with FoS (c A + W cos a tan phi) / (W sin a)",
          "[tools][stability]") {
  struct Case {
    double phi, cohesion;
    bool cluster;
  };
  // Friction either side of the dip, with and without cohesion; the last as a cluster of two.
  const auto k = GENERATE(Case{20, 0, false}, Case{40, 0, false}, Case{20, 2e4, false},
                          Case{25, 5e3, false}, Case{25, 5e3, true});
  CAPTURE(k.phi, k.cohesion, k.cluster);
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, plane_scene(k.phi, k.cohesion, k.cluster));
  const Run run{{"--free-faces", kPlaneFree}, kPlaneFree};
  const auto m = stability_of(tmp, geom, run);

  // The output is geom.h5 and more: the same blocks, the same geometry.
  const auto g = slice::read_blocks(geom);
  REQUIRE(g.blocks.size() == m.blocks());
  CHECK(g.geometry->volume == m.bs.geometry->volume);
  CHECK(g.geometry->face_area == m.bs.geometry->face_area);
  for (std::size_t b = 0; b < m.blocks(); ++b) {
    CHECK(g.blocks[b].flags == m.bs.blocks[b].flags);
    CHECK(g.blocks[b].faces.size() == m.bs.blocks[b].faces.size());
  }

  const PlaneBlock pb;
  const auto body = movable_blocks(m);  // the block on the plane, or the cluster's two members
  REQUIRE(body.size() == (k.cluster ? 2u : 1u));
  double volume = 0, area = 0;
  for (const auto b : body) {
    volume += m.volume(b);
    area += area_on(m, b, 0);
    for (const auto& t : touches(m, b))
      if (t.joint == 0) check_direction(t.normal, pb.outward, 1e-12);
  }
  CHECK_THAT(volume, WithinRel(pb.volume, 1e-9));
  CHECK_THAT(area, WithinRel(pb.area, 1e-9));
  const double w = kRho * kG * volume, a = pb.a;
  const double fos = (k.cohesion * area + w * std::cos(a) * tand(k.phi)) / (w * std::sin(a));
  CAPTURE(volume, area, w, fos);
  for (const auto b : body) {
    CAPTURE(b);
    CHECK(m.st.mode[b] == 4);
    CHECK(m.st.removable[b] == 1);
    check_direction(m.st.direction[b], pb.down_dip);
    CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, -1});
    CHECK_THAT(m.st.fos[b], WithinRel(fos, 1e-6));
    CHECK(m.st.generation[b] == (fos < 1 ? 0 : -1));
  }
  // The fixed rock below: nothing.
  for (std::size_t b = 0; b < m.blocks(); ++b)
    if (!m.movable(b)) CHECK(m.st.mode[b] == 0);
}

TEST_CASE(
    "water, an earthquake, support and the density change the plane's FoS as the closed "
    "forms say",
    "[tools][stability]") {
  const double phi = 40, cohesion = 1e4;
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, plane_scene(phi, cohesion));
  const PlaneBlock pb;
  const double a = pb.a, t = tand(phi);
  struct Case {
    std::string name;
    std::vector<std::string> args;
    double fos;  // 0: computed below from the block's own volume and contact
    Vec3 direction;
  };
  // The block's weight and contact from a dry run.
  const Run dry{{"--free-faces", kPlaneFree}, kPlaneFree};
  const auto m0 = stability_of(tmp, geom, dry, "dry.h5");
  const auto body = movable_blocks(m0);
  REQUIRE(body.size() == 1);
  const std::size_t b = body[0];
  const double v = m0.volume(b), area = area_on(m0, b, 0), w = kRho * kG * v, ca = cohesion * area;
  CHECK_THAT(m0.st.fos[b], WithinRel((ca + w * std::cos(a) * t) / (w * std::sin(a)), 1e-6));
  // The contact's centroid, for the water's pressure.
  double zc = 0;
  for (const auto& x : touches(m0, b))
    if (x.joint == 0) zc = m0.st.contacts[x.row].centroid.z();
  CHECK_THAT(zc, WithinAbs(pb.z_centroid, 1e-9));

  std::vector<Case> cases;
  {  // A water table at the top of the plane: U = rho_w g (z_w - z_c) A on all of it.
    const double u = kRhoWater * kG * (8 - pb.z_centroid) * area;
    cases.push_back({"water table at z = 8",
                     {"--water-table", "8"},
                     (ca + (w * std::cos(a) - u) * t) / (w * std::sin(a)),
                     pb.down_dip});
  }
  {  // Part of it under water: U = rho_w g width h^2 / (2 sin a), h = z_w - z of its lowest edge.
    const double h = 4 - pb.z_low, u = kRhoWater * kG * 4 * h * h / (2 * std::sin(a));
    cases.push_back({"water table at z = 4",
                     {"--water-table", "4"},
                     (ca + (w * std::cos(a) - u) * t) / (w * std::sin(a)),
                     pb.down_dip});
  }
  {  // k W towards the dip direction (east): N = W (cos a - k sin a), S = W (sin a + k cos a).
    const double kk = 0.1;
    cases.push_back(
        {"seismic 0.1 towards 90",
         {"--seismic", "0.1", "--seismic-azimuth", "90"},
         (ca + w * (std::cos(a) - kk * std::sin(a)) * t) / (w * (std::sin(a) + kk * std::cos(a))),
         pb.down_dip});
  }
  {  // k W towards north, along the strike: S = W sqrt(sin^2 a + k^2), turned towards north.
    const double kk = 0.15, s = std::sqrt(std::sin(a) * std::sin(a) + kk * kk);
    cases.push_back({"seismic 0.15 towards 0",
                     {"--seismic", "0.15", "--seismic-azimuth", "0"},
                     (ca + w * std::cos(a) * t) / (w * s),
                     Vec3(std::sin(a) * std::cos(a), kk, -std::sin(a) * std::sin(a)) / s});
  }
  {  // p on the free faces, inwards: the east face pushes west, the top down, the sides cancel.
    const double p = 5e4;
    const double n = w * std::cos(a) + p * (pb.area_east * std::sin(a) + pb.area_top * std::cos(a));
    const double s = w * std::sin(a) + p * (pb.area_top * std::sin(a) - pb.area_east * std::cos(a));
    cases.push_back(
        {"support 5e4 Pa", {"--support-pressure", "5e4"}, (ca + n * t) / s, pb.down_dip});
  }
  {  // A lighter rock: cohesion counts for more.
    const double w2 = 2000 * kG * v;
    cases.push_back({"density 2000",
                     {"--density", "2000"},
                     (ca + w2 * std::cos(a) * t) / (w2 * std::sin(a)),
                     pb.down_dip});
  }
  int i = 0;
  for (const auto& c : cases) {
    CAPTURE(c.name, c.fos);
    Run run{{"--free-faces", kPlaneFree}, kPlaneFree};
    run.args.insert(run.args.end(), c.args.begin(), c.args.end());
    const auto m = stability_of(tmp, geom, run, "case" + std::to_string(i++) + ".h5");
    CHECK(m.st.mode[b] == 4);
    check_direction(m.st.direction[b], c.direction);
    CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, -1});
    CHECK_THAT(m.st.fos[b], WithinRel(c.fos, 1e-6));
    CHECK(m.st.generation[b] == (c.fos < 1 ? 0 : -1));
  }
  // The free faces the support pressure acts on, seen from the geometry.
  double east = 0, top = 0;
  for (std::size_t k = 0; k < m0.bs.blocks[b].faces.size(); ++k) {
    const Vec3& n = m0.bs.blocks[b].faces[k].normal;
    if (n.x() > 1 - 1e-12) east = m0.face_area(b, k);
    if (n.z() > 1 - 1e-12) top = m0.face_area(b, k);
  }
  CHECK_THAT(east, WithinRel(pb.area_east, 1e-9));
  CHECK_THAT(top, WithinRel(pb.area_top, 1e-9));
}

TEST_CASE(
    "Hoek & Bray's wedge (3DEC's Sliding Wedge, planes 40/130 and 60/220) slides along "
    "the line of intersection with FoS (c_A A_A + c_B A_B + R_A tan phi_A + R_B tan phi_B) / "
    "(W sin psi)",
    "[tools][stability]") {
  struct Case {
    double phi_a, phi_b, c_a, c_b;
  };
  const auto k = GENERATE(Case{30, 30, 0, 0}, Case{45, 45, 0, 0}, Case{35, 25, 2e4, 1e4});
  CAPTURE(k.phi_a, k.phi_b, k.c_a, k.c_b);
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, wedge_scene(k.phi_a, k.phi_b, k.c_a, k.c_b));
  const std::string free_faces = "-x,+x,-y,+y,+z";
  const auto m = stability_of(tmp, geom, Run{{"--free-faces", free_faces}, free_faces});
  const auto body = movable_blocks(m);
  REQUIRE(body.size() == 1);
  const std::size_t b = body[0];

  // The weight W (0, 0, -1) is carried by normal reactions R_A, R_B on the planes (the wedge's
  // outward normals are -n_A, -n_B) and a force S along the line of intersection t, plunging
  // psi: W (0, 0, -1) = R_A (-n_A) + R_B (-n_B) + S t, S = W sin psi.
  const Vec3 na = upward_normal(40, 130), nb = upward_normal(60, 220);
  Vec3 t = na.cross(nb).normalized();
  if (t.z() > 0) t = -t;
  Eigen::Matrix3d eq;
  eq << -na, -nb, t;
  const Vec3 x = eq.colPivHouseholderQr().solve(Vec3(0, 0, -1));
  REQUIRE(x[0] > 0);
  REQUIRE(x[1] > 0);
  const double psi = std::asin(-t.z()) * 180 / kPi;
  CHECK_THAT(x[2], WithinRel(std::sin(rad(psi)), 1e-12));
  const double area_a = area_on(m, b, 0), area_b = area_on(m, b, 1);
  for (const auto& [j, area] : {std::pair{0, area_a}, std::pair{1, area_b}}) {
    double face = 0;
    for (std::size_t f = 0; f < m.bs.blocks[b].faces.size(); ++f)
      if (m.bs.blocks[b].faces[f].joint == j) face += m.face_area(b, f);
    CHECK_THAT(area, WithinRel(face, 1e-9));  // the rock below covers each face
  }
  const double w = kRho * kG * m.volume(b);
  const double fos =
      (k.c_a * area_a + k.c_b * area_b + w * (x[0] * tand(k.phi_a) + x[1] * tand(k.phi_b))) /
      (w * x[2]);
  CAPTURE(psi, x[0], x[1], area_a, area_b, m.volume(b), fos);
  CHECK(m.st.mode[b] == 5);
  CHECK(m.st.removable[b] == 1);
  check_direction(m.st.direction[b], t);
  CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, 1});
  CHECK_THAT(m.st.fos[b], WithinRel(fos, 1e-6));
  CHECK(m.st.generation[b] == (fos < 1 ? 0 : -1));
}

TEST_CASE("a block falls from a roof, from among removed blocks, or hangs by t A >= W",
          "[tools][stability]") {
  SECTION("the pyramid over the opening of roof-pyramid.toml falls with FoS 0") {
    test::TempDir tmp;
    const auto geom = geometry_of(tmp, data_scene("roof-pyramid.toml"));
    const auto m = stability_of(tmp, geom, Run{});
    // The pyramid: base [3, 7]^2 at z = 5, apex 2 tan 60 above; its centroid a quarter up.
    const double h = 2 * std::tan(rad(60));
    std::vector<std::size_t> pyramid;
    for (std::size_t b = 0; b < m.blocks(); ++b)
      if ((m.centroid(b) - Vec3(5, 5, 5 + h / 4)).norm() < 1e-9) pyramid.push_back(b);
    REQUIRE(pyramid.size() == 1);
    const std::size_t b = pyramid[0];
    CHECK_THAT(m.volume(b), WithinRel(16 * h / 3, 1e-9));
    int free = 0, held = 0;
    for (const auto& x : touches(m, b)) (x.free ? free : held) += 1;
    CHECK(free >= 1);  // its base, on the removed blocks of the opening
    CHECK(held == 4);  // its four sides
    CHECK(m.st.mode[b] == 3);
    CHECK(m.st.removable[b] == 1);
    check_direction(m.st.direction[b], Vec3(0, 0, -1));
    CHECK(m.st.fos[b] == 0);
    CHECK(m.st.generation[b] == 0);
  }
  SECTION("the block of island.toml, whose every neighbour is removed, falls") {
    test::TempDir tmp;
    const auto geom = geometry_of(tmp, data_scene("island.toml"));
    const auto m = stability_of(tmp, geom, Run{});
    std::vector<std::size_t> centre;
    for (std::size_t b = 0; b < m.blocks(); ++b)
      if ((m.centroid(b) - Vec3(5, 5, 5)).norm() < 1e-9) centre.push_back(b);
    REQUIRE(centre.size() == 1);
    const std::size_t b = centre[0];
    const auto x = touches(m, b);
    CHECK(x.size() == 6);
    for (const auto& c : x) CHECK(c.free);
    CHECK(m.st.mode[b] == 3);
    CHECK(m.st.removable[b] == 1);
    check_direction(m.st.direction[b], Vec3(0, 0, -1));
    CHECK(m.st.fos[b] == 0);
    CHECK(m.st.generation[b] == 0);
  }
  SECTION("a block hanging by the tension of the joint above it: FoS = t A / W") {
    const double ratio = GENERATE(0.5, 1.6);  // t A / W
    CAPTURE(ratio);
    const double w = kRho * kG * 4 * 4 * 2, area = 16;
    test::TempDir tmp;
    const auto geom = geometry_of(tmp, hanging_scene(ratio * w / area));
    const std::string free_faces = "-x,+x,-y,+y,-z";
    const auto m = stability_of(tmp, geom, Run{{"--free-faces", free_faces}, free_faces});
    const auto body = movable_blocks(m);
    REQUIRE(body.size() == 1);  // the block below; the one above touches the fixed top
    const std::size_t b = body[0];
    CHECK_THAT(m.volume(b), WithinRel(32, 1e-12));
    CHECK(m.st.mode[b] == 3);
    check_direction(m.st.direction[b], Vec3(0, 0, -1));
    CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{-1});
    CHECK_THAT(m.st.fos[b], WithinRel(ratio, 1e-6));
    CHECK(m.st.generation[b] == (ratio < 1 ? 0 : -1));
  }
}

TEST_CASE(
    "over a flat roof only blocks of joint pyramid 101 of Goodman's sets 30/90, 60/45 and "
    "20/330 are removable, and they slide on the 60/45 set",
    "[tools][stability]") {
  // Brady & Brown (Rock Mechanics for Underground Mining, 3rd ed., section 9.2.3, figure 9.8,
  // after Goodman 1989): for these three sets and a horizontal roof, "of the eight JPs, only JP
  // 101 has no intersection with the EP": the blocks removable from the roof lie below joint 1,
  // above joint 2 and below joint 3 (digit 0: the upper half-space of that joint, 1: the lower;
  // their JP 100 is "L1 U2 U3"). The three edges of JP 101 all plunge, so a block of it is finite
  // under the roof; the vertical is not in it (it is in JP 111, whose edges are not all
  // downwards): gravity presses a key block onto its joint-2 face, and it slides on it (mode 4),
  // down the dip of 60/45, FoS tan 35 / tan 60, rather than falling.
  //
  // With regular sets every block above the roof is a cell of the three sets cut by it, and it
  // keeps the cell's highest corner, where its faces below J1, above J2 and below J3 meet: each
  // roof block belongs to JP 101, and is removable when the faces it has beyond those (the cell's
  // opposite ones) leave a direction within JP 101 (a tetrahedron, or a slab between two joints
  // of one set). Each roof block is checked against an independent limit-equilibrium analysis of
  // its faces: in a run where only falling blocks could fail (--fos-target 1e-9), and in one with
  // the default target, where a block that can slide with FoS below 1 fails at once. A block's
  // answer is its first round's where it fails then (generation 0) or where nothing it touches
  // ever fails (its surroundings never change).
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, goodman_scene(Frame{}));
  const auto m = stability_of(tmp, geom, Run{{"--fos-target", "1e-9"}, "", 1e-9}, "slides.h5");
  const auto rounds = stability_of(tmp, geom, Run{});
  const auto& joints = m.bs.joints.joints;
  std::int64_t roof = -1;
  for (std::size_t j = 0; j < joints.size(); ++j)
    if (joints[j].set < 0) roof = std::int64_t(j);
  REQUIRE(roof >= 0);
  const std::array<Vec3, 3> n = {upward_normal(30, 90), upward_normal(60, 45),
                                 upward_normal(20, 330)};
  const std::array<int, 3> jp101 = {-1, +1, -1};  // below J1 (outward +n1), above J2, below J3

  int roof_blocks = 0, compared = 0, movers = 0, key_tetrahedra = 0;
  for (const auto b : movable_blocks(m)) {
    const auto x = touches(m, b);
    const bool exposed = std::any_of(x.begin(), x.end(), [](const Touch& t) { return t.free; });
    const bool roof_only = std::all_of(x.begin(), x.end(), [&](const Touch& t) {
      return !t.free || (t.joint == roof && t.normal.z() < -1 + 1e-12);
    });
    const auto& faces = m.bs.blocks[b].faces;
    const bool on_domain =
        std::any_of(faces.begin(), faces.end(), [](const slice::Face& f) { return f.joint < 0; });
    if (!exposed || !roof_only || on_domain) continue;
    ++roof_blocks;
    CAPTURE(b, m.volume(b), m.centroid(b).transpose());
    // The faces it presses on: all but those wholly on removed blocks.
    std::vector<double> free_area(faces.size(), 0.0);
    for (const auto& t : x)
      if (t.free) free_area[t.face] += t.area;
    std::vector<Bearing> bearing;
    std::array<std::set<int>, 3> sides;  // per set: -1 the block below a joint of it, +1 above
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto& face = faces[f];
      const auto& joint = joints[static_cast<std::size_t>(face.joint)];
      if (joint.set >= 0)
        sides[static_cast<std::size_t>(joint.set)].insert(
            face.normal.dot(joint.plane.normal) > 0 ? -1 : +1);
      if (free_area[f] >= m.face_area(b, f) * (1 - 1e-9)) continue;
      bearing.push_back({face.normal, tand(joint.friction_angle_deg), 0, face.joint});
    }
    // Every roof block has a face on JP 101's side of each set.
    for (std::size_t i = 0; i < 3; ++i) CHECK(sides[i].count(jp101[i]) == 1);

    const auto want = limit_equilibrium(bearing, Vec3(0, 0, -1));
    CHECK(want.found <= 1);
    INFO("expected mode " << want.mode << ", direction " << want.direction.transpose() << ", fos "
                          << want.fos);
    // Whether a run's answer for b is its first round's.
    const auto first_round = [&](const Model& run) {
      if (run.st.generation[b] == 0) return true;
      if (run.st.generation[b] > 0) return false;
      return std::none_of(x.begin(), x.end(), [&](const Touch& t) {
        return t.other >= 0 && run.st.generation[static_cast<std::size_t>(t.other)] >= 0;
      });
    };
    for (const Model* run : {&m, &rounds}) {
      const auto& st = run->st;
      INFO((run == &m ? "--fos-target 1e-9" : "the default target"));
      if (!first_round(*run)) continue;
      ++compared;
      CHECK(st.removable[b] == (want.removable ? 1 : 0));
      CHECK(st.mode[b] == want.mode);
      if (want.mode >= 3) {
        check_direction(st.direction[b], want.direction);
        CHECK(plane_set(st.planes[b]) == want.planes);
        CHECK_THAT(st.fos[b], WithinRel(want.fos, 1e-6));
      }
    }
    // Failing at once: a mode of motion with FoS below 1 (others may fail once a neighbour has
    // gone).
    CHECK((rounds.st.generation[b] == 0) == (want.mode >= 3 && want.fos < 1));
    if (!first_round(m)) continue;
    if (m.st.mode[b] >= 3) {
      ++movers;
      // It moves within JP 101 (closed): away from J1 and J3 below it, from J2 above it.
      const Vec3& d = m.st.direction[b];
      CHECK(d.dot(n[0]) <= 1e-9);
      CHECK(d.dot(n[1]) >= -1e-9);
      CHECK(d.dot(n[2]) <= 1e-9);
      CHECK(d.z() < 0);
      CHECK(m.st.mode[b] != 3);  // the vertical is outside JP 101
    }
    // A key block of JP 101 itself: the tetrahedron of one joint of each set and the roof.
    bool tetrahedron = bearing.size() == 3;
    for (std::size_t i = 0; i < 3; ++i) tetrahedron = tetrahedron && sides[i].size() == 1;
    if (tetrahedron) {
      ++key_tetrahedra;
      std::int64_t j2 = -1;
      for (const auto& f : faces)
        if (f.joint >= 0 && joints[static_cast<std::size_t>(f.joint)].set == 1) j2 = f.joint;
      CHECK(m.st.mode[b] == 4);
      CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{j2, -1});
      check_direction(m.st.direction[b],
                      Vec3(std::cos(rad(60)) * std::sin(rad(45)),
                           std::cos(rad(60)) * std::cos(rad(45)), -std::sin(rad(60))));
      CHECK_THAT(m.st.fos[b], WithinRel(tand(35) / tand(60), 1e-6));
      CHECK(rounds.st.generation[b] == 0);
    }
  }
  CAPTURE(roof_blocks, compared, movers, key_tetrahedra);
  CHECK(roof_blocks >= 10);
  CHECK(compared >= roof_blocks);  // most of them twice
  CHECK(movers >= 1);
  CHECK(key_tetrahedra >= 1);
}

TEST_CASE("slice-stability gives the same answers when the scene is turned, moved or scaled",
          "[tools][stability]") {
  // Goodman's roof with cohesion on two sets, once as given and once with an earthquake and a
  // water table. Turned 37 degrees about the vertical (dip directions and the seismic azimuth +
  // 37, domain and zone turned; the directions turned back), moved 1e6 m east and north, and
  // scaled by 1000 (lengths and cohesion: c / (rho g L) and so every FoS stay).
  const std::array<double, 3> cohesion = {1e3, 3e3, 0};
  struct Variant {
    std::string name;
    Frame f;
  };
  const std::vector<Variant> variants = {{"turned 37 degrees", {37, 1, Vec3::Zero()}},
                                         {"moved 1e6 m", {0, 1, Vec3(1e6, 1e6, 0)}},
                                         {"scaled by 1000", {0, 1000, Vec3::Zero()}}};
  test::TempDir tmp;
  const auto geom0 = geometry_of(tmp, goodman_scene(Frame{}, cohesion), "base");
  for (const bool loads : {false, true}) {
    CAPTURE(loads);
    const auto args = [&](const Frame& f) {
      std::vector<std::string> a;
      if (loads)
        a = {"--seismic",         "0.08",          "--seismic-azimuth",
             num(f.azimuth(200)), "--water-table", num(f.scale * 10 + f.shift.z())};
      return a;
    };
    const auto m0 = stability_of(tmp, geom0, Run{args(Frame{}), ""}, "base-stab.h5");
    int moving = 0;
    for (std::size_t b = 0; b < m0.blocks(); ++b) moving += m0.st.mode[b] >= 3 ? 1 : 0;
    CHECK(moving >= 5);
    const double L = m0.bs.joints.length_scale;
    for (const auto& v : variants) {
      CAPTURE(v.name);
      const auto geom = geometry_of(tmp, goodman_scene(v.f, cohesion), "variant");
      const auto m = stability_of(tmp, geom, Run{args(v.f), ""}, "variant-stab.h5");
      REQUIRE(m.blocks() == m0.blocks());
      // Blocks by their centroids: the variant's is the frame's image of the original's.
      std::vector<std::size_t> match(m0.blocks(), m.blocks());
      for (std::size_t b = 0; b < m0.blocks(); ++b) {
        const Vec3 c = v.f.point(m0.centroid(b));
        for (std::size_t k = 0; k < m.blocks(); ++k)
          if ((m.centroid(k) - c).norm() < 1e-6 * v.f.scale * L) match[b] = k;
      }
      // Shifting by t rounds each plane's offset by up to ulp(|t|) (2.3e-10 m here): a block of
      // inradius r is then another by about ulp(|t|) / r of its size, and so may its FoS and,
      // under water or an earthquake, its direction be (64 ulp of margin). Turning and scaling
      // round by ulp(L): 1e-9 holds for every block.
      const double noise = v.f.shift.norm() > 0
                               ? 64 * (std::nextafter(v.f.shift.norm(), kInf) - v.f.shift.norm())
                               : 0.0;
      int mismatched = 0;
      for (std::size_t b = 0; b < m0.blocks(); ++b) {
        const std::size_t k = match[b];
        const double tol = 1e-9 + noise / m0.bs.blocks[b].inradius;
        INFO("block " << b << " (volume " << m0.volume(b) << ", inradius "
                      << m0.bs.blocks[b].inradius << ") -> " << k);
        REQUIRE(k < m.blocks());
        CHECK(m.bs.blocks[k].flags == m0.bs.blocks[b].flags);
        const bool same =
            m.st.mode[k] == m0.st.mode[b] && m.st.removable[k] == m0.st.removable[b] &&
            m.st.generation[k] == m0.st.generation[b] && m.st.planes[k] == m0.st.planes[b];
        INFO("mode " << m0.st.mode[b] << " -> " << m.st.mode[k] << ", fos " << m0.st.fos[b]
                     << " -> " << m.st.fos[k] << ", direction " << m0.st.direction[b].transpose()
                     << " -> " << v.f.back(m.st.direction[k]).transpose());
        CHECK(same);
        if (m0.st.fos[b] == kInf) {
          CHECK(m.st.fos[k] == kInf);
        } else {
          CHECK_THAT(m.st.fos[k], WithinRel(m0.st.fos[b], tol) || WithinAbs(m0.st.fos[b], 1e-12));
        }
        CHECK((v.f.back(m.st.direction[k]) - m0.st.direction[b]).norm() < tol);
        mismatched += same ? 0 : 1;
      }
      CHECK(mismatched == 0);
    }
  }
}

TEST_CASE("slice-stability writes the same bytes on 1 and 2 threads", "[tools][stability]") {
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, goodman_scene(Frame{}, {1e3, 3e3, 0}));
  std::string bytes[2];
  for (int threads = 1; threads <= 2; ++threads) {
    CAPTURE(threads);
    // The same output name for both: the file records its command line (without --threads).
    const auto out = tmp / "stab.h5";
    test::fs::remove(out);
    const auto r = run_tool("slice-stability",
                            {geom, "-o", out.string(), "--seismic", "0.08", "--seismic-azimuth",
                             "200", "--water-table", "10", "--threads", std::to_string(threads)});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    bytes[threads - 1] = test::read_bytes(out);
  }
  CHECK(!bytes[0].empty());
  CHECK(bytes[0] == bytes[1]);
}

TEST_CASE("a block that can move only once another has gone fails in the next round",
          "[tools][stability]") {
  // stack.toml: the front block on the 30-degree bedding slides out at once; the back block, held
  // by it, slides once it has gone. Both on the bedding (joint 0), FoS tan 20 / tan 30 < 1.
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, data_scene("stack.toml"));
  const PlaneBlock pb;  // the same dip: down_dip
  const double fos = tand(20) / tand(30);
  std::size_t front = 0, back = 0;
  {
    const auto m = stability_of(tmp, geom, Run{{"--free-faces", kPlaneFree}, kPlaneFree});
    const auto body = movable_blocks(m);
    REQUIRE(body.size() == 2);
    front = m.centroid(body[0]).x() > 6 ? body[0] : body[1];
    back = m.centroid(body[0]).x() > 6 ? body[1] : body[0];
    REQUIRE(m.centroid(front).x() > 6);
    REQUIRE(m.centroid(back).x() < 6);
    for (const auto& [b, generation] : {std::pair{front, 0}, std::pair{back, 1}}) {
      CAPTURE(b, generation);
      CHECK(m.st.generation[b] == generation);
      CHECK(m.st.mode[b] == 4);
      check_direction(m.st.direction[b], pb.down_dip);
      CHECK(plane_set(m.st.planes[b]) == std::set<std::int64_t>{0, -1});
      CHECK_THAT(m.st.fos[b], WithinRel(fos, 1e-6));
      CHECK(m.st.fos[b] < 1);
    }
    for (std::size_t b = 0; b < m.blocks(); ++b)
      if (!m.movable(b)) CHECK(m.st.generation[b] == -1);
  }
  {  // --fos-target 0.5: the front block holds (0.63 >= 0.5), so the back one is never freed:
     // removable only upwards, against its weight.
    const auto m = stability_of(
        tmp, geom, Run{{"--free-faces", kPlaneFree, "--fos-target", "0.5"}, kPlaneFree, 0.5},
        "target.h5");
    CHECK(m.st.generation[front] == -1);
    CHECK(m.st.mode[front] == 4);
    CHECK_THAT(m.st.fos[front], WithinRel(fos, 1e-6));
    CHECK(m.st.generation[back] == -1);
    CHECK(m.st.mode[back] == 2);
    CHECK(m.st.removable[back] == 1);
  }
}

TEST_CASE("slice-stability refuses bad input with exit 1, one line and no output",
          "[tools][stability]") {
  test::TempDir tmp;
  const auto geom = geometry_of(tmp, plane_scene(30, 0));
  const auto blocks = (tmp / "scene-blocks.h5").string();
  const auto out = (tmp / "stab.h5").string();
  // A 2-D section (kim-persistent.toml) through slice-vertices, as tmp/geom.h5.
  const auto section = test::run_pipeline(tmp, "kim-persistent.toml", test::Stage::geometry);
  struct Case {
    std::string input;
    std::vector<std::string> args, words;  // the words the line must hold: the file, the option
  };
  for (const auto& c : std::vector<Case>{
           {blocks, {}, {"scene-blocks.h5", "geometry"}},  // from slice-cut: no /geometry
           {section, {}, {"geom.h5", "2-D"}},
           {geom, {"--free-faces", "+q"}, {"+q"}},
           {geom, {"--density", "-1"}, {"density"}},
           {geom, {"--seismic", "-0.1"}, {"seismic", "-0.1"}},
           {geom, {"--seismic-azimuth", "nan"}, {"azimuth"}},
           {geom, {"--water-table", "nan"}, {"water"}}}) {
    std::vector<std::string> args = {c.input, "-o", out};
    args.insert(args.end(), c.args.begin(), c.args.end());
    CAPTURE(args);
    const auto r = run_tool("slice-stability", args);
    test::check_refused(r, "slice-stability", c.words);
    CHECK_FALSE(test::fs::exists(out));
    CHECK_FALSE(test::fs::exists(out + ".partial"));
  }
  // An existing output is left as it was.
  test::write_text(out, "an older file");
  const auto r = run_tool("slice-stability", {geom, "-o", out, "--density", "-1"});
  test::check_refused(r, "slice-stability", {"density"});
  CHECK(test::read_bytes(out) == "an older file");
}
