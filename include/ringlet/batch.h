// Datasets of grooms (docs/batch.md, `ringlet batch`): a spec of base hairstyles, distributions
// over their fields and over styling operations, views and outputs; items that are pure
// functions of (spec, index), so that any engine can run any item, anywhere, any number of
// times, with the same bytes; and the bookkeeping of an output directory (one folder per item,
// written all or nothing, a `done` marker, manifest lines).
//
// Engines (the `ringlet batch` command, a Slurm job array, Dask) only choose which item
// indices to run: BatchItemRange / ShardRange, then RunBatchItem and WriteBatchItem per item.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/hair_curves.h"

namespace ringlet {

/// Most items of a spec (10^9: item folders are named with 9 digits).
inline constexpr std::int64_t kMaxBatchItems = 1000000000;

/// A distribution over one value (docs/batch.md, "Distributions").
struct BatchDistribution {
  enum class Kind : std::uint8_t {
    kChoice,   ///< one of `choices`, each with probability 1/n
    kUniform,  ///< uniform in [low, high) (integers: each of low..high with probability 1/n)
    kNormal,   ///< normal(mean, sd) restricted to [low, high] by rejection
  };
  Kind kind = Kind::kChoice;
  std::vector<nlohmann::json> choices;
  double low = 0.0, high = 0.0;  ///< bounds (uniform, normal)
  double mean = 0.0, sd = 0.0;   ///< normal
  bool integer = false;          ///< draws integers (integer fields: counts, seeds)
};

/// A hairstyle field varied per item: its dot path in the hairstyle document ("hair.curl_radius",
/// "hair.length.front", "render.hair.eumelanin") and its distribution.
struct BatchParameter {
  std::string path;
  BatchDistribution distribution;
};

/// A styling operation added to an item with a probability; any number in its object may be a
/// distribution ({"uniform": [a, b]}, {"normal": {...}}, {"choice": [...]}).
struct BatchOperation {
  double probability = 1.0;
  std::string name;      ///< "curl", "wet", "dry", "cut" or "grow"
  nlohmann::json templ;  ///< the operation's object, distributions in place
  /// The distributions inside templ, by JSON pointer ("/length"), in document order.
  std::vector<std::pair<std::string, BatchDistribution>> distributions;
};

/// The outputs of every item.
struct BatchOutputs {
  bool hair = true;   ///< strands.hair (Yuksel's .hair, metres)
  bool usda = false;  ///< strands.usda (USD BasisCurves)
  bool data = false;  ///< strands.data (USC-HairSalon: metres, y up)
  /// Points per written strand, equally spaced in arc length (0: the groom's own points).
  int points_per_strand = 0;
  /// Images per view: the path-traced picture (rgb_VV.png) and, with labels, the hair mask
  /// (mask_VV.png), the strand orientation map (orientation_VV.png) and the depth (depth_VV.npy).
  bool images = false;
  bool labels = true;
  int width = 64, height = 64, samples_per_pixel = 4;
};

/// A parsed, checked batch spec.
struct BatchSpec {
  std::string path;       ///< the spec file (for messages)
  std::string directory;  ///< relative paths of inline bodies are relative to it
  /// The base hairstyles as documents, with their relative file paths (body, masters.file)
  /// made absolute, so that an item's hairstyle.json grooms from anywhere.
  std::vector<nlohmann::json> bases;
  std::vector<std::string> base_names;  ///< as given in the spec ("bases[1]" when inline)
  std::vector<BatchParameter> parameters;
  std::vector<BatchOperation> operations;
  std::int64_t count = 1;
  std::uint64_t seed = 0;
  /// Each item gets its own masters.seed, hair.seed and render.seed from (seed, index), unless
  /// the spec says "item_seeds": false or a parameter sets them.
  bool item_seeds = true;
  /// Each base's body, read once when the spec is checked and shared by its items (the items
  /// do not vary the body).
  std::vector<std::shared_ptr<const Body>> bodies;
  /// The views: each a render "camera" object (docs/hairstyle-format.md, "render").
  std::vector<nlohmann::json> views;
  BatchOutputs outputs;
};

/// Parses and checks a spec document field by field; relative paths are relative to
/// base_directory. Every distribution's extremes are tried on every base (ParseHairstyle), so
/// that a value no item could use is found now: one line naming the field into *error. Never
/// throws.
bool ParseBatchSpec(const nlohmann::json& document, const std::string& base_directory,
                    BatchSpec* spec, std::string* error);

/// Reads and parses a spec file; every message starts with the path. Never throws.
bool LoadBatchSpec(const std::string& path, BatchSpec* spec, std::string* error);

/// One item, resolved: a pure function of (spec, index).
struct BatchItem {
  std::int64_t index = 0;
  std::string name;           ///< "item-000000007" (BatchItemName)
  int base = 0;               ///< which base hairstyle
  nlohmann::json parameters;  ///< {"path": value, ...} and "operations": [...]
  nlohmann::json hairstyle;   ///< the resolved hairstyle document
};

/// "item-000000007": 9 digits, so that names sort like indices.
std::string BatchItemName(std::int64_t index);

/// Item `index` of the spec: every random number comes from a counter-based stream seeded by
/// (spec.seed, index) only (groom/random.h, StreamSeed), never from the order items are run in.
BatchItem ResolveBatchItem(const BatchSpec& spec, std::int64_t index);

/// What running an item gave.
struct BatchItemResult {
  enum class Status : std::uint8_t { kDone, kFlagged, kFailed };
  Status status = Status::kFailed;
  std::string error;  ///< kFailed: one line
  /// The item folder's files, (name, contents), deterministic: hairstyle.json, strands.*,
  /// images, metadata.json. Written by WriteBatchItem with timing.json and done.
  std::vector<std::pair<std::string, std::string>> files;
  /// The only non-deterministic file: wall times (s) of the groom, operations, render, total.
  nlohmann::json timing;
};

/// "done", "flagged", "failed".
const char* BatchStatusName(BatchItemResult::Status status);

/// Grooms the item's hairstyle, applies its operations (as `ringlet style`), writes its strands
/// and renders its views, all in memory. threads: 0 = all cores (the bytes do not depend on it).
/// cancel (may be null): once set, returns kFailed with error "cancelled" early. Never throws.
BatchItemResult RunBatchItem(const BatchSpec& spec, const BatchItem& item, int threads,
                             const std::atomic<bool>* cancel);

/// Each strand resampled to n >= 2 points equally spaced in arc length along its polyline (the
/// outputs' points_per_strand): positions and widths interpolated linearly in double and rounded
/// to float, the first and last points kept; colours and wetness kept, major axes dropped (no
/// file format stores them).
HairCurves ResampleStrands(const HairCurves& curves, int n);

/// Whether outdir/NAME/done exists (the item is finished).
bool BatchItemDone(const std::string& outdir, const std::string& name);

/// Writes the item folder all or nothing: its files, timing.json and last `done` into a
/// temporary folder outdir/.NAME.tmp.HOST.PID, then renamed to outdir/NAME. Returns 1 when
/// written, 0 when the folder appeared meanwhile with its `done` (another process finished the
/// same item: the temporary is removed), -1 with one line in *error on failure, or when a folder
/// without `done` is in the way (nothing is left behind).
int WriteBatchItem(const std::string& outdir, const BatchItem& item, const BatchItemResult& result,
                   std::string* error);

/// One manifest line (JSON, no newline): {"item", "name", "base", "status"[, "error"]};
/// deterministic (no times).
std::string BatchManifestLine(const BatchItem& item, const BatchItemResult& result);

/// Appends line + "\n" to path with one write() under an exclusive flock(), so that lines of
/// processes writing the same file at once never interleave. False with one line in *error.
bool AppendManifestLine(const std::string& path, const std::string& line, std::string* error);

/// The items [begin, end) of a run.
struct BatchRange {
  std::int64_t begin = 0, end = 0;
};

/// "A:B" -> [A, B) within [0, count]; false with one line for bad text or bounds.
bool ParseItemRange(const std::string& text, std::int64_t count, BatchRange* range,
                    std::string* error);
/// "K/N" -> shard K (0-based) of N; false with one line.
bool ParseShard(const std::string& text, int* k, int* n, std::string* error);
/// Shard k of n of range: the contiguous block [begin + floor(k L / n), begin + floor((k+1) L /
/// n)).
BatchRange ShardRange(const BatchRange& range, int k, int n);

}  // namespace ringlet
