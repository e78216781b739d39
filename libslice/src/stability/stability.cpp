// The stability stage over a whole model (docs/stability.md): contacts, bodies, loads, and
// rounds of successive failure. One body's kinematics: kinematics.cpp.
#include "slice/stability.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <tuple>

#include "slice/contacts.hpp"
#include "slice/error.hpp"
#include "slice/h5io.hpp"
#include "slice/orientation.hpp"
#include "slice/polytope.hpp"

namespace slice {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kAngleTol = 1e-9;    // radians: a direction this close to a plane runs along it
constexpr std::int64_t kDomain = -1;  // an entry against the domain's (fixed) boundary
constexpr std::int64_t kOpen = -2;    // an entry that is free from the start

/// What a contact row resists with and the water that pushes on it.
struct RowStrength {
  double friction = 0, cohesion = 0, tension = 0;  // sums of A tan(phi), c A, t A
  bool locked = false;
  double water = 0;  // N, the hydrostatic force on the contact, pushing its sides apart
};

/// One contact of a body with something outside it.
struct Entry {
  std::size_t row;     // of the contacts
  std::int64_t other;  // the body beyond, kDomain or kOpen
  bool flip;           // the body is side b: its outward normal is -normal
};

/// A body: a block, or a cluster of two or more kept blocks (docs/design.md, "Clusters and
/// slivers"); what it touches as CSR entries.
struct Bodies {
  std::vector<std::int64_t> of_block;         // -1: removed
  std::vector<std::size_t> member_offset{0};  // CSR over members
  std::vector<std::size_t> members;
  std::vector<double> volume;
  std::vector<char> fixed;
  std::vector<std::size_t> entry_offset;
  std::vector<Entry> entries;
  std::size_t size() const { return volume.size(); }
};

Bodies make_bodies(const BlockSystem& bs, const Geometry& g) {
  std::map<std::int64_t, std::size_t> kept_in_cluster;
  for (const Block& b : bs.blocks)
    if (!(b.flags & kRemoved) && b.cluster >= 0) ++kept_in_cluster[b.cluster];
  Bodies out;
  out.of_block.assign(bs.blocks.size(), -1);
  std::map<std::int64_t, std::int64_t> body_of_cluster;
  std::vector<std::vector<std::size_t>> members;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    if (blk.flags & kRemoved) continue;
    std::int64_t id;
    if (blk.cluster >= 0 && kept_in_cluster[blk.cluster] >= 2) {
      auto [it, added] = body_of_cluster.try_emplace(blk.cluster, std::int64_t(members.size()));
      if (added) members.emplace_back();
      id = it->second;
    } else {
      id = std::int64_t(members.size());
      members.emplace_back();
    }
    members[std::size_t(id)].push_back(b);
    out.of_block[b] = id;
  }
  for (const auto& m : members) {
    double v = 0;
    bool fixed = false;
    for (const std::size_t b : m) {
      v += g.volume[b];
      fixed = fixed || is_fixed(bs.blocks[b]);
      out.members.push_back(b);
    }
    out.member_offset.push_back(out.members.size());
    out.volume.push_back(v);
    out.fixed.push_back(fixed);
  }
  return out;
}

/// The force of hydrostatic water below z_w on a polygon: rho_w g integral of (z_w - z) over its
/// part below z_w (a linear function: its area times the value at its centroid).
double water_force(const std::vector<Vec3>& polygon, const StabilityOptions& opt) {
  if (!opt.water_table) return 0;
  const auto wet = clip_polygon(polygon, Plane{Vec3::UnitZ(), *opt.water_table});
  const auto [area, centroid] = polygon_area_centroid(wet);
  return opt.water_density * opt.gravity * area * std::max(0.0, *opt.water_table - centroid.z());
}

/// The contacts of the kept blocks: with kept and removed blocks across every joint, and the
/// faces on the domain's boundary; sorted by (a, b, joint, faces), b = -1 first.
void find_rows(const BlockSystem& bs, const Geometry& g, const StabilityOptions& opt,
               ContactRows& rows, std::vector<double>& water) {
  struct Found {
    BlockContact c;
    std::uint8_t free;
    double water;
  };
  std::vector<Found> found;
  const ContactScope scope{true, true, opt.water_table.has_value()};
  for_each_contact(bs, scope, [&](const BlockContact& c, std::span<const Vec3> polygon) {
    const bool removed = bs.blocks[c.b].flags & kRemoved;
    const double u =
        opt.water_table ? water_force(std::vector<Vec3>(polygon.begin(), polygon.end()), opt) : 0;
    found.push_back({c, std::uint8_t(removed ? 1 : 0), u});
  });
  // The domain's faces: on a face of its bounding box named free, a free surface.
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  for (const Vec3& x : g.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double tol = bs.joints.options.tolerance * bs.joints.length_scale;
  std::vector<Vec3> polygon;
  std::size_t row = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    for (const Face& f : blk.faces) {
      const std::size_t r = row++;
      if ((blk.flags & kRemoved) || f.joint >= 0) continue;
      polygon.clear();
      const auto base = g.vertex_offset[b];
      for (auto v = g.face_vertex_offset[r]; v < g.face_vertex_offset[r + 1]; ++v)
        polygon.push_back(g.vertices[std::size_t(base + g.face_vertices[std::size_t(v)])]);
      bool free = false;
      for (int k = 0; k < 6; ++k) {
        if (!(opt.free_faces & (1u << k))) continue;
        const int axis = k / 2;
        const double sign = k % 2 ? 1 : -1, bound = k % 2 ? hi[axis] : lo[axis];
        bool on = sign * f.normal[axis] >= 1 - kAngleTol;
        for (const Vec3& x : polygon) on = on && std::abs(x[axis] - bound) <= tol;
        free = free || on;
      }
      const auto [area, centroid] = polygon_area_centroid(polygon);
      BlockContact c;
      c.a = b;
      c.b = std::size_t(-1);
      c.face_a = r;
      c.face_b = std::size_t(-1);
      c.joint = -1;
      c.area = g.face_area[r];
      c.centroid = centroid;
      c.normal = f.normal;
      c.open = c.area;
      found.push_back({c, std::uint8_t(free ? 1 : 0), water_force(polygon, opt)});
    }
  }
  const auto signed_row = [](std::size_t v) {
    return v == std::size_t(-1) ? std::int64_t(-1) : std::int64_t(v);
  };
  // Sorted by (a, b, joint, faces), b = -1 first: compact keys, then the rows in their order.
  struct Key {
    std::size_t a;
    std::int64_t b, joint;
    std::size_t face_a, face_b, index;
    bool operator<(const Key& o) const {
      return std::tie(a, b, joint, face_a, face_b) <
             std::tie(o.a, o.b, o.joint, o.face_a, o.face_b);
    }
  };
  std::vector<Key> keys(found.size());
  for (std::size_t i = 0; i < found.size(); ++i) {
    const BlockContact& c = found[i].c;
    keys[i] = {c.a, signed_row(c.b), c.joint, c.face_a, c.face_b, i};
  }
  std::sort(keys.begin(), keys.end());
  const std::size_t n = found.size();
  rows.pairs.reserve(n), rows.faces.reserve(n), rows.area.reserve(n), rows.centroid.reserve(n);
  rows.normal.reserve(n), rows.joint.reserve(n), rows.fraction.reserve(n), rows.free.reserve(n);
  water.reserve(n);
  for (const Key& k : keys) {
    const Found& x = found[k.index];
    const BlockContact& c = x.c;
    rows.pairs.push_back({std::int64_t(c.a), signed_row(c.b)});
    rows.faces.push_back({std::int64_t(c.face_a), signed_row(c.face_b)});
    rows.area.push_back(c.area);
    rows.centroid.push_back(c.centroid);
    rows.normal.push_back(c.normal);
    rows.joint.push_back(c.joint);
    rows.fraction.push_back(c.area > 0 ? std::min(c.open, c.area) / c.area : 1);
    rows.free.push_back(x.free);
    water.push_back(x.water);
  }
}

/// Each row's strength (docs/stability.md, "Strength"): its joint's over the part on the joint's
/// polygon, [rock]'s over the rest (a rock bridge) when the scene has a [rock] table; a
/// construction joint or the domain's boundary is intact rock: [rock]'s, or without one, it
/// never slips.
RowStrength strength_of(const JointSystem& js, const ContactRows& rows, std::size_t r) {
  RowStrength s;
  const double area = rows.area[r];
  const RockSpec& rock = js.rock;
  const auto add = [&](double a, double phi_deg, double c, double t) {
    s.friction += a * std::tan(phi_deg * std::numbers::pi / 180);
    s.cohesion += a * c;
    s.tension += a * t;
  };
  const std::int64_t j = rows.joint[r];
  if (j < 0 || js.joints[std::size_t(j)].kind == JointKind::construction) {
    if (rock.given)
      add(area, rock.friction_angle_deg, rock.cohesion, rock.tension);
    else
      s.locked = true;
    return s;
  }
  const Joint& joint = js.joints[std::size_t(j)];
  const double open = rock.given ? rows.fraction[r] * area : area;
  add(open, joint.friction_angle_deg, joint.cohesion, joint.tension);
  if (area > open) add(area - open, rock.friction_angle_deg, rock.cohesion, rock.tension);
  return s;
}

/// The entries of every body: each row seen from each kept side that is not inside one body.
void make_entries(const BlockSystem& bs, const ContactRows& rows, Bodies& bodies) {
  std::vector<std::vector<Entry>> per(bodies.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto [a, b] = rows.pairs[r];
    const std::int64_t A = bodies.of_block[std::size_t(a)];
    if (b < 0) {
      per[std::size_t(A)].push_back({r, rows.free[r] ? kOpen : kDomain, false});
      continue;
    }
    const std::int64_t B = bodies.of_block[std::size_t(b)];
    if (B < 0 || (bs.blocks[std::size_t(b)].flags & kRemoved)) {
      per[std::size_t(A)].push_back({r, kOpen, false});
      continue;
    }
    if (A == B) continue;  // inside a cluster
    per[std::size_t(A)].push_back({r, B, false});
    per[std::size_t(B)].push_back({r, A, true});
  }
  bodies.entry_offset.assign(1, 0);
  for (const auto& e : per) {
    bodies.entries.insert(bodies.entries.end(), e.begin(), e.end());
    bodies.entry_offset.push_back(bodies.entries.size());
  }
}

/// One body's analysis in the current state (failed: the round each body failed in, -1 none).
struct BodyAnswer {
  bool exposed = false;
  BodyStability s;
  std::array<std::int64_t, 2> joints{-1, -1};
};

/// The bodies that move as one rigid body: one body, or a group (sorted, small).
using Members = std::span<const std::size_t>;

/// Which neighbours an analysis keeps: all of them in place, or only those that cannot move (fixed
/// bodies and the domain), to see which of the others are in the way.
enum class Neighbours { in_place, fixed_only };

bool contains(Members m, std::size_t k) { return std::find(m.begin(), m.end(), k) != m.end(); }

/// The outward normal of a body's side of an entry.
Vec3 outward(const ContactRows& rows, const Entry& en) {
  return en.flip ? Vec3(-rows.normal[en.row]) : rows.normal[en.row];
}

BodyAnswer analyse(const Bodies& bodies, Members group, const ContactRows& rows,
                   const std::vector<RowStrength>& strength, const std::vector<int>& failed,
                   const StabilityOptions& opt, Neighbours which = Neighbours::in_place) {
  BodyAnswer out;
  double volume = 0;
  for (const std::size_t k : group) volume += bodies.volume[k];
  const double weight = opt.density * opt.gravity * volume;
  const double az = opt.seismic_azimuth_deg;
  Vec3 load(opt.seismic * weight * sind(az), opt.seismic * weight * cosd(az), -weight);
  std::vector<ContactPlane> planes;
  std::vector<double> largest;  // area of each plane's largest contact
  for (const std::size_t k : group)
    for (std::size_t e = bodies.entry_offset[k]; e < bodies.entry_offset[k + 1]; ++e) {
      const Entry& en = bodies.entries[e];
      const Vec3 n = outward(rows, en);
      const double area = rows.area[en.row];
      if (en.other == kOpen) {
        out.exposed = true;
        load -= opt.support_pressure * area * n;
        continue;
      }
      if (en.other >= 0) {
        const auto o = std::size_t(en.other);
        if (failed[o] >= 0) {
          out.exposed = true;
          continue;
        }
        if (contains(group, o)) continue;  // inside the group
        if (which == Neighbours::fixed_only && !bodies.fixed[o]) continue;
      }
      const RowStrength& s = strength[en.row];
      load -= s.water * n;
      auto it = std::find_if(planes.begin(), planes.end(), [&](const ContactPlane& p) {
        return (p.normal - n).cwiseAbs().maxCoeff() <= kAngleTol;
      });
      if (it == planes.end()) {
        planes.push_back({n, 0, 0, 0, 0, false, -1});
        largest.push_back(0);
        it = planes.end() - 1;
      }
      it->area += area;
      it->friction += s.friction;
      it->cohesion += s.cohesion;
      it->tension += s.tension;
      it->locked = it->locked || s.locked;
      double& big = largest[std::size_t(it - planes.begin())];
      if (area > big) big = area, it->joint = rows.joint[en.row];
    }
  if (!out.exposed) return out;
  out.s = analyse_body(planes, load, kAngleTol);
  for (int i = 0; i < 2; ++i)
    if (out.s.planes[std::size_t(i)] >= 0)
      out.joints[std::size_t(i)] = planes[std::size_t(out.s.planes[std::size_t(i)])].joint;
  return out;
}

bool fails(const BodyAnswer& a, double target) {
  const auto m = a.s.mode;
  return a.exposed &&
         (m == FailureMode::falls || m == FailureMode::slides_one ||
          m == FailureMode::slides_two) &&
         a.s.fos < target;
}

/// Sorts v and drops its repeats.
void sorted_unique(std::vector<std::size_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// A group of bodies that fails as one, and its answer.
struct GroupAnswer {
  std::vector<std::size_t> members;  // sorted
  BodyAnswer answer;
};

/// Bodies that fail together (docs/stability.md, "Groups"): from a body that holds, the movable
/// neighbours in the way of the motion it would have without them join it, and the group is
/// analysed as one rigid body (its joints inside do not slip); again from the group, up to
/// opt.max_group bodies. Nothing when the body, freed of its movable neighbours, holds anyway.
std::optional<GroupAnswer> find_group(const Bodies& bodies, std::size_t seed,
                                      const ContactRows& rows,
                                      const std::vector<RowStrength>& strength,
                                      const std::vector<int>& failed, const StabilityOptions& opt) {
  std::vector<std::size_t> group{seed};
  while (true) {
    const BodyAnswer freed =
        analyse(bodies, group, rows, strength, failed, opt, Neighbours::fixed_only);
    if (!fails(freed, opt.fos_target)) return std::nullopt;
    std::vector<std::size_t> in_way;
    for (const std::size_t k : group)
      for (std::size_t e = bodies.entry_offset[k]; e < bodies.entry_offset[k + 1]; ++e) {
        const Entry& en = bodies.entries[e];
        if (en.other < 0) continue;
        const auto o = std::size_t(en.other);
        if (bodies.fixed[o] || failed[o] >= 0 || contains(group, o)) continue;
        if (outward(rows, en).dot(freed.s.direction) > kAngleTol) in_way.push_back(o);
      }
    sorted_unique(in_way);
    if (in_way.empty() || group.size() + in_way.size() > opt.max_group) return std::nullopt;
    group.insert(group.end(), in_way.begin(), in_way.end());
    std::sort(group.begin(), group.end());
    BodyAnswer together = analyse(bodies, group, rows, strength, failed, opt);
    if (fails(together, opt.fos_target)) return GroupAnswer{std::move(group), together};
  }
}

std::string shortest(double v) {  // the shortest text that reads back as v
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), r.ptr);
}

}  // namespace

std::uint8_t parse_free_faces(const std::string& text) {
  const auto bits = parse_fixed_faces(text);
  if (!bits)
    throw Error("--free-faces", "\"" + text + "\" names no faces of the domain's bounding box",
                "write e.g. --free-faces +z,-x (faces -x +x -y +y -z +z, comma separated)");
  return *bits;
}

void check_stability_options(const StabilityOptions& opt) {
  const auto check = [](const char* option, double v, bool positive, const char* unit) {
    if (!std::isfinite(v) || v < 0 || (positive && v == 0))
      throw Error(option,
                  "is " + shortest(v) + "; it must be a finite number " +
                      (positive ? "above 0" : "of 0 or more"),
                  std::string("give it in ") + unit);
  };
  check("--density", opt.density, true, "kg/m3, e.g. --density 2650");
  check("gravity", opt.gravity, true, "m/s2");
  check("--seismic", opt.seismic, false, "units of g, e.g. --seismic 0.1");
  check("--water-density", opt.water_density, true, "kg/m3");
  check("--support-pressure", opt.support_pressure, false, "Pa, e.g. --support-pressure 50e3");
  check("--fos-target", opt.fos_target, true, "units of the factor of safety, e.g. 1.3");
  if (opt.max_group < 1 || opt.max_group > kMaxGroup)
    throw Error(
        "--max-group",
        "is " + std::to_string(opt.max_group) + "; it must be 1 to " + std::to_string(kMaxGroup),
        "give the most bodies a group that fails together may have, e.g. --max-group 8 "
        "(1: one body at a time)");
  if (!std::isfinite(opt.seismic_azimuth_deg))
    throw Error("--seismic-azimuth", "is not a finite number",
                "give degrees clockwise from North, e.g. --seismic-azimuth 90");
  if (opt.water_table && !std::isfinite(*opt.water_table))
    throw Error("--water-table", "is not a finite number",
                "give the water table's elevation z in the scene's length unit");
}

StabilityData analyse_stability(const BlockSystem& bs, const StabilityOptions& opt,
                                StabilityStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  check_stability_options(opt);
  const Geometry& g = geometry_of(bs, "/geometry");
  if (bs.joints.dimension != 3)
    throw Error("the blocks file", "is a 2-D section; slice-stability analyses 3-D models only",
                "run it on a 3-D model");
  StabilityData out;
  std::vector<double> water;
  const auto since = [](auto t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  find_rows(bs, g, opt, out.contacts, water);
  const double contacts_seconds = since(start);
  const ContactRows& rows = out.contacts;
  std::vector<RowStrength> strength(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    strength[r] = strength_of(bs.joints, rows, r);
    strength[r].water = water[r];
  }
  Bodies bodies = make_bodies(bs, g);
  make_entries(bs, rows, bodies);
  const auto analysis_start = std::chrono::steady_clock::now();
  const double bodies_seconds = since(start) - contacts_seconds;

  // Rounds: every body that can move, then the ones next to a body that failed. In each round,
  // the bodies that fail alone, then the groups that fail together (seeded by the bodies analysed
  // and their neighbours), all found in the state at the round's start.
  const std::size_t n = bodies.size();
  std::vector<BodyAnswer> answer(n);
  std::vector<int> failed(n, -1);
  std::vector<std::int64_t> leader(n, -1);  // a group's smallest body, -1 alone
  std::vector<std::size_t> dirty;
  for (std::size_t k = 0; k < n; ++k)
    if (!bodies.fixed[k]) dirty.push_back(k);
  const auto movable_neighbours = [&](std::size_t k, auto&& visit) {
    for (std::size_t e = bodies.entry_offset[k]; e < bodies.entry_offset[k + 1]; ++e) {
      const std::int64_t o = bodies.entries[e].other;
      if (o >= 0 && failed[std::size_t(o)] < 0 && !bodies.fixed[std::size_t(o)])
        visit(std::size_t(o));
    }
  };
  std::size_t groups = 0;
  int round = 0;
  for (; !dirty.empty(); ++round) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, dirty.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i)
                          answer[dirty[i]] =
                              analyse(bodies, Members(&dirty[i], 1), rows, strength, failed, opt);
                      });
    std::vector<std::size_t> seeds;
    if (opt.max_group > 1) {
      seeds = dirty;
      if (round > 0)
        for (const std::size_t k : dirty)
          movable_neighbours(k, [&](std::size_t o) { seeds.push_back(o); });
      sorted_unique(seeds);
      std::erase_if(seeds, [&](std::size_t k) {
        return !answer[k].exposed || fails(answer[k], opt.fos_target);
      });
    }
    std::vector<std::optional<GroupAnswer>> found(seeds.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, seeds.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t i = range.begin(); i != range.end(); ++i)
                          found[i] = find_group(bodies, seeds[i], rows, strength, failed, opt);
                      });
    std::vector<std::size_t> failing;
    for (const std::size_t k : dirty)
      if (fails(answer[k], opt.fos_target)) failing.push_back(k);
    for (const std::size_t k : failing) failed[k] = round;
    // The weakest group first (then by its members): it claims its bodies, whatever their order.
    std::vector<GroupAnswer> groups_found;
    for (auto& f : found)
      if (f) groups_found.push_back(std::move(*f));
    std::sort(groups_found.begin(), groups_found.end(),
              [](const GroupAnswer& x, const GroupAnswer& y) {
                return std::tie(x.answer.s.fos, x.members) < std::tie(y.answer.s.fos, y.members);
              });
    for (const GroupAnswer& group : groups_found) {
      if (std::any_of(group.members.begin(), group.members.end(),
                      [&](std::size_t k) { return failed[k] >= 0; }))
        continue;
      ++groups;
      for (const std::size_t k : group.members) {
        failed[k] = round;
        answer[k] = group.answer;
        leader[k] = std::int64_t(group.members.front());
        failing.push_back(k);
      }
    }
    if (failing.empty()) break;
    std::vector<std::size_t> next;
    for (const std::size_t k : failing)
      movable_neighbours(k, [&](std::size_t o) { next.push_back(o); });
    sorted_unique(next);
    dirty = std::move(next);
  }

  StabilityResult& res = out.result;
  res.options = opt;
  const std::size_t B = bs.blocks.size();
  res.removable.assign(B, 0);
  res.mode.assign(B, std::uint8_t(FailureMode::not_exposed));
  res.fos.assign(B, kInf);
  res.direction.assign(B, Vec3::Zero());
  res.generation.assign(B, -1);
  res.planes.assign(B, {-1, -1});
  res.group.assign(B, -1);
  StabilityStats st;
  st.bodies = n;
  st.contacts = rows.size();
  st.rounds = std::size_t(round);  // rounds in which something failed
  st.groups = groups;
  for (std::size_t k = 0; k < n; ++k) {
    const BodyAnswer& a = answer[k];
    if (!a.exposed) continue;
    ++st.exposed;
    st.removable += a.s.removable ? 1 : 0;
    st.failing += failed[k] >= 0 ? 1 : 0;
    for (std::size_t m = bodies.member_offset[k]; m < bodies.member_offset[k + 1]; ++m) {
      const std::size_t b = bodies.members[m];
      res.removable[b] = a.s.removable ? 1 : 0;
      res.mode[b] = std::uint8_t(a.s.mode);
      res.fos[b] = a.s.fos;
      res.direction[b] = a.s.direction;
      res.generation[b] = failed[k];
      res.planes[b] = a.joints;
      if (leader[k] >= 0)
        res.group[b] = std::int64_t(bodies.members[bodies.member_offset[std::size_t(leader[k])]]);
    }
  }
  st.analysis_seconds = since(analysis_start);
  st.contacts_seconds = contacts_seconds;
  st.bodies_seconds = bodies_seconds;
  st.seconds = since(start);
  if (stats) *stats = st;
  return out;
}

}  // namespace slice
