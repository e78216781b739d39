// rockslice.Model: a joint or block system in memory, its data as numpy arrays. Arrays of one
// field of a struct array (a block's flags, a joint's normal) and of /geometry are views of the
// model's memory, read-only, that keep the model alive; arrays the library does not store
// contiguously (the faces, the joints' polygons) are made once and kept.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "rockslice.hpp"
#include "slice/cut.hpp"
#include "slice/error.hpp"
#include "slice/export_yade.hpp"
#include "slice/shape.hpp"
#include "slice/vertices.hpp"

namespace rockslice {
namespace {

// A read-only array over `rows` elements of `row_bytes` bytes each, starting at `first` (one
// field of the first row), of `cols` values of T per row (0: a 1-D array); `owner` keeps the
// memory alive.
template <class T>
py::array view(const py::handle& owner, const T* first, std::size_t rows, std::size_t row_bytes,
               std::size_t cols = 0) {
  std::vector<py::ssize_t> shape{py::ssize_t(rows)}, strides{py::ssize_t(row_bytes)};
  if (cols) {
    shape.push_back(py::ssize_t(cols));
    strides.push_back(sizeof(T));
  }
  static const T none{};
  py::array a(py::dtype::of<T>(), shape, strides, rows ? first : &none, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

// A whole vector as a read-only array (cols > 0: each element is cols values of T).
template <class T, class E>
py::array view_vector(const py::handle& owner, const std::vector<E>& v, std::size_t cols = 0) {
  static_assert(sizeof(E) == sizeof(T) * (sizeof(E) / sizeof(T)));
  return view(owner, reinterpret_cast<const T*>(v.data()), v.size(), sizeof(E), cols);
}

// A vector handed over to numpy without a copy (a capsule owns it); cols > 0: rows of cols.
template <class T>
py::array owned(std::vector<T>&& v, std::size_t cols = 0) {
  auto held = std::make_unique<std::vector<T>>(std::move(v));
  std::vector<py::ssize_t> shape{py::ssize_t(cols ? held->size() / cols : held->size())};
  if (cols) shape.push_back(py::ssize_t(cols));
  const T* data = held->data();
  py::capsule owner(held.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  held.release();  // the capsule owns it now
  return py::array_t<T>(shape, data, owner);
}

// One value per item, get(item), as an array handed to numpy (of get's return type).
template <class Item, class F>
py::array column(const std::vector<Item>& items, F get) {
  std::vector<std::decay_t<std::invoke_result_t<F, const Item&>>> v;
  v.reserve(items.size());
  for (const Item& i : items) v.push_back(get(i));
  return owned(std::move(v));
}

Model& self_of(const py::handle& h) { return h.cast<Model&>(); }

void require_blocks(const Model& m, const char* what) {
  if (m.stage == Stage::joints)
    throw slice::Error("model", std::string("has no blocks (a joints.h5) for ") + what,
                       "cut it first: rockslice.cut(model), or rockslice.slice(scene)");
}

// The model's /geometry, or one computed from a pruned copy of its blocks (Model::derived).
// `per_face`: the caller needs the per-face or per-vertex arrays, which only a pruned model's
// geometry has in the model's face order.
const slice::Geometry& geometry_of(const py::handle& h, bool per_face, const char* what) {
  Model& m = self_of(h);
  require_blocks(m, what);
  if (m.bs->geometry) return *m.bs->geometry;
  if (per_face && m.stage == Stage::blocks)
    throw slice::Error(
        "model",
        std::string("its blocks are not pruned: ") + what + " follow the faces of pruned blocks",
        "prune them first: rockslice.prune(model), or rockslice.vertices(model)");
  if (!m.derived) {
    auto copy = std::make_shared<slice::BlockSystem>(*m.bs);
    const bool pruned = m.stage != Stage::blocks;
    run_interruptible(
        [&](const slice::Progress& p) {
          if (!pruned) slice::prune_blocks(*copy, slice::kDefaultLpBackend, p);
          slice::compute_geometry(*copy, p);
        },
        py::none());
    if (!m.derived) m.derived = std::shared_ptr<const slice::Geometry>(copy, &*copy->geometry);
  }
  return *m.derived;
}

void make_faces(Model& m) {
  if (m.face_offset) return;
  auto planes = std::make_shared<std::vector<double>>();
  auto joint = std::make_shared<std::vector<std::int64_t>>();
  auto offset = std::make_shared<std::vector<std::int64_t>>(1, 0);
  for (const slice::Block& b : m.bs->blocks) {
    for (const slice::Face& f : b.faces) {
      planes->insert(planes->end(), {f.normal.x(), f.normal.y(), f.normal.z(), f.d});
      joint->push_back(f.joint);
    }
    offset->push_back(std::int64_t(joint->size()));
  }
  m.face_planes = std::move(planes);
  m.face_joint = std::move(joint);
  m.face_offset = std::move(offset);
}

// Per-block fields, views of the blocks' struct array.
template <class T>
py::array block_field(const py::handle& h, T slice::Block::*field, std::size_t cols = 0) {
  const auto& blocks = self_of(h).bs->blocks;
  const T* first = blocks.empty() ? nullptr : &(blocks.front().*field);
  return view(h, first, blocks.size(), sizeof(slice::Block), cols);
}

template <class T>
py::array joint_field(const py::handle& h, const T* (*field)(const slice::Joint&),
                      std::size_t cols = 0) {
  const auto& joints = self_of(h).bs->joints.joints;
  return view(h, joints.empty() ? nullptr : field(joints.front()), joints.size(),
              sizeof(slice::Joint), cols);
}

// The traces of each set's joints on its mapping window, as slice-joints reports them and
// slice-info --json lists them (scene.hpp TraceStats): columns trace_*; a set without a window
// has trace_window False, count 0 and NaN statistics. mapped_mean / mapped_sd: the trace lengths
// mapped there, NaN when not given.
void add_trace_columns(py::dict& d, const std::vector<slice::JointSetSpec>& sets) {
  using Set = slice::JointSetSpec;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  py::array_t<bool> w(py::ssize_t(sets.size()));
  std::vector<std::int64_t> censored;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const bool given = sets[i].mapping.given;
    w.mutable_at(py::ssize_t(i)) = given;
    for (const std::int64_t c : sets[i].traces.censored) censored.push_back(given ? c : 0);
  }
  // A statistic of the traces where the set has a window, else `none`.
  const auto traced = [](auto get, auto none) {
    return [=](const Set& s) { return s.mapping.given ? get(s.traces) : none; };
  };
  using T = slice::TraceStats;
  d["trace_window"] = w;
  d["trace_count"] = column(sets, traced([](const T& t) { return t.count; }, std::int64_t{0}));
  d["trace_censored"] = owned(std::move(censored), 3);
  d["trace_mean"] = column(sets, traced([](const T& t) { return t.mean; }, nan));
  d["trace_sd"] = column(sets, traced([](const T& t) { return t.sd; }, nan));
  d["trace_complete_mean"] = column(sets, traced([](const T& t) { return t.complete_mean; }, nan));
  d["trace_p21"] = column(sets, traced([](const T& t) { return t.p21; }, nan));
  // The mapped trace lengths, NaN where not given (0).
  const auto mapped = [nan](double slice::TraceMapping::*field) {
    return [=](const Set& s) {
      return s.mapping.given && s.mapping.*field > 0 ? s.mapping.*field : nan;
    };
  };
  d["mapped_mean"] = column(sets, mapped(&slice::TraceMapping::field_mean));
  d["mapped_sd"] = column(sets, mapped(&slice::TraceMapping::field_sd));
}

// The joint sets ([[sets]] entries) as columns.
py::dict sets_of(const Model& m) {
  using Set = slice::JointSetSpec;
  const auto& sets = m.bs->joints.sets;
  py::dict d;
  py::list names, intensity, kind;
  for (const auto& s : sets) {
    names.append(text(s.name));
    intensity.append(slice::to_string(s.intensity));
    kind.append(slice::to_string(s.kind));
  }
  const auto of = [&](auto Set::*field) {
    return column(sets, [=](const Set& s) { return s.*field; });
  };
  d["name"] = names;
  d["kind"] = kind;
  d["intensity"] = intensity;
  d["dip"] = of(&Set::dip_deg);
  d["dip_direction"] = of(&Set::dip_direction_deg);
  d["spacing"] = of(&Set::spacing);
  d["offset"] = of(&Set::offset);
  d["friction_angle"] = of(&Set::friction_angle_deg);
  d["cohesion"] = of(&Set::cohesion);
  d["tension"] = of(&Set::tension);
  d["fisher_kappa"] = of(&Set::fisher_kappa);
  d["joint_count"] = of(&Set::joint_count);
  d["achieved_p32"] = of(&Set::achieved_p32);
  d["achieved_p10"] = of(&Set::achieved_p10);
  add_trace_columns(d, sets);
  return d;
}

// The joints' polygons as one array: joint j's corners are rows [offset[j], offset[j + 1]) of
// the (P, 3) global corners (none for a persistent joint).
py::tuple polygons_of(const Model& m) {
  std::vector<double> corners;
  std::vector<std::int64_t> offset{0};
  for (const auto& j : m.bs->joints.joints) {
    for (const slice::Vec3& x : slice::joint_polygon(j))
      corners.insert(corners.end(), {x.x(), x.y(), x.z()});
    offset.push_back(std::int64_t(corners.size() / 3));
  }
  return py::make_tuple(owned(std::move(offset)), owned(std::move(corners), 3));
}

// The block shape factors of every block (docs/block-shape.md) as columns: alpha, beta (MBSCT's
// elongation index), beta_k (Kalenchuk's, as UnBlocks-gen's paper states it), class (MBSCT's
// classes) and class_kalenchuk (UnBlocks-gen's classes on alpha and beta_k); NaN / 'none' where
// undefined. Removed blocks included, in the model's block order, as slice-info computes them.
py::dict shapes_of(const py::handle& h) {
  const Model& m = self_of(h);
  const slice::Geometry& g = geometry_of(h, true, "block shapes");
  using S = slice::BlockShape;
  const auto shapes = slice::block_shapes(m.bs->blocks, g, m.bs->joints.dimension);
  py::list cls, cls_k;
  for (const S& s : shapes) {
    cls.append(slice::to_string(s.shape));
    cls_k.append(slice::to_string(s.shape_k));
  }
  const py::object array = py::module_::import("numpy").attr("array");
  py::dict d;
  d["alpha"] = column(shapes, [](const S& s) { return s.alpha; });
  d["beta"] = column(shapes, [](const S& s) { return s.beta; });
  d["beta_k"] = column(shapes, [](const S& s) { return s.beta_k; });
  d["class"] = array(cls, "U4");
  d["class_kalenchuk"] = array(cls_k, "U4");
  return d;
}

// The rows of the exported YADE script's BLOCKS list (export_yade.hpp's rules: removed blocks
// left out, fixed by slice::is_fixed, friction by slice::block_friction_deg), for
// rockslice.yade: (block, fixed, friction [deg], cluster, volume, centroid, vertices); a
// section's polygon becomes its unit-thickness prism, as in the script.
py::list yade_rows(const Model& m, double default_friction_deg) {
  if (!m.bs->geometry)
    throw slice::Error("model", "has no vertices (no /geometry)",
                       "compute them first: rockslice.vertices(model)");
  const slice::BlockSystem& bs = *m.bs;
  const slice::Geometry& g = *bs.geometry;
  const bool section = bs.joints.dimension == 2;
  py::list rows;
  std::size_t first_face = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); first_face += bs.blocks[b++].faces.size()) {
    const slice::Block& blk = bs.blocks[b];
    if (blk.flags & slice::kRemoved) continue;
    py::list vertices;
    for (const double y : section ? std::vector<double>{-0.5, 0.5} : std::vector<double>{0})
      for (auto v = g.vertex_offset[b]; v < g.vertex_offset[b + 1]; ++v) {
        const slice::Vec3& x = g.vertices[std::size_t(v)];
        vertices.append(py::make_tuple(x.x(), x.y() + y, x.z()));
      }
    const slice::Vec3& c = g.centroid[b];
    rows.append(py::make_tuple(b, slice::is_fixed(blk) ? 1 : 0,
                               slice::block_friction_deg(bs, b, first_face, default_friction_deg),
                               blk.cluster, g.volume[b], py::make_tuple(c.x(), c.y(), c.z()),
                               py::tuple(vertices)));
  }
  return rows;
}

// The rows of the exported YADE script's CONTACTS list (slice::yade_contacts): (block a, block
// b, friction [deg], cohesion [Pa], tension [Pa], area, centroid, normal from a to b).
py::list yade_contact_rows(const Model& m) {
  if (!m.bs->geometry)
    throw slice::Error("model", "has no vertices (no /geometry)",
                       "compute them first: rockslice.vertices(model)");
  py::list rows;
  for (const slice::YadeContact& c : slice::yade_contacts(*m.bs))
    rows.append(py::make_tuple(c.a, c.b, c.friction_deg, c.cohesion, c.tension, c.area,
                               py::make_tuple(c.centroid.x(), c.centroid.y(), c.centroid.z()),
                               py::make_tuple(c.normal.x(), c.normal.y(), c.normal.z())));
  return rows;
}

}  // namespace

void bind_model(py::module_& m) {
  py::class_<Model, std::shared_ptr<Model>> c(
      m, "Model", R"(A joint system, or blocks and their joints, in memory.

Made by rockslice.slice, rockslice.load and the stage functions (joints, cut, prune, vertices).
Arrays are read-only numpy views of the model's memory where it allows (they keep the model
alive), else arrays made once. Per block: volume, centroid, inertia, flags, cluster, inradius,
origin, bsphere; per face (face_offset[b] to face_offset[b + 1] for block b): face_normal,
face_d (relative to the block's origin), face_joint, face_area, face_joint_fraction; vertices:
vertex_offset, vertices (global), face_vertex_offset, face_vertices (indices into the block's own
vertices). The names are those of the HDF5 datasets (docs/python.md).)");
  c.def_property_readonly(
      "stage", [](const Model& s) { return to_string(s.stage); },
      "'joints', 'blocks' (not pruned), 'pruned' or 'geometry'");
  c.def_property_readonly("name", [](const Model& s) { return text(s.bs->joints.name); });
  c.def_property_readonly("seed", [](const Model& s) { return s.bs->joints.seed; });
  c.def_property_readonly("dimension", [](const Model& s) { return s.bs->joints.dimension; });
  c.def_property_readonly("length_scale", [](const Model& s) { return s.bs->joints.length_scale; });
  c.def_property_readonly("pruned", [](const Model& s) { return s.bs->pruned; });
  c.def_property_readonly("provenance", [](const Model& s) {
    const auto& p = s.provenance;
    py::dict d;
    d["tool"] = text(p.tool);
    d["version"] = text(p.version);
    d["command_line"] = text(p.command_line);
    d["input"] = text(p.input);
    d["input_sha256"] = text(p.input_sha256);
    return d;
  });
  c.def(
      "__len__", [](const Model& s) { return s.bs->blocks.size(); }, "the number of blocks");
  c.def("__repr__", [](const Model& s) {
    return text("<rockslice.Model '" + s.bs->joints.name + "': " + to_string(s.stage) + ", " +
                std::to_string(s.bs->joints.joints.size()) + " joints, " +
                std::to_string(s.bs->blocks.size()) + " blocks>");
  });

  // Blocks: views of the block array.
  c.def_property_readonly(
      "flags", [](py::handle h) { return block_field(h, &slice::Block::flags); },
      "uint8 per block: 1 boundary, 2 removed, 4 fixed (rockslice.BOUNDARY, ...)");
  c.def_property_readonly(
      "cluster", [](py::handle h) { return block_field(h, &slice::Block::cluster); },
      "int64 per block: its cluster, -1 for none");
  c.def_property_readonly("inradius",
                          [](py::handle h) { return block_field(h, &slice::Block::inradius); });
  c.def_property_readonly(
      "origin",
      [](py::handle h) {
        const auto& blocks = self_of(h).bs->blocks;
        return view(h, blocks.empty() ? nullptr : blocks.front().origin.data(), blocks.size(),
                    sizeof(slice::Block), 3);
      },
      "(B, 3): each block's Chebyshev centre, the origin of its face_d");
  c.def_property_readonly(
      "bsphere",
      [](py::handle h) {
        const auto& blocks = self_of(h).bs->blocks;
        return view(h, blocks.empty() ? nullptr : blocks.front().bsphere.data(), blocks.size(),
                    sizeof(slice::Block), 4);
      },
      "(B, 4): bounding sphere, centre and radius");
  c.def_property_readonly(
      "fixed",
      [](const Model& s) {
        py::array_t<bool> a(py::ssize_t(s.bs->blocks.size()));
        auto w = a.mutable_unchecked<1>();
        for (std::size_t b = 0; b < s.bs->blocks.size(); ++b)
          w(py::ssize_t(b)) = slice::is_fixed(s.bs->blocks[b]);
        return a;
      },
      "bool per block: it never moves in a DEM model (boundary or fixed_faces)");

  // Faces: flat arrays made once.
  c.def_property_readonly("face_offset", [](py::handle h) {
    Model& s = self_of(h);
    make_faces(s);
    return view_vector<std::int64_t>(h, *s.face_offset);
  });
  c.def_property_readonly("face_normal", [](py::handle h) {
    Model& s = self_of(h);
    make_faces(s);
    return view(h, s.face_planes->data(), s.face_joint->size(), 4 * sizeof(double), 3);
  });
  c.def_property_readonly("face_d", [](py::handle h) {
    Model& s = self_of(h);
    make_faces(s);
    return view(h, s.face_planes->data() + 3, s.face_joint->size(), 4 * sizeof(double));
  });
  c.def_property_readonly(
      "face_joint",
      [](py::handle h) {
        Model& s = self_of(h);
        make_faces(s);
        return view_vector<std::int64_t>(h, *s.face_joint);
      },
      "int64 per face: the joint that made it, -1 for a domain face");

  // /geometry: views (computed first for a model without it).
  c.def_property_readonly(
      "volume",
      [](py::handle h) { return view_vector<double>(h, geometry_of(h, false, "volume").volume); },
      "float64 per block, in the file's block order");
  c.def_property_readonly("centroid", [](py::handle h) {
    return view_vector<double>(h, geometry_of(h, false, "centroid").centroid, 3);
  });
  c.def_property_readonly(
      "inertia",
      [](py::handle h) {
        return view_vector<double>(h, geometry_of(h, false, "inertia").inertia, 6);
      },
      "(B, 6): xx yy zz xy yz zx about the centroid, unit density");
  c.def_property_readonly("vertex_offset", [](py::handle h) {
    return view_vector<std::int64_t>(h, geometry_of(h, true, "vertices").vertex_offset);
  });
  c.def_property_readonly("vertices", [](py::handle h) {
    return view_vector<double>(h, geometry_of(h, true, "vertices").vertices, 3);
  });
  c.def_property_readonly("face_vertex_offset", [](py::handle h) {
    return view_vector<std::int64_t>(h, geometry_of(h, true, "face loops").face_vertex_offset);
  });
  c.def_property_readonly("face_vertices", [](py::handle h) {
    return view_vector<std::int64_t>(h, geometry_of(h, true, "face loops").face_vertices);
  });
  c.def_property_readonly("face_area", [](py::handle h) {
    return view_vector<double>(h, geometry_of(h, true, "face areas").face_area);
  });
  c.def_property_readonly("face_joint_fraction", [](py::handle h) {
    return view_vector<double>(h, geometry_of(h, true, "face joint fractions").face_joint_fraction);
  });
  // /stability and /contacts (slice-stability, rockslice.stability): dicts of views, or None.
  c.def_property_readonly(
      "stability",
      [](py::handle h) -> py::object {
        const Model& s = self_of(h);
        if (!s.bs->stability) return py::none();
        const slice::StabilityResult& r = s.bs->stability->result;
        py::dict d;
        d["removable"] = view_vector<std::uint8_t>(h, r.removable);
        d["mode"] = view_vector<std::uint8_t>(h, r.mode);
        d["fos"] = view_vector<double>(h, r.fos);
        d["direction"] = view_vector<double>(h, r.direction, 3);
        d["generation"] = view_vector<std::int32_t>(h, r.generation);
        d["planes"] = view_vector<std::int64_t>(h, r.planes, 2);
        d["group"] = view_vector<std::int64_t>(h, r.group);
        return d;
      },
      "None, or a dict of arrays per block (/stability, docs/stability.md): removable, mode "
      "(0 not exposed, 1 not removable, 2 stable, 3 falls, 4 slides on one plane, 5 on two), "
      "fos (+inf where nothing can move), direction (B, 3), generation (round it fails in, -1 "
      "never), planes (B, 2: joints of the sliding planes, -1 none), group (a group that fails "
      "together: its smallest block, -1 none)");
  c.def_property_readonly(
      "contacts",
      [](py::handle h) -> py::object {
        const Model& s = self_of(h);
        if (!s.bs->stability) return py::none();
        const slice::ContactRows& r = s.bs->stability->contacts;
        py::dict d;
        d["pairs"] = view_vector<std::int64_t>(h, r.pairs, 2);
        d["faces"] = view_vector<std::int64_t>(h, r.faces, 2);
        d["area"] = view_vector<double>(h, r.area);
        d["centroid"] = view_vector<double>(h, r.centroid, 3);
        d["normal"] = view_vector<double>(h, r.normal, 3);
        d["joint"] = view_vector<std::int64_t>(h, r.joint);
        d["fraction"] = view_vector<double>(h, r.fraction);
        d["free"] = view_vector<std::uint8_t>(h, r.free);
        return d;
      },
      "None, or a dict of arrays per contact (/contacts, docs/formats.md): pairs (C, 2; -1 the "
      "domain's boundary), faces (C, 2), area, centroid (C, 3), normal (C, 3: the first block's "
      "outward normal), joint, fraction (part on the joint's polygon), free");
  c.def_property_readonly(
      "shape", &shapes_of,
      "the block shape factors per block (docs/block-shape.md), a dict of columns: alpha, beta "
      "(MBSCT's elongation index, 0..1), beta_k (Kalenchuk's beta, 10/9..10), class (MBSCT's "
      "classes: 'C', 'PC', 'P', 'CE', 'EP', 'E', 'none') and class_kalenchuk (UnBlocks-gen's "
      "classes on alpha and beta_k); computed on each call, removed blocks included; 3-D only");

  // Joints: views of the joint array; the polygons and the sets as arrays made here.
  using J = slice::Joint;
  c.def_property_readonly("joint_count", [](const Model& s) { return s.bs->joints.joints.size(); });
  c.def_property_readonly("joint_normal", [](py::handle h) {
    return joint_field<double>(
        h, +[](const J& j) { return j.plane.normal.data(); }, 3);
  });
  c.def_property_readonly(
      "joint_d",
      [](py::handle h) {
        return joint_field<double>(
            h, +[](const J& j) { return &j.plane.d; });
      },
      "float64 per joint: its plane normal . x = d");
  c.def_property_readonly("joint_centre", [](py::handle h) {
    return joint_field<double>(
        h, +[](const J& j) { return j.centre.data(); }, 3);
  });
  c.def_property_readonly("joint_dip", [](py::handle h) {
    return joint_field<double>(
        h, +[](const J& j) { return &j.dip_deg; });
  });
  c.def_property_readonly("joint_dip_direction", [](py::handle h) {
    return joint_field<double>(
        h, +[](const J& j) { return &j.dip_direction_deg; });
  });
  c.def_property_readonly(
      "joint_kind",
      [](py::handle h) {
        return joint_field<std::uint8_t>(
            h, +[](const J& j) { return reinterpret_cast<const std::uint8_t*>(&j.kind); });
      },
      "uint8 per joint: 0 rock, 1 construction, 2 boundary");
  c.def_property_readonly(
      "joint_set",
      [](py::handle h) {
        return joint_field<std::int32_t>(
            h, +[](const J& j) { return &j.set; });
      },
      "int32 per joint: its set (model.sets), -1 for a [[joints]] entry");
  c.def_property_readonly("joint_friction_angle", [](py::handle h) {
    return joint_field<double>(
        h, +[](const J& j) { return &j.friction_angle_deg; });
  });
  c.def_property_readonly("joint_cohesion", [](py::handle h) {
    return joint_field<double>(
        h, +[](const J& j) { return &j.cohesion; });
  });
  c.def_property_readonly("joint_tension", [](py::handle h) {
    return joint_field<double>(
        h, +[](const J& j) { return &j.tension; });
  });
  c.def_property_readonly(
      "joint_polygons", [](const Model& s) { return polygons_of(s); },
      "(offset, corners): joint j's polygon is corners[offset[j]:offset[j + 1]] "
      "(global, counter-clockwise about its normal); none for a persistent joint");
  c.def_property_readonly(
      "sets", [](const Model& s) { return sets_of(s); },
      "the [[sets]] entries: a dict of columns (name, dip, joint_count, ...)");

  c.def(
      "friction_deg",
      [](const Model& s, const py::object& given) {
        const double default_deg = number_arg(given, "default");  // one line, not pybind's four
        std::vector<double> phi;
        std::size_t first_face = 0;
        for (std::size_t b = 0; b < s.bs->blocks.size();
             first_face += s.bs->blocks[b++].faces.size())
          phi.push_back(slice::block_friction_deg(*s.bs, b, first_face, default_deg));
        return owned(std::move(phi));
      },
      py::arg("default") = 30.0, "each block's friction angle by the YADE export's rule");
  c.def("_yade_rows", &yade_rows, py::arg("default_friction_deg"));
  c.def("_yade_contacts", &yade_contact_rows);
}

}  // namespace rockslice
