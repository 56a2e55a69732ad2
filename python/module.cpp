// The Python module `ringlet` (docs/python.md): pybind11 bindings of the library, numpy in and
// out, names as in the C++ API (functions in snake_case). This file: the module, ringlet.Error,
// JSON conversion and the interruptible runner shared by the parts.
#include <Python.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <mutex>
#include <thread>

#include "bindings.h"
#include "io/json_reader.h"

namespace ringlet::python {

namespace {
// The Python type of ringlet.Error, created once by RegisterError (a new reference that lives
// as long as the interpreter).
PyObject* error_type = nullptr;
}  // namespace

void RegisterError(py::module_& m) {
  py::tuple bases = py::make_tuple(py::handle(PyExc_ValueError), py::handle(PyExc_RuntimeError));
  error_type = PyErr_NewExceptionWithDoc(
      "ringlet.Error",
      "Bad input or a failed operation: the message is the library's one line naming the field "
      "and what was expected (the same line the ringlet command prints). A subclass of both "
      "ValueError and RuntimeError.",
      bases.ptr(), nullptr);
  if (!error_type) throw py::error_already_set();
  m.attr("Error") = py::handle(error_type);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      PyErr_SetString(error_type, e.what());
    }
  });
}

namespace {

// ToJson below `depth` containers (the top level is 1), `ancestors` being the containers on the
// way down (a container met again is a circular reference).
nlohmann::json ToJsonAt(py::handle value, const std::string& where, int depth,
                        std::vector<PyObject*>* ancestors) {
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) {
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow == 0) return v;
    if (overflow > 0) {
      const unsigned long long u = PyLong_AsUnsignedLongLong(value.ptr());
      if (!PyErr_Occurred()) return u;
      PyErr_Clear();
    }
    return value.cast<double>();  // beyond 64 bits: a (huge) number, rejected by range checks
  }
  if (py::isinstance<py::float_>(value)) {
    // A JSON file cannot hold NaN or infinity; nlohmann would keep the double, and the readers
    // would quote it as null ("got null"). Said here instead, naming the field.
    const double x = value.cast<double>();
    if (!std::isfinite(x)) {
      throw Error(where + ": expected a finite number (JSON has no NaN or infinity), got " +
                  std::string(py::repr(value)));
    }
    return x;
  }
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  const bool is_dict = py::isinstance<py::dict>(value);
  if (is_dict || py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    // The file readers' limits (json_reader.h): a dict holding itself, or nested deeper than a
    // file may be, is refused before the recursion goes on (it used to overflow the stack).
    for (PyObject* ancestor : *ancestors) {
      if (ancestor == value.ptr()) {
        throw Error(internal::Truncate(where, internal::kMaxShownPath) +
                    ": expected a JSON-like value, got a circular reference (a container "
                    "holding itself)");
      }
    }
    if (depth > internal::kMaxJsonDepth) {
      throw Error(internal::Truncate(where, internal::kMaxShownPath) +
                  ": expected at most " + std::to_string(internal::kMaxJsonDepth) +
                  " levels of nested dicts and lists (the limit of JSON files), got deeper");
    }
    ancestors->push_back(value.ptr());
    nlohmann::json result;
    if (is_dict) {
      result = nlohmann::json::object();
      for (auto item : value.cast<py::dict>()) {
        if (!py::isinstance<py::str>(item.first)) {
          throw Error(where + ": expected string keys, got " +
                      internal::Truncate(std::string(py::str(py::repr(item.first))),
                                         internal::kMaxShownCharacters));
        }
        const std::string key = item.first.cast<std::string>();
        result[key] = ToJsonAt(item.second, internal::Member(where, key), depth + 1, ancestors);
      }
    } else {
      result = nlohmann::json::array();
      size_t i = 0;
      for (auto item : value) {
        result.push_back(ToJsonAt(item, internal::Element(where, i), depth + 1, ancestors));
        ++i;
      }
    }
    ancestors->pop_back();
    return result;
  }
  // numpy arrays and scalars (np.int64 is not an int): their Python equivalent, at the same
  // depth (an array's tolist() is the container standing for it).
  if (py::hasattr(value, "tolist")) {
    py::object plain = value.attr("tolist")();
    if (plain.ptr() != value.ptr() && !py::hasattr(plain, "tolist")) {
      return ToJsonAt(plain, where, depth, ancestors);
    }
  }
  throw Error(where + ": expected a JSON-like value (dict, list, str, number, bool or None), "
              "got " + std::string(py::str(value.get_type().attr("__name__"))));
}

}  // namespace

nlohmann::json ToJson(py::handle value, const std::string& where) {
  std::vector<PyObject*> ancestors;
  return ToJsonAt(value, where, 1, &ancestors);
}

void RequireNumber(bool ok, double value, const std::string& field, const char* expected) {
  if (ok && std::isfinite(value)) return;
  throw Error(field + ": expected " + expected + ", got " +
              std::string(py::repr(py::float_(value))));
}

std::string AbsoluteDirectory(const std::string& directory) {
  std::error_code ignored;
  const std::filesystem::path absolute =
      std::filesystem::absolute(directory.empty() ? "." : directory, ignored);
  return absolute.lexically_normal().string();
}

py::array RealArray(const py::handle& value, const std::string& field, const char* expected) {
  py::array a = py::module_::import("numpy").attr("asarray")(value);
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u' && kind != 'f') {
    throw Error(field + ": expected " + expected + ", got an array of dtype " +
                std::string(py::str(a.dtype())));
  }
  return a;
}

void CheckThreads(long long threads) {
  if (threads < 0 || threads > kMaxThreads) {
    throw Error("threads: expected an integer in [0, " + std::to_string(kMaxThreads) +
                "] (0 = all cores), got " + std::to_string(threads));
  }
}

void RunInterruptibly(const std::function<void()>& work, std::atomic<bool>* cancel,
                      const std::function<void()>& on_tick) {
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        work();
      } catch (...) {
        failure = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_all();
    });
    std::unique_lock<std::mutex> lock(mutex);
    while (!finished.wait_for(lock, std::chrono::milliseconds(20), [&] { return done; })) {
      if (interrupted) continue;
      lock.unlock();
      {
        py::gil_scoped_acquire gil;
        // Runs the Python signal handlers (this is the main thread when called from it); the
        // KeyboardInterrupt stays set in this thread state until re-raised below.
        interrupted = PyErr_CheckSignals() != 0;
        if (!interrupted && on_tick) {
          try {
            on_tick();
          } catch (py::error_already_set& e) {
            e.restore();  // raised again below, as a signal handler's exception would be
            interrupted = true;
          }
        }
      }
      if (interrupted) cancel->store(true);
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  if (failure) std::rethrow_exception(failure);
  if (on_tick) on_tick();  // the final report, so that short work reports once too
}

BatchProgress::BatchProgress(py::object callback, const char* field)
    : callback_(std::move(callback)) {
  if (!callback_.is_none() && !PyCallable_Check(callback_.ptr())) {
    throw Error(std::string(field) + ": expected None or a callable progress(done, total), got " +
                std::string(py::str(callback_.get_type().attr("__name__"))));
  }
}

std::function<void(int, int)> BatchProgress::Reporter() {
  if (callback_.is_none()) return {};
  return [this](int finished, int total) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished <= last_) {  // a new phase: its count starts again
      offset_ = total_;
    }
    last_ = finished;
    done_ = offset_ + finished;
    total_ = offset_ + total;
  };
}

std::function<void()> BatchProgress::Tick() {
  if (callback_.is_none()) return {};
  return [this] {
    int done = 0, total = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done = done_;
      total = total_;
    }
    if (total == 0 || (done == reported_done_ && total == reported_total_)) return;
    reported_done_ = done;
    reported_total_ = total;
    callback_(done, total);
  };
}

}  // namespace ringlet::python

PYBIND11_MODULE(_ringlet, m) {
  using namespace ringlet::python;
  m.doc() =
      "ringlet: hair shapes from the statics of Kirchhoff rods (Bertails et al. 2005). Solve "
      "strands, groom and style hairstyles, read and write hair files and render, with numpy "
      "arrays in SI units (metres, seconds, kilograms). See docs/python.md.";
  RegisterError(m);
  BindSolve(m);
  BindHair(m);
  BindRender(m);
  BindInverse(m);
  BindBody(m);
  BindEnergy(m);
  BindBatch(m);
  BindSimulate(m);
  BindValues(m);
}
