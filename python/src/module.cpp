// The rockslice Python module (docs/python.md): the library's pipeline in-process, its data as
// numpy arrays. python/rockslice/__init__.py is the module users import; this is its
// extension, rockslice._rockslice.
#include <pybind11/pybind11.h>

#include "rockslice.hpp"
#include "slice/error.hpp"
#include "slice/export_yade.hpp"
#include "slice/geometry.hpp"
#include "slice/version.hpp"

PYBIND11_MODULE(_rockslice, m) {
  namespace py = pybind11;
  m.doc() = "rockslice's library in-process (docs/python.md); import rockslice, not this";
  m.attr("__version__") = slice::version();
  m.attr("BOUNDARY") = int(slice::kBoundary);
  m.attr("REMOVED") = int(slice::kRemoved);
  m.attr("FIXED") = int(slice::kFixed);

  // slice::Error, the tools' exit 1: rockslice.Error, a ValueError whose message is the line a
  // tool prints after "<tool>: error: ", with its parts as attributes.
  static py::exception<slice::Error> error(m, "Error", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const slice::Error& e) {
      // Through rockslice::text: a path's bytes that are no UTF-8 must not lose the message.
      py::object value = py::reinterpret_borrow<py::object>(error.ptr())(rockslice::text(e.what()));
      value.attr("where") = rockslice::text(e.where());
      value.attr("problem") = rockslice::text(e.problem());
      value.attr("fix") = rockslice::text(e.fix());
      PyErr_SetObject(error.ptr(), value.ptr());
    }
  });

  // The YADE model's options (export_yade.hpp), for rockslice.yade: defaults and checks.
  m.attr("YADE_INITIAL_GAP") = slice::kYadeInitialGap;
  m.def("_yade_options", [](const py::kwargs& given) {
    slice::YadeOptions o;
    const std::pair<const char*, double*> fields[] = {{"density", &o.density},
                                                      {"young", &o.young},
                                                      {"poisson", &o.poisson},
                                                      {"default_friction", &o.default_friction_deg},
                                                      {"damping", &o.damping},
                                                      {"gravity", &o.gravity},
                                                      {"timestep_factor", &o.timestep_factor}};
    py::dict out;
    // rockslice::*_arg: rockslice.Error or a one-line TypeError, not "Unable to cast".
    for (const auto& [name, field] : fields) {
      if (given.contains(name)) *field = rockslice::number_arg(given[name], name);
      out[name] = *field;
    }
    if (given.contains("steps")) o.steps = rockslice::whole_arg(given["steps"], "steps");
    out["steps"] = o.steps;
    if (given.contains("law"))
      o.law = slice::parse_yade_law(rockslice::text_arg(given["law"], "law"));
    out["law"] = slice::to_string(o.law);
    o.validate();
    return out;
  });

  rockslice::bind_model(m);
  rockslice::bind_stages(m);
}
