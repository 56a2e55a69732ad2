// Shared helpers of the Python module `ringlet` (docs/python.md): the ringlet.Error exception,
// JSON-like Python objects -> nlohmann::json, numpy views on C++ storage, and running long work
// with the GIL released and Ctrl-C honoured. Bindings only: no physics here.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ringlet::python {

namespace py = pybind11;

/// The C++ side of ringlet.Error: carries the library's one-line message.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// The most worker threads a call may ask for: the commands' --threads limit (CLI::Range(0,
/// 1024) in cli/*_command.cpp). TBB's arena with 10^5 threads crashed the interpreter.
inline constexpr int kMaxThreads = 1024;

/// Raises ringlet.Error unless 0 <= threads <= kMaxThreads ("threads: expected ...").
void CheckThreads(long long threads);

/// Raises ringlet.Error "field: expected EXPECTED, got VALUE" (the file readers' wording, value
/// as Python prints it) unless ok and value is finite.
void RequireNumber(bool ok, double value, const std::string& field, const char* expected);

/// The absolute, normalized form of a directory ("" is the working directory).
std::string AbsoluteDirectory(const std::string& directory);

/// value as a numpy array of real numbers (integers or floats; not bool, complex, strings or
/// objects, which numpy's casts would turn into numbers silently); otherwise ringlet.Error
/// "field: expected EXPECTED, got an array of dtype D".
py::array RealArray(const py::handle& value, const std::string& field, const char* expected);

/// Registers ringlet.Error (a subclass of ValueError and RuntimeError) and its translator.
void RegisterError(py::module_& m);

/// A JSON-like Python value (dict with str keys, list, tuple, str, int, float, bool, None, numpy
/// arrays and scalars) as JSON. `where` names the value in errors ("scene").
nlohmann::json ToJson(py::handle value, const std::string& where);

/// Runs work() on a worker thread while the calling (Python) thread waits with the GIL released,
/// checking for signals every 20 ms. On Ctrl-C (any exception from a signal handler) sets
/// *cancel, waits for the worker to stop and re-raises the Python exception (KeyboardInterrupt).
/// An exception thrown by work() is re-thrown in the calling thread. on_tick, when given, is
/// called with the GIL held on each 20-ms check and once after work() succeeded (progress
/// callbacks); an exception it raises cancels like Ctrl-C and is re-raised.
void RunInterruptibly(const std::function<void()>& work, std::atomic<bool>* cancel,
                      const std::function<void()>& on_tick = {});

/// A Python callback progress(done, total) fed by a library ProgressCallback (solve_strands.h):
/// Reporter() is called from worker threads and only stores the counts; Tick(), for
/// RunInterruptibly's on_tick (the waiting thread, with the GIL), calls the Python callable with
/// them when they changed since its last call. Work in phases (a groom's masters, then its
/// solved children: each phase's count starts again at 1) is reported as one count: done never
/// decreases, total grows by each new phase's total when it starts.
class BatchProgress {
 public:
  /// callback: None (no reports) or a callable; anything else raises ringlet.Error naming
  /// `field`.
  BatchProgress(py::object callback, const char* field);
  /// The library's callback (empty without a Python callback).
  std::function<void(int, int)> Reporter();
  /// The on_tick of RunInterruptibly (empty without a Python callback).
  std::function<void()> Tick();

 private:
  py::object callback_;
  std::mutex mutex_;
  int offset_ = 0;      // the totals of the finished phases
  int last_ = 0;        // the last count of the current phase
  int done_ = 0;        // offset_ + last_
  int total_ = 0;       // offset_ + the current phase's total
  int reported_done_ = -1, reported_total_ = -1;  // what the callback was last given
};

/// A numpy array viewing `data` (no copy) with the given shape and strides (bytes), kept alive
/// by `owner` (the Python object owning the storage). Read-only unless writable.
template <class T>
py::array View(const T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
               py::handle owner, bool writable) {
  py::array array(py::dtype::of<T>(), std::move(shape), std::move(strides), data, owner);
  if (!writable) array.attr("flags").attr("writeable") = false;
  return array;
}

/// A numpy array taking ownership of the vector's storage (no copy), shape as given (the
/// product must equal the size times `per_item` scalars).
template <class T>
py::array OwnedArray(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t stride = sizeof(T);
  for (size_t i = shape.size(); i-- > 0;) {
    strides[i] = stride;
    stride *= shape[i];
  }
  return py::array(py::dtype::of<T>(), std::move(shape), std::move(strides), owned->data(),
                   owner);
}

/// The immutable object parsed from a document text (relative paths from base_directory): the
/// one still alive in this process that was made from the same text and directory, else make()
/// (which may throw ringlet.Error; a failure caches nothing). Objects that are costly to parse
/// and never change after (a mesh body's distance grid takes seconds; a hairstyle parses its
/// body) are so shared by every value that holds them, e.g. by a worker unpickling one per task.
/// The cache holds weak pointers: an object lives as long as its holders. One cache per T.
template <typename T, typename Make>
std::shared_ptr<const T> SharedWhileAlive(const std::string& text,
                                          const std::string& base_directory, Make&& make) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::string>, std::weak_ptr<const T>> alive;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto key = std::make_pair(text, base_directory);
  if (const auto it = alive.find(key); it != alive.end()) {
    if (auto shared = it->second.lock()) return shared;
    alive.erase(it);
  }
  for (auto it = alive.begin(); it != alive.end();) {  // forget the dead ones
    it = it->second.expired() ? alive.erase(it) : std::next(it);
  }
  std::shared_ptr<const T> made = make();
  alive[key] = made;
  return made;
}

/// The module's parts, one per file.
void BindSolve(py::module_& m);
void BindHair(py::module_& m);
void BindRender(py::module_& m);
void BindInverse(py::module_& m);  // after BindSolve (it extends StrandModel)
void BindBody(py::module_& m);
void BindEnergy(py::module_& m);  // after BindSolve (its EnergyTerms)
void BindBatch(py::module_& m);  // datasets (batch.h): one item at a time, for the engines
void BindSimulate(py::module_& m);  // after BindHair (its Groom and Hairstyle)
/// Pickling, copy.copy/deepcopy and repr of the values (after the others: extends their classes).
void BindValues(py::module_& m);

}  // namespace ringlet::python
