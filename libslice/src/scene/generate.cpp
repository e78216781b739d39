#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "scene_common.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/orientation_stats.hpp"
#include "slice/polytope.hpp"
#include "slice/scene.hpp"
#include "slice/stochastic.hpp"
#include "slice/traces.hpp"
#include "slice/zone_report.hpp"

// The joints of a scene (generate_joints) and their order (order_joints).
namespace slice {

using namespace scene_read;

namespace {

// The planes n . x = offset + k * spacing of a set that pass through the domain's interior:
// lo + tol < c < hi - tol, so a plane on a domain face (or within tol of it) is not generated.
std::vector<double> set_planes(const JointSetSpec& s, const Vec3& n,
                               const std::vector<Vec3>& vertices, double tol) {
  const auto [lo, hi] = extent_along(vertices, n);
  std::vector<double> c;
  const double k0 = std::ceil((lo + tol - s.offset) / s.spacing) - 1;
  const double k1 = std::floor((hi - tol - s.offset) / s.spacing) + 1;
  // Counted by an integer: past 2^53, k + 1 == k in double and a loop on k never ends.
  const auto steps = static_cast<std::int64_t>(k1 - k0);
  for (std::int64_t i = 0; i <= steps; ++i) {
    const double ck = s.offset + (k0 + double(i)) * s.spacing;
    if (lo + tol < ck && ck < hi - tol) c.push_back(ck);
  }
  return c;
}

}  // namespace

namespace scene_read {
void set_joint_properties(Joint& j, const JointSetSpec& spec, std::int32_t set) {
  j.kind = spec.kind;
  j.set = set;
  j.friction_angle_deg = spec.friction_angle_deg;
  j.cohesion = spec.cohesion;
  j.tension = spec.tension;
  j.limits = spec.limits;
  j.boundary_side = spec.boundary_side;
}
}  // namespace scene_read

JointSystem generate_joints(const Scene& scene) {
  JointSystem js;
  js.name = scene.name;
  js.seed = scene.seed;
  js.dimension = scene.dimension;
  js.domain = scene.domain;
  js.options = scene.options;
  js.sets = scene.sets;
  js.rock = scene.rock;
  js.zones = scene.zones;
  js.zone_meshes = scene.zone_meshes;
  js.zone_info = scene.zone_info;  // measured below, once the length scale is known
  const std::string where = scene.source.string();
  const Region solid{solid_region(scene.domain, scene.dimension)};
  const RegionAnalysis dom = analyse_region(solid.planes, scene.options.tolerance, scene.dimension);
  if (dom.status != RegionStatus::ok)
    throw Error(where,
                dom.status == RegionStatus::unbounded ? "the domain is unbounded"
                                                      : "the domain has no volume",
                "give a bounded domain with an interior (load the scene with load_scene)");
  js.length_scale = dom.length_scale;
  const double tol = scene.options.tolerance * dom.length_scale;
  if (const std::string why = precision_problem(dom.info.min, dom.info.max, tol); !why.empty())
    throw Error(where, why, "move the scene nearer the origin or raise its tolerance");
  js.zone_info = measure_zones(js);
  const Vec3 mean = dom.info.interior_point;  // the domain's vertex mean
  const DomainBox box = domain_box(solid, dom, scene.options.tolerance);

  // [[joints]], then the sets; order_joints then puts them in sequence. A joint that misses the
  // domain entirely is kept: the slicer finds that it cuts nothing.
  // place[i]: the entry joint i comes from. A Scene built in code may have no places: then each
  // [[joints]] entry is its own entry, all before the sets (group 0, then 1), as order_joints
  // without places has it.
  std::vector<EntryPlace> place;
  const auto place_of = [](const std::vector<EntryPlace>& places, std::size_t i,
                           std::int64_t group) {
    return i < places.size() ? places[i] : EntryPlace{1, group, static_cast<std::int64_t>(i)};
  };
  // A joint keeps its set if it is a given one (deterministic: a [[dfn]] file's, or named by
  // [[joints]] `set`); the sets below generate their own.
  const auto given = [&](std::int32_t s) {
    return s >= 0 && std::size_t(s) < js.sets.size() &&
           js.sets[std::size_t(s)].intensity == SetIntensity::deterministic;
  };
  for (std::size_t i = 0; i < scene.joints.size(); ++i) {
    js.joints.push_back(scene.joints[i]);
    if (!given(js.joints.back().set)) js.joints.back().set = -1;
    place.push_back(place_of(scene.joint_places, i, 0));
  }
  for (std::size_t s = 0; s < js.sets.size(); ++s) {
    JointSetSpec& spec = js.sets[s];
    std::vector<const Joint*> mine;
    if (spec.intensity == SetIntensity::deterministic) {
      // Its mean orientation: the Fisher mean of its joints' poles folded into one hemisphere
      // (orientation_stats.hpp; summing upward normals is wrong for steep sets).
      std::vector<Vec3> normals;
      for (std::size_t i = 0; i < scene.joints.size(); ++i)
        if (js.joints[i].set == std::int32_t(s)) {
          mine.push_back(&js.joints[i]);
          normals.push_back(js.joints[i].plane.normal);
        }
      if (!normals.empty()) {
        const OrientationStats os = orientation_stats(normals);
        spec.dip_deg = os.mean_dip_deg;
        spec.dip_direction_deg = os.mean_dip_direction_deg;
      }
    }
    const Vec3 n = dip_normal(spec.dip_deg, spec.dip_direction_deg, scene.dimension);
    if (!spec.scanline_given) std::tie(spec.scanline_from, spec.scanline_to) = chord(box, mean, n);
    const std::size_t first = js.joints.size();
    if (spec.intensity == SetIntensity::deterministic) {
      measure_set(spec, mine, box);  // its joints are among the scene's, placed above
      continue;
    }
    if (spec.intensity != SetIntensity::spacing) {
      // In a section, a 3-D set's traces (docs/2d.md); read_set refuses the other 2-D cases.
      std::vector<Joint> joints =
          scene.section
              ? generate_section_set(spec, s, scene.seed, *scene.section, scene.set_traces.at(s),
                                     box, scene.max_joints, where)
              : generate_stochastic_set(spec, s, scene.seed, box, scene.max_joints, where);
      std::move(joints.begin(), joints.end(), std::back_inserter(js.joints));
    } else {
      if (!(spec.spacing > 0) || !std::isfinite(spec.spacing) || !std::isfinite(spec.offset))
        throw Error(where,
                    "set \"" + spec.name + "\" has spacing " + fmt(spec.spacing) + " and offset " +
                        fmt(spec.offset),
                    "give a finite spacing > 0 and a finite offset");
      const auto [lo, hi] = extent_along(dom.info.vertices, n);
      if ((hi - lo) / spec.spacing > kMaxPlanesPerSet)
        throw Error(
            where,
            "set \"" + spec.name + "\" would have more than " + fmt(kMaxPlanesPerSet) + " planes",
            "check the units of spacing and of the domain");
      const std::vector<double> planes = set_planes(spec, n, dom.info.vertices, tol);
      spec.stream_seed = set_stream_seed(scene.seed, s);  // drawn from only with scatter
      // With fisher_kappa, each plane has its own pole, drawn in increasing offset; without,
      // nothing is drawn and every plane has the mean orientation.
      const std::vector<Vec3> poles = spec.fisher_kappa > 0
                                          ? fisher_normals(spec, spec.stream_seed, planes.size())
                                          : std::vector<Vec3>{};
      for (std::size_t k = 0; k < planes.size(); ++k) {
        const double c = planes[k];
        Joint j;
        j.plane = {n, c};
        j.centre = mean - (n.dot(mean) - c) * n;  // the vertex mean projected on the plane
        j.dip_deg = spec.dip_deg;
        j.dip_direction_deg = spec.dip_direction_deg;
        if (!poles.empty()) {  // turned about its centre, which stays on the mean normal's line
          const DipAndDirection dd = dip_from_normal(poles[k]);
          j.dip_deg = dd.dip_deg;
          j.dip_direction_deg = dd.dip_direction_deg;
          // The normal from the stored angles, as readers of joints.h5 rebuild it.
          const Vec3 nk = normal_from_dip(j.dip_deg, j.dip_direction_deg);
          j.plane = {nk, nk.dot(j.centre)};
        }
        set_joint_properties(j, spec, static_cast<std::int32_t>(s));
        js.joints.push_back(std::move(j));
      }
      spec.candidates = static_cast<std::int64_t>(planes.size());
    }
    for (std::size_t i = first; i < js.joints.size(); ++i) mine.push_back(&js.joints[i]);
    measure_set(spec, mine, box);
    if (spec.mapping.given) spec.traces = trace_stats(mine, spec.mapping, tol);
    place.resize(js.joints.size(), place_of(scene.set_places, s, 1));
  }
  order_joints(js.joints, scene.options.order, place);
  return js;
}

std::vector<Vec3> joint_polygon(const Joint& j) {
  std::vector<Vec3> p;
  if (j.persistent()) return p;
  const JointFrame f = plane_frame(j.dip_deg, j.dip_direction_deg);
  for (const Vec2& uv : j.polygon_uv) p.push_back(f.to_global(j.centre, uv));
  return p;
}

double polygon_area(const Joint& j) {
  if (j.persistent()) return std::numeric_limits<double>::infinity();
  const auto& p = j.polygon_uv;
  double a = 0;  // shoelace formula
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& q = p[i];
    const Vec2& r = p[(i + 1) % p.size()];
    a += q.x() * r.y() - q.y() * r.x();
  }
  return 0.5 * std::abs(a);
}

void order_joints(std::vector<Joint>& joints, JointOrder order, std::span<const EntryPlace> place) {
  if (place.size() != joints.size())
    throw std::invalid_argument("order_joints: one place per joint expected");
  const auto key = [&](std::size_t i) {
    return std::make_tuple(place[i].stage, place[i].line, place[i].entry);
  };
  std::vector<std::size_t> idx(joints.size());
  std::iota(idx.begin(), idx.end(), std::size_t{0});
  // Stages in order, each stage's entries in file order, a set's joints as generated.
  std::stable_sort(idx.begin(), idx.end(),
                   [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  if (order == JointOrder::as_given || order == JointOrder::by_set) {
    // by-set is the same sequence: every entry (a set or a single joint) in one piece.
  } else {
    std::vector<double> area(joints.size());
    for (std::size_t i = 0; i < joints.size(); ++i) area[i] = polygon_area(joints[i]);
    const auto larger = [&](std::size_t a, std::size_t b) { return area[a] > area[b]; };
    std::vector<std::size_t> out;
    out.reserve(idx.size());
    for (auto stage = idx.begin(); stage != idx.end();) {
      const auto end = std::find_if(
          stage, idx.end(), [&](std::size_t i) { return place[i].stage != place[*stage].stage; });
      if (order == JointOrder::largest_first) {
        std::stable_sort(stage, end, larger);
        out.insert(out.end(), stage, end);
      } else {  // alternating: one joint of each entry in turn, each entry largest first
        std::vector<std::vector<std::size_t>> groups;
        for (auto it = stage; it != end; ++it) {
          if (groups.empty() || key(groups.back().front()) != key(*it)) groups.emplace_back();
          groups.back().push_back(*it);
        }
        std::size_t longest = 0;
        for (auto& g : groups) {
          std::stable_sort(g.begin(), g.end(), larger);
          longest = std::max(longest, g.size());
        }
        for (std::size_t round = 0; round < longest; ++round)
          for (const auto& g : groups)
            if (round < g.size()) out.push_back(g[round]);
      }
      stage = end;
    }
    idx = std::move(out);
  }
  std::vector<Joint> sorted;
  sorted.reserve(joints.size());
  for (const std::size_t i : idx) sorted.push_back(std::move(joints[i]));
  joints = std::move(sorted);
}

void order_joints(std::vector<Joint>& joints, JointOrder order) {
  if (order == JointOrder::as_given) return;
  std::vector<EntryPlace> place(joints.size());
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const auto n = static_cast<std::int64_t>(i);
    if (order == JointOrder::largest_first || joints[i].set < 0)
      place[i] = {1, 0, n};  // ties in the given order; a single joint is its own entry
    else
      place[i] = {1, 1, std::int64_t{joints[i].set}};  // the sets after, by index
  }
  order_joints(joints, order, place);
}

}  // namespace slice
