#include "slice/export_vtu.hpp"

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPoints.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <string>
#include <vector>

#include "../io/h5/h5.hpp"
#include "slice/error.hpp"
#include "slice/orientation.hpp"
#include "slice/output.hpp"
#include "slice/polytope.hpp"
#include "slice/vertices.hpp"

namespace slice {
namespace {

/// VTK reports errors by printing them; the library prints nothing. This switches VTK's
/// (process-wide) messages off while a writer runs and restores the setting after.
class QuietVtk {
 public:
  QuietVtk() : was_(vtkObject::GetGlobalWarningDisplay()) { vtkObject::GlobalWarningDisplayOff(); }
  ~QuietVtk() { vtkObject::SetGlobalWarningDisplay(was_); }
  QuietVtk(const QuietVtk&) = delete;
  QuietVtk& operator=(const QuietVtk&) = delete;

 private:
  int was_;
};

template <class Array>
vtkNew<Array> named_array(const char* name, std::size_t rows) {
  vtkNew<Array> a;
  a->SetName(name);
  a->SetNumberOfComponents(1);
  a->SetNumberOfTuples(vtkIdType(rows));
  return a;
}

/// Writes `grid` to out atomically: binary appended data, compressed, 64-bit headers.
void write_grid(const std::filesystem::path& out, vtkUnstructuredGrid* grid,
                VtuCompressor compressor) {
  PartialFile part(out);
  {
    const QuietVtk quiet;
    vtkNew<vtkXMLUnstructuredGridWriter> w;
    w->SetFileName(part.path().c_str());
    w->SetInputData(grid);
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff();  // raw binary, not base64
    switch (compressor) {
      case VtuCompressor::lz4:
        w->SetCompressorTypeToLZ4();
        break;
      case VtuCompressor::zlib:
        w->SetCompressorTypeToZLib();
        break;
      case VtuCompressor::none:
        w->SetCompressorTypeToNone();
        break;
    }
    w->SetHeaderTypeToUInt64();
    w->SetIdTypeToInt64();
    if (w->Write() != 1 || w->GetErrorCode() != vtkErrorCode::NoError)
      throw Error(out.string(),
                  std::string("VTK could not write it (") +
                      vtkErrorCode::GetStringFromErrorCode(w->GetErrorCode()) + ")",
                  "check that the directory is writable and the disk is not full");
  }
  part.commit();
}

}  // namespace

VtuCompressor parse_vtu_compressor(const std::string& text, const std::string& option) {
  if (text == "lz4") return VtuCompressor::lz4;
  if (text == "zlib") return VtuCompressor::zlib;
  if (text == "none") return VtuCompressor::none;
  throw Error(option, "is \"" + text + "\"", "use lz4 (fast), zlib (small) or none");
}

VtuStats write_blocks_vtu(const std::filesystem::path& out, const BlockSystem& bs,
                          VtuCompressor compressor) {
  if (!bs.geometry)
    throw Error(out.string(), "the blocks have no vertices (no /geometry)",
                "run slice-vertices on the blocks file first");
  const Geometry& g = *bs.geometry;
  VtuStats st;
  std::size_t kept = 0;
  for (const Block& b : bs.blocks) kept += (b.flags & kRemoved) ? 0 : 1;

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkUnstructuredGrid> grid;
  grid->Allocate(vtkIdType(kept));
  auto block_id = named_array<vtkTypeInt64Array>("block_id", kept);
  auto volume = named_array<vtkDoubleArray>("volume", kept);
  auto inradius = named_array<vtkDoubleArray>("inradius", kept);
  auto cluster = named_array<vtkTypeInt64Array>("cluster", kept);
  auto boundary = named_array<vtkUnsignedCharArray>("boundary", kept);
  auto fixed = named_array<vtkUnsignedCharArray>("fixed", kept);  // boundary or fixed_faces
  auto aspect = named_array<vtkDoubleArray>("aspect_ratio", kept);

  std::vector<vtkIdType> ids, faces;
  std::size_t face_row = 0;
  vtkIdType cell = 0;
  for (std::size_t b = 0; b < bs.blocks.size(); ++b) {
    const Block& blk = bs.blocks[b];
    const std::size_t nf = blk.faces.size();
    if (blk.flags & kRemoved) {
      face_row += nf;
      ++st.skipped;
      continue;
    }
    const vtkIdType base = points->GetNumberOfPoints();
    ids.clear();
    for (auto v = g.vertex_offset[b]; v < g.vertex_offset[b + 1]; ++v) {
      const Vec3& x = g.vertices[std::size_t(v)];
      ids.push_back(points->InsertNextPoint(x.x(), x.y(), x.z()));
    }
    faces.clear();
    for (std::size_t f = 0; f < nf; ++f, ++face_row) {
      const auto lo = g.face_vertex_offset[face_row], hi = g.face_vertex_offset[face_row + 1];
      faces.push_back(vtkIdType(hi - lo));
      for (auto k = lo; k < hi; ++k)
        faces.push_back(base + vtkIdType(g.face_vertices[std::size_t(k)]));
    }
    grid->InsertNextCell(VTK_POLYHEDRON, vtkIdType(ids.size()), ids.data(), vtkIdType(nf),
                         faces.data());
    block_id->SetValue(cell, std::int64_t(b));
    volume->SetValue(cell, g.volume[b]);
    inradius->SetValue(cell, blk.inradius);
    cluster->SetValue(cell, blk.cluster);
    boundary->SetValue(cell, (blk.flags & kBoundary) ? 1 : 0);
    fixed->SetValue(cell, (blk.flags & (kBoundary | kFixed)) ? 1 : 0);
    aspect->SetValue(cell, blk.inradius > 0 ? blk.bsphere[3] / blk.inradius : 0.0);
    ++cell;
  }
  grid->SetPoints(points);
  for (vtkAbstractArray* a :
       {static_cast<vtkAbstractArray*>(block_id.Get()),
        static_cast<vtkAbstractArray*>(volume.Get()),
        static_cast<vtkAbstractArray*>(inradius.Get()),
        static_cast<vtkAbstractArray*>(cluster.Get()),
        static_cast<vtkAbstractArray*>(boundary.Get()), static_cast<vtkAbstractArray*>(fixed.Get()),
        static_cast<vtkAbstractArray*>(aspect.Get())})
    grid->GetCellData()->AddArray(a);
  grid->GetCellData()->SetActiveScalars("volume");
  write_grid(out, grid, compressor);
  st.cells = std::size_t(cell);
  st.points = std::size_t(points->GetNumberOfPoints());
  return st;
}

VtuStats write_joints_vtu(const std::filesystem::path& out, const JointSystem& js,
                          VtuCompressor compressor) {
  const double tol = js.options.tolerance * js.length_scale;
  const PolytopeInfo dom = analyse_polytope(js.domain.planes, tol);
  if (!dom.bounded || !dom.has_interior)
    throw Error(out.string(), "the domain is empty or unbounded",
                "regenerate it with slice-joints");
  const Vec3 centre = (dom.min + dom.max) / 2;
  const double half = 2 * ((dom.max - dom.min).norm() / 2 + tol);  // covers the whole domain

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkUnstructuredGrid> grid;
  grid->Allocate(vtkIdType(js.joints.size()));
  struct Row {
    std::size_t joint;
  };
  std::vector<Row> rows;
  std::vector<vtkIdType> ids;
  VtuStats st;
  for (std::size_t j = 0; j < js.joints.size(); ++j) {
    const Joint& jt = js.joints[j];
    std::vector<Vec3> poly = joint_polygon(jt);
    if (poly.empty()) {  // persistent: a square of the plane around the domain's centre
      const JointFrame f = plane_frame(jt.dip_deg, jt.dip_direction_deg);
      const Vec3 c = centre - jt.plane.distance(centre) * jt.plane.normal;
      poly = {c + half * (-f.u - f.v), c + half * (f.u - f.v), c + half * (f.u + f.v),
              c + half * (-f.u + f.v)};
    }
    for (const Plane& p : js.domain.planes) {
      poly = clip_polygon(poly, p);
      if (poly.size() < 3) break;
    }
    if (poly.size() < 3 || newell_normal(poly).norm() / 2 <= tol * tol) {
      ++st.skipped;
      continue;
    }
    ids.clear();
    for (const Vec3& x : poly) ids.push_back(points->InsertNextPoint(x.x(), x.y(), x.z()));
    grid->InsertNextCell(VTK_POLYGON, vtkIdType(ids.size()), ids.data());
    rows.push_back({j});
  }
  auto joint_id = named_array<vtkTypeInt64Array>("joint_id", rows.size());
  auto set = named_array<vtkTypeInt32Array>("set", rows.size());
  auto kind = named_array<vtkUnsignedCharArray>("kind", rows.size());
  auto persistent = named_array<vtkUnsignedCharArray>("persistent", rows.size());
  auto friction = named_array<vtkDoubleArray>("friction_angle", rows.size());
  auto cohesion = named_array<vtkDoubleArray>("cohesion", rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const Joint& jt = js.joints[rows[r].joint];
    const auto c = vtkIdType(r);
    joint_id->SetValue(c, std::int64_t(rows[r].joint));
    set->SetValue(c, jt.set);
    kind->SetValue(c, static_cast<unsigned char>(jt.kind));
    persistent->SetValue(c, jt.persistent() ? 1 : 0);
    friction->SetValue(c, jt.friction_angle_deg);
    cohesion->SetValue(c, jt.cohesion);
  }
  grid->SetPoints(points);
  for (vtkAbstractArray* a :
       {static_cast<vtkAbstractArray*>(joint_id.Get()), static_cast<vtkAbstractArray*>(set.Get()),
        static_cast<vtkAbstractArray*>(kind.Get()),
        static_cast<vtkAbstractArray*>(persistent.Get()),
        static_cast<vtkAbstractArray*>(friction.Get()),
        static_cast<vtkAbstractArray*>(cohesion.Get())})
    grid->GetCellData()->AddArray(a);
  write_grid(out, grid, compressor);
  st.cells = rows.size();
  st.points = std::size_t(points->GetNumberOfPoints());
  return st;
}

}  // namespace slice
