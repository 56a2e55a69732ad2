// Datasets (batch.h, docs/batch.md) for the Python module: a checked batch spec
// (ringlet.BatchSpec), one item resolved (resolve_batch_item) or made and written into a dataset
// directory exactly as `ringlet batch` makes it (run_batch_item: same files, same bytes, GIL
// released), and the manifest's locked append. The Dask engine (python/ringlet/batch.py) is
// built on these; bindings only: every byte is RunBatchItem / WriteBatchItem's.
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "bindings.h"
#include "ringlet/atomic_file.h"
#include "ringlet/batch.h"

namespace ringlet::python {

namespace {

// A JSON value as the equivalent Python object (json.loads of its text).
py::object FromJson(const nlohmann::json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

void CheckIndex(const BatchSpec& spec, long long index) {
  if (index < 0 || index >= spec.count) {
    throw Error("index: expected an item of the spec, in [0, " + std::to_string(spec.count) +
                "), got " + std::to_string(index));
  }
}

// The status recorded in a finished item's metadata.json ("done" or "flagged"; "done" when it
// cannot be read: the `done` marker is the truth about the item being finished).
BatchItemResult::Status RecordedStatus(const std::string& outdir, const std::string& name) {
  std::string text, ignored;
  const std::string path = (std::filesystem::path(outdir) / name / "metadata.json").string();
  if (ReadFile(path, &text, &ignored)) {
    const nlohmann::json metadata = nlohmann::json::parse(text, nullptr, false);
    if (metadata.is_object() && metadata.contains("status") && metadata["status"] == "flagged") {
      return BatchItemResult::Status::kFlagged;
    }
  }
  return BatchItemResult::Status::kDone;
}

}  // namespace

void BindBatch(py::module_& m) {
  py::class_<BatchSpec, std::shared_ptr<BatchSpec>>(
      m, "BatchSpec",
      "A checked batch spec (docs/batch.md): its bases, distributions, operations, views and "
      "outputs. BatchSpec(path) reads and checks the file as `ringlet batch` does (every base "
      "read once, every distribution's extremes tried); a bad spec raises ringlet.Error with the "
      "command's one line naming the field. Immutable; share it between calls.")
      .def(py::init([](const std::string& path) {
             auto spec = std::make_shared<BatchSpec>();
             std::string error;
             bool ok = false;
             {
               py::gil_scoped_release release;  // reading a head mesh takes seconds
               ok = LoadBatchSpec(path, spec.get(), &error);
             }
             if (!ok) throw Error(error);
             return spec;
           }),
           py::arg("path"))
      .def_property_readonly(
          "path", [](const BatchSpec& s) { return s.path; }, "The spec file (as given)")
      .def_property_readonly(
          "count", [](const BatchSpec& s) { return s.count; }, "The items: 0 to count - 1")
      .def_property_readonly(
          "seed", [](const BatchSpec& s) { return s.seed; },
          "The seed of every item's random streams")
      .def_property_readonly(
          "base_names", [](const BatchSpec& s) { return s.base_names; },
          "The base hairstyles as named in the spec")
      .def_property_readonly(
          "views", [](const BatchSpec& s) { return s.views.size(); },
          "The number of views (images per item and label kind)")
      .def("__repr__", [](const BatchSpec& s) {
        return "<ringlet.BatchSpec " + s.path + ": " + std::to_string(s.count) + " items, " +
               std::to_string(s.bases.size()) + " bases, " + std::to_string(s.views.size()) +
               " views>";
      });

  m.def(
      "batch_item_name",
      [](long long index) {
        if (index < 0 || index >= kMaxBatchItems) {
          throw Error("index: expected an integer in [0, " + std::to_string(kMaxBatchItems) +
                      "), got " + std::to_string(index));
        }
        return BatchItemName(index);
      },
      py::arg("index"),
      "The folder name of item `index`: \"item-000000007\" (9 digits, names sort like indices).");

  m.def("batch_item_done", &BatchItemDone, py::arg("outdir"), py::arg("name"),
        "Whether outdir/NAME/done exists: the item is finished (its folder is complete).");

  m.def(
      "resolve_batch_item",
      [](const BatchSpec& spec, long long index) {
        CheckIndex(spec, index);
        const BatchItem item = ResolveBatchItem(spec, index);
        py::dict d;
        d["item"] = item.index;
        d["name"] = item.name;
        d["base"] = item.base;
        d["parameters"] = FromJson(item.parameters);
        d["hairstyle"] = FromJson(item.hairstyle);
        return d;
      },
      py::arg("spec"), py::arg("index"),
      "Item `index` of the spec, resolved (a pure function of the spec and the index): a dict "
      "with item, name, base, parameters (the drawn values and operations, as `ringlet batch "
      "--plan` prints them) and hairstyle (the item's hairstyle document).");

  m.def(
      "run_batch_item",
      [](const BatchSpec& spec, const std::string& outdir, long long index, long long threads) {
        CheckIndex(spec, index);
        CheckThreads(threads);
        const std::string name = BatchItemName(index);
        const auto start = std::chrono::steady_clock::now();
        const BatchItem item = ResolveBatchItem(spec, index);
        BatchItemResult result;
        bool skipped = false;
        std::string error;
        if (BatchItemDone(outdir, name)) {
          skipped = true;
        } else {
          std::atomic<bool> cancel{false};
          RunInterruptibly(
              [&] {
                result = RunBatchItem(spec, item, static_cast<int>(threads), &cancel);
                if (cancel.load()) return;  // abandoned (Ctrl-C): nothing is written
                if (result.status == BatchItemResult::Status::kFailed) return;
                const int written = WriteBatchItem(outdir, item, result, &error);
                if (written == 0) skipped = true;  // another process finished it meanwhile
                if (written < 0) {
                  result.status = BatchItemResult::Status::kFailed;
                  result.error = error;
                }
              },
              &cancel);
        }
        if (skipped) {
          result = BatchItemResult{};
          result.status = RecordedStatus(outdir, name);
        }
        py::dict d;
        d["item"] = item.index;
        d["name"] = name;
        d["base"] = item.base;
        d["status"] = skipped ? "skipped" : BatchStatusName(result.status);
        d["recorded_status"] = BatchStatusName(result.status);
        d["error"] = result.status == BatchItemResult::Status::kFailed
                         ? py::object(py::str(result.error))
                         : py::object(py::none());
        d["manifest_line"] = BatchManifestLine(item, result);
        d["timing"] = skipped ? py::object(py::none()) : FromJson(result.timing);
        d["seconds"] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return d;
      },
      py::arg("spec"), py::arg("outdir"), py::arg("index"), py::arg("threads") = 0,
      "Makes item `index` of the spec into outdir as `ringlet batch` does (docs/batch.md): the "
      "same files, byte for byte, written all or nothing (a temporary folder renamed into place, "
      "`done` last); an item already done is not made again. Releases the GIL; Ctrl-C abandons "
      "the item (nothing of it is written) and raises KeyboardInterrupt. threads: per item (0 = "
      "all cores; the bytes do not depend on it). outdir must exist (run_batch_item records "
      "neither spec.json nor a manifest line). Returns a dict: item, name, base, status (\"done\", "
      "\"flagged\", \"failed\" or \"skipped\": done before, or by another process meanwhile), "
      "recorded_status (a skipped item's status from its metadata.json; otherwise status), "
      "error (a failed item's one line, else None), manifest_line (the line `ringlet batch` "
      "appends for it, with recorded_status), timing (timing.json's wall times, None when "
      "skipped) and seconds (this call's wall time).");

  m.def(
      "append_manifest_line",
      [](const std::string& path, const std::string& line) {
        if (line.find('\n') != std::string::npos) {
          throw Error("line: expected one line (no newline), got " + std::to_string(line.size()) +
                      " characters with a newline");
        }
        std::string error;
        bool ok = false;
        {
          py::gil_scoped_release release;
          ok = AppendManifestLine(path, line, &error);
        }
        if (!ok) throw Error(error);
      },
      py::arg("path"), py::arg("line"),
      "Appends line + newline to a manifest file with one write() under an exclusive flock(), "
      "as `ringlet batch` does: lines of processes appending at once never interleave.");
}

}  // namespace ringlet::python
