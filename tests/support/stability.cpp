// Definitions of tests/support/stability.hpp.
#include "support/stability.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/pipeline.hpp"

namespace test::stability {

using slice::Vec3;

namespace {

/// A point as a TOML array, 17 significant digits.
std::string point(const Vec3& p) {
  std::ostringstream s;
  s << std::setprecision(17) << '[' << p.x() << ", " << p.y() << ", " << p.z() << ']';
  return s.str();
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
  const auto& group = column(m, "stability/group", "int64", blocks);
  for (std::size_t b = 0; b < blocks; ++b) {
    s.removable.push_back(static_cast<int>(removable.v[b]));
    s.mode.push_back(static_cast<int>(mode.v[b]));
    s.fos.push_back(fos.v[b]);
    s.direction.emplace_back(direction.v[3 * b], direction.v[3 * b + 1], direction.v[3 * b + 2]);
    s.generation.push_back(static_cast<int>(generation.v[b]));
    s.planes.push_back({static_cast<std::int64_t>(planes.v[2 * b]),
                        static_cast<std::int64_t>(planes.v[2 * b + 1])});
    s.group.push_back(static_cast<std::int64_t>(group.v[b]));
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
    CHECK(c.fraction >= 0);  // 0: wholly off its joint's polygon (a rock bridge)
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
    // Exposed at the start: a mode of its own; never exposed: nothing fails at once, but as a
    // member of a group.
    if (m.movable(b) && exposed[b]) CHECK(st.mode[b] >= 1);
    if (!exposed[b] && st.group[b] < 0) CHECK(st.generation[b] != 0);
    // A group: blocks that fail together, named by its smallest block.
    CHECK(st.group[b] >= -1);
    CHECK(st.group[b] < std::int64_t(nb));
    if (st.group[b] >= 0) {
      CHECK(st.generation[b] >= 0);
      CHECK(st.group[b] <= std::int64_t(b));
      CHECK(st.group[std::size_t(st.group[b])] == st.group[b]);
    }
  }
  // A group's members carry the group's values; a group fails at once only if one of its
  // members was exposed.
  std::map<std::int64_t, bool> group_exposed;
  for (std::size_t b = 0; b < nb; ++b) {
    const auto g = st.group[b];
    if (g < 0 || g >= std::int64_t(nb)) continue;
    group_exposed[g] = group_exposed[g] || exposed[b];
    const auto f = std::size_t(g);
    INFO("group " << g << ": block " << b);
    CHECK(st.mode[b] == st.mode[f]);
    CHECK(st.generation[b] == st.generation[f]);
    CHECK(st.fos[b] == st.fos[f]);
    CHECK((st.direction[b].array() == st.direction[f].array()).all());
    CHECK(st.planes[b] == st.planes[f]);
  }
  for (const auto& [g, any] : group_exposed)
    if (st.generation[std::size_t(g)] == 0) CHECK(any);
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

}  // namespace

double rad(double deg) { return deg * kPi / 180; }
double tand(double deg) { return std::tan(rad(deg)); }

Vec3 upward_normal(double dip, double dd) {
  return {std::sin(rad(dip)) * std::sin(rad(dd)), std::sin(rad(dip)) * std::cos(rad(dd)),
          std::cos(rad(dip))};
}

std::string num(double x) {
  std::ostringstream s;
  s << std::setprecision(17) << x;
  return s.str();
}

std::string geometry_of(const TempDir& tmp, const std::string& scene, const std::string& stem) {
  return geometry_of_text(tmp, scene, stem + "-");
}

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

Model stability_of(const test::TempDir& tmp, const std::string& geom, const Run& run,
                   const std::string& out_name) {
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

std::vector<std::size_t> movable_blocks(const Model& m) {
  std::vector<std::size_t> out;
  for (std::size_t b = 0; b < m.blocks(); ++b)
    if (m.movable(b)) out.push_back(b);
  return out;
}

double area_on(const Model& m, std::size_t b, std::int64_t j) {
  double a = 0;
  for (const auto& t : touches(m, b))
    if (t.joint == j) a += t.area;
  return a;
}

std::set<std::int64_t> plane_set(const std::array<std::int64_t, 2>& p) { return {p[0], p[1]}; }

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

std::string plane_scene(double phi, double cohesion, bool cluster) {
  std::ostringstream s;
  s << "[scene]\nname = \"plane\"\n[domain]\nbox = { min = [0, 0, 0], max = [12, 4, 8] }\n"
    << "[options]\nfixed_faces = [\"-z\"]\n"
    << "[[joints]]\ndip = 30\ndip_direction = 90\npoint = [6, 2, 5]\nfriction_angle = " << num(phi)
    << "\ncohesion = " << num(cohesion) << "\n";
  if (cluster)
    s << "[[joints]]\ndip = 90\ndip_direction = 90\npoint = [9, 2, 4]\nkind = \"construction\"\n";
  return s.str();
}

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

std::string hanging_scene(double tension) {
  std::ostringstream s;
  s << "[scene]\nname = \"hanging\"\n[domain]\nbox = { min = [0, 0, 0], max = [4, 4, 4] }\n"
    << "[options]\nfixed_faces = [\"+z\"]\n"
    << "[[joints]]\ndip = 0\ndip_direction = 0\npoint = [2, 2, 2]\ntension = " << num(tension)
    << "\n";
  return s.str();
}

Vec3 Frame::vector(const Vec3& v) const {
  const double c = std::cos(rad(turn_deg)), s = std::sin(rad(turn_deg));
  return {c * v.x() + s * v.y(), -s * v.x() + c * v.y(), v.z()};
}
Vec3 Frame::back(const Vec3& v) const {
  const double c = std::cos(rad(turn_deg)), s = std::sin(rad(turn_deg));
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}
Vec3 Frame::point(const Vec3& p) const { return scale * vector(p) + shift; }
double Frame::azimuth(double az) const { return std::fmod(az + turn_deg + 360, 360.0); }

std::string goodman_scene(const Frame& f, const std::array<double, 3>& cohesion) {
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

void check_direction(const Vec3& got, const Vec3& want, double tol) {
  INFO("direction " << got.transpose() << ", expected " << want.transpose());
  CHECK((got - want).norm() < tol);
}

}  // namespace test::stability
