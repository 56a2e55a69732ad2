// The studio's editing model, without GL (STYLE.md: view state apart from the model, the edit
// logic testable without a window): a hairstyle document (its parameters as JSON plus the
// `operations` list that `ringlet style` reads), the hair computed from it, an undo / redo
// history of edits, and a worker thread that re-solves after each edit.
//
// Edits and their re-solves:
//  - an operation (curl, wet, dry, cut, grow; curl optionally on a brushed set of masters) is
//    appended to the list and applied to the current styled hair, warm-started from its
//    equilibrium: exactly the step `ringlet style` takes for that list entry, so a saved file
//    reproduces the studio's hair bit for bit;
//  - a parameter change (a field of the hairstyle JSON, e.g. "hair.length") rebuilds the
//    masters; masters whose model did not change keep their solution (SolveStrand is
//    deterministic, so re-solving them would give the same bits), the others are solved from the
//    natural shape as `ringlet groom` does, and the operations are replayed.
// A newer edit cancels a stale solve (BatchOptions::cancel, checked between blocks of masters).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "ringlet/hairstyle.h"
#include "ringlet/styling.h"

namespace ringlet::studio {

/// What the solve of one edit did (the panel's "result" line).
struct SolveStats {
  std::string what;            ///< "groom", "curl", "wet", ... (the last step of the edit)
  int masters = 0;             ///< masters in the hair
  int resolved = 0;            ///< master solves made by this edit (a master solved by the
                               ///< groom and again by an operation counts twice)
  int reused = 0;              ///< masters whose unchanged solution was kept (parameter edits)
  long iterations = 0;         ///< minimizer iterations of this edit
  int unconverged = 0;         ///< masters of the hair whose last solve did not converge
  int unstable = 0;            ///< masters found unstable (when the stability check ran)
  double max_penetration = 0;  ///< deepest master point below the body surface (m)
  double seconds = 0;          ///< wall time of the edit's solve and wisps (s)
  double solve_seconds = 0;    ///< of which the groom and operations' solves (s)
  double wisp_seconds = 0;     ///< of which growing the wisps (s)
  int regrown = -1;            ///< wisps regrown (-1: every wisp, grown from scratch)
  std::string message;         ///< the operations' one-line reports, joined
};

/// Per master: what the view colours.
enum class MasterStatus : std::uint8_t { kConverged = 0, kUnconverged = 1, kUnstable = 2 };

/// The hair of one history entry: the styled masters and the strands drawn.
struct HairState {
  /// The unstyled groom (masters and their solutions from the natural shape): what a parameter
  /// edit compares its new masters with.
  std::shared_ptr<const Groom> base;
  StyledHair styled;                          ///< after every operation of the entry
  std::shared_ptr<const HairCurves> strands;  ///< wisps of styled (StyledStrands)
  std::vector<MasterStatus> status;           ///< one per master
  SolveStats stats;
  /// A serial number of `strands` (unique in the process), and of the strands these were
  /// copied from when only the wisps of `regrown` masters were regrown (0 = grown from scratch):
  /// the view then uploads those wisps only.
  std::uint64_t strands_id = 0;
  std::uint64_t regrown_from = 0;
  std::vector<int> regrown;
};

/// A hairstyle document: the file's JSON without "operations", and the operations.
struct Document {
  nlohmann::ordered_json parameters;
  std::vector<StyleOperation> operations;
  std::string base_directory;  ///< relative paths in parameters are relative to it
};

/// The JSON of one operation as docs/hairstyle-format.md ("operations") writes it:
/// ParseStyleOperations reads it back to the same StyleOperation (numbers round-trip exactly).
nlohmann::ordered_json OperationToJson(const StyleOperation& operation);

/// The whole file: parameters plus "operations" (omitted when empty), with relative paths
/// ("body", body meshes) rewritten relative to `directory`.
nlohmann::ordered_json DocumentToJson(const Document& document, const std::string& directory);

/// A JSON value typed by a user ("0.3", "true", "[0, 0, -1]", "\"wavy\"", or a bare word like
/// wavy, taken as a string).
nlohmann::ordered_json ParseValue(const std::string& text);

/// The fields that set the hair's length, for the panel: "hair.length" when it is one number
/// (or absent), else one field per region of a regional length ("hair.length.front", ...,
/// docs/hairstyle-format.md), so that editing one region keeps the others.
std::vector<std::string> LengthFields(const nlohmann::ordered_json& parameters);

/// The editing session. All public functions are called from one (the UI) thread; the solve
/// runs on an internal worker thread.
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  /// Worker threads of the solves (0 = all cores).
  void SetThreads(int threads) { threads_ = threads; }
  /// The least time between two Preview() publications (s; 0.3 by default, 0 in tests).
  void SetPreviewSeconds(double seconds) { preview_seconds_ = seconds; }
  /// Called on the worker thread after each Preview() publication and each finished solve, so
  /// that a waiting UI wakes at once (the studio: glfwPostEmptyEvent). Set before the first edit.
  void SetWake(std::function<void()> wake) { wake_ui_ = std::move(wake); }
  /// Called on the worker thread with each Preview() publication as it is made (tests; set
  /// before the edit).
  void SetPreviewListener(std::function<void(const std::shared_ptr<const HairState>&)> listener) {
    preview_listener_ = std::move(listener);
  }

  /// A hairstyle file read and checked, its body built (Read), for Open: reading can run on
  /// another thread (the studio reads its file while the window opens; the head mesh's body
  /// takes seconds).
  struct File {
    std::string path;
    nlohmann::ordered_json json;
    std::shared_ptr<const Body> body;
    std::string error;  ///< not empty: the file does not open (the CLI's one-line message)
  };
  /// Reads and checks a hairstyle file (thread-safe: touches no session).
  static File Read(const std::string& path);
  /// Reads a hairstyle file (with its operations) and starts grooming it. A bad file returns
  /// false with the CLI's one-line message and keeps the current document, hair and history.
  bool Open(const std::string& path, std::string* error) { return Open(Read(path), error); }
  /// The same with a file read before (Read).
  bool Open(const File& file, std::string* error);
  /// The same from a JSON document in memory (relative paths against base_directory).
  bool OpenDocument(const nlohmann::ordered_json& json, const std::string& base_directory,
                    const std::string& name, std::string* error);

  /// Sets a field of the hairstyle ("hair.length", "comb.parting.offset", "wisps.jitter", ...;
  /// dots separate object keys) and re-solves. The new document is checked first
  /// (ParseHairstyle): a bad value returns false with the CLI's message and changes nothing.
  bool SetParameter(const std::string& field, const nlohmann::ordered_json& value,
                    std::string* error);
  /// The current value of a field (null when absent: the format's default applies).
  nlohmann::ordered_json Parameter(const std::string& field) const;

  /// Appends an operation and re-solves warm-started. Checked first (StyleOperation::IsValid,
  /// selection indices against the master count, dry only when wet): false with the message.
  bool AddOperation(const StyleOperation& operation, std::string* error);

  /// Undo / redo the last edit; false when there is none. The hair of an entry solved before
  /// is shown at once; otherwise it is re-solved.
  bool Undo();
  bool Redo();
  bool CanUndo() const { return cursor_ > 0; }
  bool CanRedo() const { return cursor_ + 1 < static_cast<int>(history_.size()); }

  /// Writes the current document (parameters and operations) atomically to path; `ringlet
  /// style path -o OUT/` then reproduces Hair() bit for bit. An existing file is replaced only
  /// when overwrite (and only a regular file). False with a message on failure.
  bool Save(const std::string& path, std::string* error, bool overwrite = true);

  /// Drops the document, the hair and the history: an empty session (the UI asks first when
  /// Modified()).
  void New();

  /// Called by the UI each frame: takes a finished solve, if any. True when Hair() changed.
  bool Poll();
  /// Blocks until the worker has finished every scheduled solve, then Poll()s.
  void Wait();
  /// Whether a solve is scheduled or running.
  bool Busy() const;
  /// Progress of the running solve: masters done and total (0, 0 when idle).
  void Progress(int* done, int* total, std::string* what) const;

  /// The hair shown: the last finished solve (null before the first one).
  std::shared_ptr<const HairState> Hair() const { return shown_; }
  /// While the current entry is solved (a freshly opened document, or an edit that takes longer
  /// than the preview period): the masters as solved so far, one polyline each (2 points per
  /// segment), published by the worker at most every 0.3 s (SetPreviewSeconds; the first one that
  /// long after the solve started): during the groom, after each block of masters (a master not
  /// solved yet keeps the shape it had in the hair shown before, or is a zero-length segment at
  /// its root when there was none); after each operation; and once every master is solved,
  /// while the wisps grow. Its masters, style and roots are the groom's or the styled hair's,
  /// stats.what "solving", stats.resolved the masters in their final shape for this solve.
  /// Null otherwise (and once the solve's hair is shown).
  std::shared_ptr<const HairState> Preview() const;
  /// The document of the current history entry.
  const Document& CurrentDocument() const { return history_[cursor_].document; }
  /// Whether Hair() is the solve of the current entry (false while it is being solved).
  bool UpToDate() const;
  /// The last error of a solve (an operation that failed on this hair), empty if none.
  std::string LastError() const;
  /// Labels of the history entries, oldest first, and the current index.
  std::vector<std::string> HistoryLabels() const;
  int HistoryCursor() const { return cursor_; }
  /// The file name of the document (Open's path), empty for a document from memory.
  const std::string& Path() const { return path_; }
  /// Solves cancelled while running or replaced before they started, since construction.
  int CancelledSolves() const { return cancelled_.load(); }
  /// Whether there are edits since the last Open or Save.
  bool Modified() const { return cursor_ != saved_cursor_; }

  /// Selection of masters for brushed operations (indices; empty = every master).
  std::vector<int> brush;

 private:
  struct Entry {
    Document document;
    std::string label;
    std::shared_ptr<const HairState> state;  // null until solved
  };
  // What the worker needs of a job, copied on the UI thread: the worker never reads history_.
  struct Candidate {
    Document document;
    std::shared_ptr<const HairState> state;
  };
  struct JobData {
    int entry = -1;
    std::uint64_t generation = 0;
    Document document;
    std::shared_ptr<const Body> body;  // the document's body when read before (CachedBody)
    std::vector<Candidate> solved;  // entries solved before, oldest first
    std::shared_ptr<std::atomic<bool>> cancel;
  };

  // The worker's publication of Preview(): at most every `seconds` (the first one `seconds` after
  // the job started, so that a quick edit publishes nothing), the masters' polylines.
  class PreviewPublisher {
   public:
    // eager: the first publication is due at once (a fresh file: nothing is on screen yet).
    PreviewPublisher(Session* session, std::uint64_t generation, double seconds, bool eager);
    // Whether a publication is due now.
    bool Due() const;
    // The masters of `masters`: shape(i, &points) fills master i's centreline (empty: a stub at
    // the root) and returns whether it is final for this job (then kept for later
    // publications, not asked again).
    template <class Shape>
    void Publish(const Hairstyle& style, const HairstyleMasters& masters, const Shape& shape);
    // Every master of a styled hair (its final shapes).
    void PublishStyled(const StyledHair& styled);

   private:
    void Send(const Hairstyle& style, const HairstyleMasters& masters);
    Session* session_;
    std::uint64_t generation_;
    double seconds_;
    bool eager_;
    std::chrono::steady_clock::time_point last_;
    std::vector<std::vector<Vec3f>> lines_;  // per master, the polyline of the last publication
    std::vector<char> final_;
  };

  void PushEntry(Document document, std::string label);
  // The body of these parameters when it was read before in this session (its "body" member and
  // base directory equal), else null; Remember keeps a body read for them. Reading the head
  // mesh's body builds its distance grid (about 1.7 s of CPU), which every edit, the worker's
  // parse and the open's two checks would otherwise repeat.
  std::shared_ptr<const Body> CachedBody(const nlohmann::ordered_json& parameters,
                                         const std::string& base_directory) const;
  void RememberBody(const nlohmann::ordered_json& parameters, const std::string& base_directory,
                    std::shared_ptr<const Body> body);
  // Shows entry `cursor_` at once when it was solved (strands kept), else schedules it.
  void ShowOrSchedule();
  // Cancels the running solve and schedules entry (or nothing, for -1).
  void Schedule(int entry);
  void WorkerLoop();
  // Computes the hair of job.document from the closest solved entry; false when cancelled or
  // failed (error set on failure only).
  bool Compute(const JobData& job, std::shared_ptr<HairState>* out, std::string* error);

  struct CachedBodyEntry {
    nlohmann::ordered_json key;  // the "body" member
    std::string base_directory;
    std::shared_ptr<const Body> body;
  };
  std::vector<CachedBodyEntry> bodies_;  // UI thread; the newest last, at most 4
  std::vector<Entry> history_;
  int cursor_ = 0;
  int saved_cursor_ = 0;
  std::string path_;
  std::shared_ptr<const HairState> shown_;
  int threads_ = 0;
  double preview_seconds_ = 0.3;
  std::function<void(const std::shared_ptr<const HairState>&)> preview_listener_;
  std::function<void()> wake_ui_;

  // Worker state, guarded by mutex_.
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::thread worker_;
  bool stop_ = false;
  std::unique_ptr<JobData> pending_;  // the newest scheduled job, not started yet
  bool running_ = false;
  std::uint64_t generation_ = 0;
  std::shared_ptr<std::atomic<bool>> cancel_;  // of the running job
  // Finished results waiting for Poll: (entry, generation, state, error).
  struct Finished {
    int entry = -1;
    std::uint64_t generation = 0;
    std::shared_ptr<const HairState> state;
    std::string error;
  };
  std::vector<Finished> finished_;
  std::string last_error_;
  std::atomic<int> progress_done_{0}, progress_total_{0};
  std::atomic<int> cancelled_{0};
  std::string progress_what_;
  std::shared_ptr<const HairState> preview_;  // Preview(), of job preview_generation_
  std::uint64_t preview_generation_ = 0;
  std::uint64_t scheduled_generation_ = 0;  // UI thread: the job whose result is wanted
  std::uint64_t shown_generation_ = 0;      // UI thread: the job whose result is shown_
};

}  // namespace ringlet::studio
