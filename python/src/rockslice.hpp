#pragma once
// The Python module's shared pieces (python/src/*.cpp): the model a Python user holds, and the
// runner that calls the library off the interpreter's lock so that Ctrl-C interrupts it.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "slice/h5io.hpp"
#include "slice/progress.hpp"

namespace rockslice {

namespace py = pybind11;

/// What a model holds: "joints" (joints.h5: no blocks), "blocks" (cut, not pruned), "pruned"
/// (blocks.h5 after slice-prune or slice-cut --prune) or "geometry" (geom.h5: with /geometry).
enum class Stage { joints, blocks, pruned, geometry };
const char* to_string(Stage s);

/// A joint system, or a block system and its joints, in memory. Immutable once made: every
/// stage makes a new Model, so the numpy arrays that view its memory stay valid while the array
/// (which keeps the Model alive) does.
struct Model {
  std::shared_ptr<slice::BlockSystem> bs;  // bs->joints is the joint system
  Stage stage = Stage::joints;
  slice::Provenance provenance;  // of the file it was loaded from, or of the in-process run
  /// The geometry of a model without /geometry, computed at the first array that needs it
  /// (volumes of blocks.h5): a pruned copy's, so only its per-block arrays are the model's when
  /// the model is not pruned.
  std::shared_ptr<const slice::Geometry> derived;
  /// The faces as flat arrays, made at the first call (blocks keep their faces apart).
  std::shared_ptr<const std::vector<double>> face_planes;  // F x 4: normal, d (global frame)
  std::shared_ptr<const std::vector<std::int64_t>> face_joint, face_offset;
};

/// Runs `work` on a thread of its own while this thread, without the interpreter's lock, waits
/// for it: every 50 ms it checks for signals (Ctrl-C raises KeyboardInterrupt: the work is told
/// to stop at its next progress report and this throws once it has) and hands the latest
/// progress report to `callback` (if not None; once more at the end if a report came after the
/// last call). An exception of `work` is rethrown here; so is one the callback raises, after
/// the work has stopped.
void run_interruptible(const std::function<void(const slice::Progress&)>& work,
                       const py::object& callback);

/// The provenance of an in-process run from `input` (a file name, or a name for a dict scene)
/// whose content hashes to `sha256`.
slice::Provenance python_provenance(const std::string& call, const std::string& input,
                                    const std::string& sha256);

/// `s` (a message, a path) as a Python str: bytes that are no UTF-8 (a path's) as escapes
/// ("\xff"), so that a message is never lost to a UnicodeDecodeError.
py::str text(const std::string& s);

/// Raises `type` (PyExc_OSError, ...) with `line` as its message.
[[noreturn]] void raise(PyObject* type, const std::string& line);

/// A value given from Python as the library takes it, or rockslice.Error (a ValueError) naming
/// `name` for a value no C++ type holds (2**70, 1e400, a lone surrogate), TypeError (one line)
/// for a value of the wrong type: never pybind11's RuntimeError "Unable to cast".
double number_arg(const py::handle& v, const std::string& name);
std::int64_t whole_arg(const py::handle& v, const std::string& name);
std::string text_arg(const py::handle& v, const std::string& name);

void bind_model(py::module_& m);
void bind_stages(py::module_& m);

}  // namespace rockslice
