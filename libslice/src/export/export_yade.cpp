#include "slice/export_yade.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "../io/h5/h5.hpp"
#include "slice/contacts.hpp"
#include "slice/error.hpp"
#include "slice/output.hpp"
#include "slice/utf8.hpp"
#include "slice/version.hpp"

namespace slice {
namespace {

// Shortest text that reads back as the same double in Python ("0.1", "1e+300", "-0").
std::string num(double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

std::string vec(const Vec3& v) {
  // Appended piecewise: GCC 12 warns (-Wrestrict, a false positive) on "(" + a + ...
  std::string s = "(";
  s.append(num(v.x())).append(", ").append(num(v.y())).append(", ").append(num(v.z()));
  return s.append(")");
}

// A Python string literal of any bytes (a file name, a scene name from a damaged file): quote
// and backslash escaped; control characters as \xNN, since Python ends a source line at "\r"
// as at "\n" and refuses NUL; bytes that are no UTF-8 (Python reads the script as UTF-8) as
// \udcNN, Python's surrogateescape, so that os.fsencode() gives a file name's bytes back.
std::string py_str(const std::string& s) {
  std::string q = "'";
  for (std::size_t i = 0; i < s.size();) {
    const auto u = static_cast<unsigned char>(s[i]);
    const std::size_t len = decode_utf8(s, i).second;
    if (len > 1) {
      q.append(s, i, len);
      i += len;
      continue;
    }
    ++i;
    if (len == 1 && u >= 0x20 && u != 0x7f) {
      if (u == '\\' || u == '\'') q += '\\';
      q += char(u);
      continue;
    }
    std::array<char, 8> buf{};
    std::snprintf(buf.data(), buf.size(), len == 1 ? "\\x%02x" : "\\udc%02x", unsigned(u));
    q += buf.data();
  }
  return q + "'";
}

// Everything the script needs of one block.
struct BodyData {
  std::size_t block = 0;
  bool fixed = false;
  double friction = 0;
  std::int64_t cluster = -1;
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
};

const char* kHeader = R"(# Rules (rockslice docs/dem-exports.md, "YADE"):
#  - one body per block that is not removed;
#  - Polyhedra with LAW 'mohr-coulomb': each contact across a joint (CONTACTS) has its joint's
#    friction, cohesion and tension ([rock]'s for a rock bridge) and its own shear force; a
#    contact made later as blocks move has the smaller of its two blocks' angles (below);
#  - LAW 'volumetric' and PotentialBlock: one material per block; its friction angle is the
#    smallest friction angle of the joints of its faces, over rock and boundary joints (domain
#    faces and construction joints are no contacts); a block with no such face gets
#    DEFAULT_FRICTION_DEG;
#  - boundary blocks are fixed; the blocks of a cluster (joined across construction joints) are
#    one clump, fixed if it holds a boundary block;
#  - gravity along -z; STEPS > 0 runs that many steps of the settling run at the end.
)";

// The script's program after BLOCKS, for both shapes: bodies, clumps, engines and the run. The
// text is python/rockslice/yade_program.py, embedded by the build (libslice/CMakeLists.txt),
// which the Python module's rockslice.yade.build() runs in YADE on a model in memory: one set
// of rules.
constexpr const char* kYadeProgram =
#include "yade_program.inc"
    ;

}  // namespace

const char* to_string(YadeLaw law) {
  return law == YadeLaw::volumetric ? "volumetric" : "mohr-coulomb";
}

YadeLaw parse_yade_law(const std::string& name) {
  for (const YadeLaw law : {YadeLaw::mohr_coulomb, YadeLaw::volumetric})
    if (name == to_string(law)) return law;
  throw Error("--yade-law", "is '" + name + "'", "use mohr-coulomb or volumetric");
}

void YadeOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(std::isfinite(v) && v > 0))
      throw Error(std::string("--") + name, "is " + num(v), "give a positive number");
  };
  if (steps < 0) throw Error("--yade-steps", "is " + std::to_string(steps), "give 0 or more");
  // A number past long's range reaches here clamped to its largest value (CLI11 reads 1e20 so):
  // refuse what no run would ask for, 1e15 steps being 30 years at a million steps a second.
  if (steps > kYadeMaxSteps)
    throw Error("--yade-steps",
                "is " + std::to_string(steps) + ", more than " + std::to_string(kYadeMaxSteps) +
                    " (or past the integers' range)",
                "give a whole number of steps from 0 to 1000000000000000");
  positive(density, "yade-density");
  positive(young, "yade-young");
  positive(poisson, "yade-poisson");
  positive(timestep_factor, "yade-timestep-factor");
  if (!(gravity >= 0 && std::isfinite(gravity)))
    throw Error("--yade-gravity", "is " + num(gravity), "give 0 or more");
  if (!(damping >= 0 && damping < 1))
    throw Error("--yade-damping", "is " + num(damping), "give a value in [0, 1)");
  if (!(default_friction_deg >= 0 && default_friction_deg < 90))
    throw Error("--yade-friction", "is " + num(default_friction_deg), "give an angle in [0, 90)");
  if (!(pb_rounding > 0 && pb_rounding < 0.5))
    throw Error("--pb-rounding", "is " + num(pb_rounding), "give a fraction in (0, 0.5)");
}

double block_friction_deg(const BlockSystem& bs, std::size_t b, std::size_t first_face,
                          double default_friction_deg) {
  // With [rock] and /geometry, a face's angle is its joint's on the part of it inside the
  // joint's polygon and intact rock's on the rest (a rock bridge): weighted by the fraction.
  const bool bridges = bs.joints.rock.given && bs.geometry;
  double phi = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < bs.blocks[b].faces.size(); ++k) {
    const Face& f = bs.blocks[b].faces[k];
    if (f.joint < 0) continue;
    const Joint& j = bs.joints.joints[std::size_t(f.joint)];
    if (j.kind == JointKind::construction) continue;
    const double part = bridges ? bs.geometry->face_joint_fraction[first_face + k] : 1.0;
    phi =
        std::min(phi, part * j.friction_angle_deg + (1 - part) * bs.joints.rock.friction_angle_deg);
  }
  return std::isfinite(phi) ? phi : default_friction_deg;
}

std::vector<YadeContact> yade_contacts(const BlockSystem& bs) {
  std::vector<YadeContact> rows;
  if (bs.joints.dimension == 2) return rows;  // a section's contacts are edges (not yet here)
  const RockSpec& rock = bs.joints.rock;
  for (const BlockContact& c : find_contacts(bs)) {
    const Joint& j = bs.joints.joints[std::size_t(c.joint)];
    const bool bridge = is_rock_bridge(bs, c);
    YadeContact r{c.a,
                  c.b,
                  bridge ? rock.friction_angle_deg : j.friction_angle_deg,
                  bridge ? rock.cohesion : j.cohesion,
                  bridge ? rock.tension : j.tension,
                  c.area,
                  c.centroid,
                  c.normal,
                  bridge};
    // find_contacts sorts by (a, b): a pair on two joints keeps its larger contact.
    if (!rows.empty() && rows.back().a == r.a && rows.back().b == r.b) {
      if (r.area > rows.back().area) rows.back() = r;
      continue;
    }
    rows.push_back(r);
  }
  return rows;
}

double block_friction_deg(const BlockSystem& bs, std::size_t b, double default_friction_deg) {
  std::size_t first_face = 0;
  for (std::size_t i = 0; i < b; ++i) first_face += bs.blocks[i].faces.size();
  return block_friction_deg(bs, b, first_face, default_friction_deg);
}

YadeStats write_yade_script(const std::filesystem::path& out, const BlockSystem& bs,
                            const YadeOptions& opt) {
  opt.validate();
  const Geometry& g = geometry_of(bs, out.string());
  const bool pb = opt.shape == YadeShape::potential_blocks;
  // A section (docs/2d.md): each polygon is a prism of unit thickness, y in [-0.5, 0.5], that
  // moves in (x, z) only: blockedDOFs 'yXZ' (YADE's State.blockedDOFs: lower case blocks a
  // translation, upper case a rotation) on every body that is not fixed.
  const bool section = bs.joints.dimension == 2;
  if (section && pb)
    throw Error(opt.source.empty() ? out.string() : opt.source,
                "is a 2-D section (dimension 2): PotentialBlock models are 3-D only",
                "export it with --format yade (Polyhedra prisms) or --format vtu");

  std::vector<BodyData> bodies;
  YadeStats st;
  std::size_t first_face = 0;  // block b's first row in the per-face arrays
  for (std::size_t b = 0; b < bs.blocks.size(); first_face += bs.blocks[b++].faces.size()) {
    const Block& blk = bs.blocks[b];
    if (blk.flags & kRemoved) {
      ++st.removed;
      continue;
    }
    bodies.push_back({b, is_fixed(blk),
                      block_friction_deg(bs, b, first_face, opt.default_friction_deg), blk.cluster,
                      g.volume[b], g.centroid[b]});
    st.fixed += bodies.back().fixed ? 1 : 0;
  }
  st.bodies = bodies.size();
  st.dem = dem_bodies(bs);
  st.clumps = st.dem.clumps;  // clusters of two or more kept blocks
  // The Polyhedra script's contacts (its law takes each contact's strength from them).
  std::vector<YadeContact> contacts;
  if (!pb) contacts = yade_contacts(bs);
  st.contacts = contacts.size();
  for (const YadeContact& c : contacts) st.bridges += c.bridge ? 1 : 0;
  // Both scripts set O.dt by the same rule.
  st.timestep = yade_timestep(st.dem, opt.density, opt.young, opt.timestep_factor);
  // Options each finite but together past the doubles (a young of 1e-308) give O.dt = inf or 0.
  if (st.dem.moving_block >= 0 && !(std::isfinite(st.timestep) && st.timestep > 0))
    throw Error("--yade-young " + num(opt.young),
                "with --yade-density " + num(opt.density) + " and --yade-timestep-factor " +
                    num(opt.timestep_factor) + " the time step O.dt would be " + num(st.timestep) +
                    " s",
                "give a stiffness, density and factor of the model's order (defaults 1e9, 2650, "
                "0.2)");

  PartialFile part(out);
  {
    errno = 0;  // what a failed write leaves here is its reason (system_reason)
    std::ofstream s(part.path(), std::ios::binary);
    if (!s)
      throw Error(out.string(),
                  "cannot create " + part.path().filename().string() + system_reason(),
                  "check that the directory is writable");
    settle_truncation(part.path());
    s << "# rockslice " << version() << ": a YADE model of " << st.bodies << " blocks ("
      << (pb ? "PotentialBlock" : "Polyhedra") << " bodies), " << st.fixed << " fixed, "
      << st.clumps << " clumps.\n"
      << "# Made by slice-export --format " << (pb ? "yade-potential-blocks" : "yade")
      << " from the geometry of scene " << py_str(bs.joints.name) << ".\n"
      << "# Run headless: yade -n -x model.py     With the GUI: yade model.py\n"
      << "# Frame x East, y North, z Up; lengths in the scene's unit (m), mass in kg, time in s.\n"
      << kHeader;
    if (section)
      s << "# A 2-D section in (x, z): each block is a prism of unit thickness (y from -0.5 to "
           "0.5)\n"
        << "# that moves in the section only (blockedDOFs 'yXZ').\n";
    if (pb)
      s << "# PotentialBlock bodies need a YADE built with ENABLE_POTENTIAL_BLOCKS=ON (Debian's\n"
        << "# yade has none): planes a x + b y + c z = d about the block's centroid, rounded by\n"
        << "# r = PB_ROUNDING x the inscribed radius (d is given unrounded and reduced by r "
           "below),\n"
        << "# R = the bounding radius about the centroid.\n";
    s << "import math\nimport time\n"
      << "import sys\n"
      << "from yade import config, log\n";
    s << "from yade import " << (pb ? "potential_utils" : "polyhedra_utils") << "\n\n";
    if (pb)
      s << "if 'POTENTIAL_BLOCKS' not in config.features:\n"
        << "    sys.exit('rockslice model: this YADE was built without potential blocks; rebuild "
           "it with "
           "ENABLE_POTENTIAL_BLOCKS=ON, or export with --format yade (Polyhedra)')\n\n";
    s << "SOURCE = " << py_str(opt.source) << "\n"
      << "STEPS = " << opt.steps << "\n"
      << "DENSITY = " << num(opt.density) << "  # kg/m3\n"
      << "YOUNG = " << num(opt.young)
      << (pb ? "  # normal contact stiffness per unit area\n"
             : "  # PolyhedraMat.young: volumetric contact stiffness [N/m3]\n")
      << "POISSON = " << num(opt.poisson) << "  # shear / normal contact stiffness\n"
      << "DEFAULT_FRICTION_DEG = " << num(opt.default_friction_deg) << "\n"
      << "DAMPING = " << num(opt.damping) << "\n"
      << "GRAVITY = " << num(opt.gravity) << "  # m/s2, along -z\n"
      << "TIMESTEP_FACTOR = " << num(opt.timestep_factor) << "\n";
    s << (pb ? "PB_ROUNDING = " + num(opt.pb_rounding) + "\n"
             : "INITIAL_GAP = " + num(kYadeInitialGap) + "  # relative: see SHRINK below\n")
      << "SHAPE = '" << (pb ? "potential_blocks" : "polyhedra") << "'\n"
      << (pb ? std::string()
             : std::string("LAW = '") + to_string(opt.law) +
                   "'  # the contact law (docs/dem-exports.md): 'mohr-coulomb' or 'volumetric'\n")
      << "SECTION = " << (section ? "True" : "False")
      << "  # a 2-D section: bodies move in (x, z) only\n"
      << "ENGINES = True  # set O.engines and O.dt\n";
    s << "\n";

    if (!pb) {
      s << "# (block id in blocks.h5, fixed, friction angle [deg], cluster (-1: none), volume "
           "(/geometry),\n#  centroid (/geometry), vertices (global))\n"
        << "BLOCKS = [\n";
      for (const BodyData& d : bodies) {
        // A section's prism has its polygon's centroid: y = 0 is its middle.
        s << "(" << d.block << ", " << (d.fixed ? 1 : 0) << ", " << num(d.friction) << ", "
          << d.cluster << ", " << num(d.volume) << ", " << vec(d.centroid) << ", (";
        // A section's polygon (y = 0) becomes its prism: the polygon at y = -0.5, then at 0.5.
        for (const double y : section ? std::vector<double>{-0.5, 0.5} : std::vector<double>{0})
          for (auto v = g.vertex_offset[d.block]; v < g.vertex_offset[d.block + 1]; ++v)
            s << vec(g.vertices[std::size_t(v)] + Vec3(0, y, 0)) << ", ";
        s << ")),\n";
      }
      s << "]\n\n";
      s << "# (block a, block b, friction angle [deg], cohesion [Pa], tension [Pa], area, "
           "centroid,\n#  unit normal from a to b): the contacts across joints, each with its "
           "joint's strength\n#  ([rock]'s for a rock bridge)\n"
        << "CONTACTS = [\n";
      for (const YadeContact& c : contacts)
        s << "(" << c.a << ", " << c.b << ", " << num(c.friction_deg) << ", " << num(c.cohesion)
          << ", " << num(c.tension) << ", " << num(c.area) << ", " << vec(c.centroid) << ", "
          << vec(c.normal) << "),\n";
      s << "]\n\n";
    } else {
      s << "# (block id in blocks.h5, fixed, friction angle [deg], cluster (-1: none), volume "
           "(/geometry),\n#  inscribed radius, bounding radius R about the centroid, centroid "
           "(global),\n#  planes (a, b, c, d): a x + b y + c z <= d about the centroid, "
           "unrounded)\n"
        << "BLOCKS = [\n";
      for (const BodyData& d : bodies) {
        const Block& blk = bs.blocks[d.block];
        double r_bound = 0;
        for (auto v = g.vertex_offset[d.block]; v < g.vertex_offset[d.block + 1]; ++v)
          r_bound = std::max(r_bound, (g.vertices[std::size_t(v)] - d.centroid).norm());
        s << "(" << d.block << ", " << (d.fixed ? 1 : 0) << ", " << num(d.friction) << ", "
          << d.cluster << ", " << num(d.volume) << ", " << num(blk.inradius) << ", " << num(r_bound)
          << ", " << vec(d.centroid) << ", (";
        for (const Face& f : blk.faces) {
          // n . (x - o) <= d  <=>  n . (x - c) <= d - n . (c - o)
          const double dc = f.d - f.normal.dot(d.centroid - blk.origin);
          s << "(" << num(f.normal.x()) << ", " << num(f.normal.y()) << ", " << num(f.normal.z())
            << ", " << num(dc) << "), ";
        }
        s << ")),\n";
      }
      s << "]\n\n";
    }

    s << kYadeProgram;
    s.flush();
    if (!s) {
      const int e = errno;
      throw Error(out.string(), "cannot write " + part.path().filename().string() + system_reason(),
                  write_error_fix(e));
    }
  }
  part.commit();
  return st;
}

}  // namespace slice
