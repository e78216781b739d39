// The runner that calls the library off the interpreter's lock (rockslice.hpp).
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

#include "rockslice.hpp"
#include "slice/error.hpp"
#include "slice/version.hpp"

namespace rockslice {
namespace {

// Thrown by the progress callback once the caller asked the work to stop: the library lets it
// through (it reaches run_interruptible like any exception of the work), nobody else sees it.
struct Stopped {};

struct Shared {
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  bool stop = false;
  // The latest progress report, and whether the callback has not had it yet.
  std::string stage;
  std::size_t count = 0, total = 0;
  bool fresh = false;
};

}  // namespace

const char* to_string(Stage s) {
  switch (s) {
    case Stage::joints:
      return "joints";
    case Stage::blocks:
      return "blocks";
    case Stage::pruned:
      return "pruned";
    case Stage::geometry:
      return "geometry";
  }
  return "?";
}

void run_interruptible(const std::function<void(const slice::Progress&)>& work,
                       const py::object& callback) {
  Shared sh;
  const slice::Progress progress = [&sh](std::string_view stage, std::size_t n, std::size_t total) {
    const std::lock_guard lock(sh.mutex);
    if (sh.stop) throw Stopped{};
    sh.stage = stage;
    sh.count = n;
    sh.total = total;
    sh.fresh = true;
  };
  std::exception_ptr failure;
  std::thread worker([&] {
    try {
      work(progress);
    } catch (...) {
      failure = std::current_exception();
    }
    const std::lock_guard lock(sh.mutex);
    sh.done = true;
    sh.done_cv.notify_all();
  });
  // What this thread raises once the work has stopped: Ctrl-C's KeyboardInterrupt, or whatever
  // the callback raised (the worker must be joined before anything leaves this function).
  std::exception_ptr raised;
  const auto hand_over = [&](bool last) {
    std::string stage;
    std::size_t n = 0, total = 0;
    {
      const std::lock_guard lock(sh.mutex);
      if (!sh.fresh) return;
      sh.fresh = false;
      stage = sh.stage;
      n = sh.count;
      total = sh.total;
    }
    if (callback.is_none() || (raised && !last)) return;
    callback(stage, n, total);
  };
  for (bool done = false; !done;) {
    {
      py::gil_scoped_release unlocked;
      std::unique_lock lock(sh.mutex);
      done = sh.done_cv.wait_for(lock, std::chrono::milliseconds(50), [&] { return sh.done; });
    }
    if (done || raised) continue;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      hand_over(false);
    } catch (...) {
      raised = std::current_exception();
      const std::lock_guard lock(sh.mutex);
      sh.stop = true;
    }
  }
  {
    py::gil_scoped_release unlocked;
    worker.join();
  }
  if (raised) std::rethrow_exception(raised);
  if (failure) std::rethrow_exception(failure);
  hand_over(true);  // the last report, if the callback has not had it
}

py::str text(const std::string& s) {
  PyObject* u = PyUnicode_DecodeUTF8(s.data(), Py_ssize_t(s.size()), "backslashreplace");
  if (!u) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(u);
}

void raise(PyObject* type, const std::string& line) {
  PyErr_SetObject(type, text(line).ptr());
  throw py::error_already_set();
}

namespace {
std::string repr_of(const py::handle& v) {
  std::string r = py::repr(v).cast<std::string>();  // repr escapes surrogates: always UTF-8
  return r.size() > 60 ? r.substr(0, 57) + "..." : r;
}
std::string type_of(const py::handle& v) {
  return py::str(py::type::handle_of(v).attr("__name__")).cast<std::string>();
}
}  // namespace

double number_arg(const py::handle& v, const std::string& name) {
  if (!PyNumber_Check(v.ptr()) || PyBool_Check(v.ptr()))
    throw py::type_error(name + " is a number, not " + type_of(v));
  const double x = PyFloat_AsDouble(v.ptr());  // ints and numpy scalars too
  if (x == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();  // OverflowError: an int past 1.8e308
    throw slice::Error(name, repr_of(v) + " is too large for a double",
                       "give a number of magnitude below 1.8e308");
  }
  return x;
}

std::int64_t whole_arg(const py::handle& v, const std::string& name) {
  if (PyBool_Check(v.ptr()) || !PyIndex_Check(v.ptr()))
    throw py::type_error(name + " is an integer, not " + type_of(v));
  const py::object i = py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()));
  if (!i) throw py::error_already_set();
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow != 0)
    throw slice::Error(name, repr_of(v) + " is out of range",
                       "give an integer from -2^63 to 2^63 - 1");
  if (x == -1 && PyErr_Occurred()) throw py::error_already_set();
  return x;
}

std::string text_arg(const py::handle& v, const std::string& name) {
  if (!PyUnicode_Check(v.ptr())) throw py::type_error(name + " is a str, not " + type_of(v));
  Py_ssize_t size = 0;
  const char* utf8 = PyUnicode_AsUTF8AndSize(v.ptr(), &size);
  if (!utf8) {  // a lone surrogate ('\udc80', as os.fsdecode makes of a byte that is no UTF-8)
    PyErr_Clear();
    throw slice::Error(name, repr_of(v) + " holds a lone surrogate, which is no text",
                       "give valid Unicode text");
  }
  return std::string(utf8, std::size_t(size));
}

slice::Provenance python_provenance(const std::string& call, const std::string& input,
                                    const std::string& sha256) {
  return {"rockslice (Python)", slice::version(), call, input, sha256};
}

}  // namespace rockslice
