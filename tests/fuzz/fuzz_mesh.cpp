// libFuzzer targets: the mesh readers of [[zones]] meshes (mesh.hpp). One source, two targets,
// by the file name the input is given (SLICE_FUZZ_MESH_EXT):
//   fuzz_obj  the input as "mesh.obj": the OBJ reader;
//   fuzz_stl  the input as "mesh.stl": the STL reader, ASCII or binary (read_mesh tells them
//             apart by the bytes: the binary size rule, then text or not).
// As the scene parser does with a zone's mesh: slice::read_mesh, then slice::check_solid_mesh;
// a solid then answers MeshInside for two points. slice::Error (bad input, exit 1 in the tools)
// is the expected answer; any other exception, a crash, a sanitizer report, a timeout or
// running out of memory is a finding, and so is a mesh that is accepted but breaks what the
// header promises: a triangle index out of the vertices, a non-finite vertex, a solid whose
// volume is not positive and finite, a point beyond the mesh's bounding box found inside.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "slice/error.hpp"
#include "slice/mesh.hpp"

#ifndef SLICE_FUZZ_MESH_EXT
#error "SLICE_FUZZ_MESH_EXT (\".obj\" or \".stl\") names the reader"
#endif

namespace {

const char* const kTarget = "fuzz_mesh (" SLICE_FUZZ_MESH_EXT ")";

void check_read(const slice::TriangleMesh& m) {
  for (const slice::Vec3& x : m.vertices)
    if (!x.allFinite()) fuzz::finding(kTarget, "read_mesh accepted a non-finite vertex");
  const auto n = std::int64_t(m.vertices.size());
  for (const auto& t : m.triangles)
    for (const std::int64_t v : t)
      if (v < 0 || v >= n)
        fuzz::finding(kTarget, "read_mesh accepted vertex index " + std::to_string(v) + " of " +
                                   std::to_string(n));
  if (m.triangles.empty()) fuzz::finding(kTarget, "read_mesh accepted a mesh without triangles");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  fuzz::set_input_name("mesh" SLICE_FUZZ_MESH_EXT);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = fuzz::write_input(data, size);
  try {
    const slice::TriangleMesh m = slice::read_mesh(path);
    check_read(m);
    const double volume = slice::check_solid_mesh(m, "fuzz zone");
    if (!(volume > 0 && std::isfinite(volume)))
      fuzz::finding(kTarget,
                    "check_solid_mesh accepted a solid of volume " + std::to_string(volume));
    slice::Vec3 lo = m.vertices.front(), hi = lo;
    for (const slice::Vec3& x : m.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    const slice::MeshInside inside(m);
    // Beyond the box by its size (or by 1 for a flat box): outside whatever the mesh.
    const slice::Vec3 far = hi + (hi - lo).cwiseMax(slice::Vec3::Ones());
    if (far.allFinite() && inside(far))
      fuzz::finding(kTarget, "MeshInside finds a point beyond the mesh's box inside");
    (void)inside((lo + hi) / 2);
  } catch (const slice::Error&) {
    // Refused with a message: the promised answer to bad input.
  }
  return 0;
}
