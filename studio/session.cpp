// The studio's editing model: document, history and the worker thread that re-solves.
#include "session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <sstream>

#include "ringlet/atomic_file.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/strand_geometry.h"

namespace ringlet::studio {
namespace {

using ojson = nlohmann::ordered_json;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

ojson Vector3(const Vec3& v) { return ojson::array({v.x(), v.y(), v.z()}); }

// The brush fields of sculpt and puff (docs/hairstyle-format.md): radius always, the others
// when they differ from the defaults.
void BrushToJson(const Brush& brush, ojson* body) {
  const Brush defaults;
  (*body)["radius"] = brush.radius;
  if (brush.strength != defaults.strength) (*body)["strength"] = brush.strength;
  if (brush.falloff != defaults.falloff) (*body)["falloff"] = FalloffName(brush.falloff);
  if (brush.mirror) (*body)["mirror"] = true;
}

// Whether two master models give the same SolveStrand result: every field SolveStrand reads,
// compared exactly (the obstacle by identity: the studio shares one body between entries whose
// "body" did not change).
bool SameModel(const StrandModel& a, const StrandModel& b) {
  return a.segment_lengths == b.segment_lengths && a.section.a == b.section.a &&
         a.section.b == b.section.b && a.material.young_modulus == b.material.young_modulus &&
         a.material.poisson_ratio == b.material.poisson_ratio &&
         a.material.density == b.material.density && a.natural_curvature == b.natural_curvature &&
         a.rest_curvatures.size() == b.rest_curvatures.size() &&
         (a.rest_curvatures.size() == 0 || a.rest_curvatures == b.rest_curvatures) &&
         a.root_position == b.root_position && a.root_frame == b.root_frame &&
         a.gravity == b.gravity && a.contact.obstacle == b.contact.obstacle &&
         a.contact.clearance == b.contact.clearance && a.contact.stiffness == b.contact.stiffness &&
         a.contact.samples_per_segment == b.contact.samples_per_segment;
}

// "a.b.c" -> {"a", "b", "c"}.
std::vector<std::string> SplitField(const std::string& field) {
  std::vector<std::string> keys;
  std::stringstream stream(field);
  std::string key;
  while (std::getline(stream, key, '.')) keys.push_back(key);
  return keys;
}

// A path relative to `to` (a directory) if it can be, else absolute.
std::string Rebase(const std::string& path, const std::string& from, const std::string& to) {
  namespace fs = std::filesystem;
  fs::path p(path);
  if (p.is_absolute()) return path;
  std::error_code ec;
  const fs::path absolute = fs::weakly_canonical(fs::absolute(fs::path(from) / p), ec);
  if (ec) return path;
  const fs::path target = fs::weakly_canonical(fs::absolute(to.empty() ? "." : to), ec);
  if (ec) return absolute.string();
  const fs::path relative = absolute.lexically_relative(target);
  return relative.empty() ? absolute.string() : relative.string();
}

bool SameOperation(const StyleOperation& a, const StyleOperation& b) {
  return OperationToJson(a) == OperationToJson(b);
}

// The numbers of a styled head that the panel shows and the view colours.
void FillStatus(HairState* state) {
  const std::vector<StrandSolution>& solutions = state->styled.solutions;
  state->status.assign(solutions.size(), MasterStatus::kConverged);
  SolveStats& s = state->stats;
  s.masters = static_cast<int>(solutions.size());
  s.unconverged = s.unstable = 0;
  s.max_penetration = 0.0;
  for (size_t i = 0; i < solutions.size(); ++i) {
    const SolveSummary& summary = solutions[i].summary;
    if (!summary.Converged()) {
      state->status[i] = MasterStatus::kUnconverged;
      ++s.unconverged;
    } else if (summary.stability_checked && !summary.stable) {
      state->status[i] = MasterStatus::kUnstable;
      ++s.unstable;
    }
    s.max_penetration = std::max(s.max_penetration, summary.contact.max_penetration);
  }
}

}  // namespace

ojson OperationToJson(const StyleOperation& op) {
  using Kind = StyleOperation::Kind;
  ojson body = ojson::object();
  switch (op.kind) {
    case Kind::kCurl: {
      if (std::isinf(op.curl_radius)) {
        body["radius"] = "inf";
      } else {
        body["radius"] = op.curl_radius;
      }
      body["pitch"] = op.curl_pitch;
      if (op.curl_brushed) {
        ojson brush = ojson::object();
        brush["centre"] = Vector3(op.curl_brush.centre);
        BrushToJson(op.curl_brush, &brush);
        body["brush"] = std::move(brush);
      }
      break;
    }
    case Kind::kWet:
      body["stiffness_factor"] = op.wet.stiffness_factor;
      body["swelling"] = op.wet.swelling;
      body["water_density"] = op.wet.water_density;
      body["layer_factor"] = op.wet.layer_factor;
      break;
    case Kind::kDry:
      break;
    case Kind::kCut: {
      const CutRegion& r = op.cut_region;
      switch (r.kind) {
        case CutRegion::Kind::kAbovePlane:
          if (r.normal == Vec3::UnitZ()) {
            body["z"] = r.offset;
          } else {
            body["plane"] = {{"normal", Vector3(r.normal)}, {"offset", r.offset}};
          }
          break;
        case CutRegion::Kind::kInsideSphere:
          body["sphere"] = {{"centre", Vector3(r.centre)}, {"radius", r.radius}};
          break;
        case CutRegion::Kind::kMaxLength:
          body["length"] = r.length;
          break;
      }
      if (op.cut.settle) body["settle"] = true;
      const CutOptions defaults;
      if (op.cut.tolerance != defaults.tolerance) body["tolerance"] = op.cut.tolerance;
      if (op.cut.max_rounds != defaults.max_rounds) body["max_rounds"] = op.cut.max_rounds;
      if (op.cut.samples_per_segment != defaults.samples_per_segment) {
        body["samples_per_segment"] = op.cut.samples_per_segment;
      }
      break;
    }
    case Kind::kGrow:
      body["step"] = op.grow_step;
      body["steps"] = op.grow_steps;
      break;
    case Kind::kSculpt:
      body["from"] = Vector3(op.sculpt.brush.centre);
      body["to"] = Vector3(op.sculpt.to);
      BrushToJson(op.sculpt.brush, &body);
      break;
    case Kind::kPuff:
      body["angle"] = op.puff_angle;
      body["centre"] = Vector3(op.puff_brush.centre);
      BrushToJson(op.puff_brush, &body);
      break;
    case Kind::kLength:
    case Kind::kClump:
      body["factor"] = op.factor;
      body["centre"] = Vector3(op.brush.centre);
      BrushToJson(op.brush, &body);
      break;
    case Kind::kFrizz:
      body["amplitude"] = op.frizz_amplitude;
      body["centre"] = Vector3(op.brush.centre);
      BrushToJson(op.brush, &body);
      break;
  }
  // The masters it acts on (every operation may have a "select").
  const StrandSelection& s = op.selection;
  const StrandSelection all;
  ojson select = ojson::object();
  if (!s.indices.empty()) {
    select["indices"] = s.indices;
  } else {
    if (s.min_polar_angle != all.min_polar_angle || s.max_polar_angle != all.max_polar_angle) {
      select["polar_angle"] = ojson::array({s.min_polar_angle, s.max_polar_angle});
    }
    // JSON has no infinity: an open end of the height range is written as +-1e300 m, which
    // selects the same roots.
    if (std::isfinite(s.min_height) || std::isfinite(s.max_height)) {
      select["height"] = ojson::array({std::isfinite(s.min_height) ? s.min_height : -1e300,
                                       std::isfinite(s.max_height) ? s.max_height : 1e300});
    }
  }
  if (!select.empty()) body["select"] = std::move(select);
  ojson out = ojson::object();
  out[OperationName(op.kind)] = std::move(body);
  return out;
}

ojson DocumentToJson(const Document& document, const std::string& directory) {
  ojson out = document.parameters;
  // Relative paths follow the file: the body file, or the OBJ meshes of an inline body.
  if (out.contains("body")) {
    ojson& body = out["body"];
    if (body.is_string()) {
      body = Rebase(body.get<std::string>(), document.base_directory, directory);
    } else if (body.is_object() && body.contains("meshes") && body["meshes"].is_array()) {
      for (ojson& mesh : body["meshes"]) {
        if (mesh.is_object() && mesh.contains("obj") && mesh["obj"].is_string()) {
          mesh["obj"] = Rebase(mesh["obj"].get<std::string>(), document.base_directory, directory);
        }
      }
    }
  }
  // An explicit masters file ("masters": {"file": ...}) follows the file too.
  if (out.contains("masters") && out["masters"].is_object() && out["masters"].contains("file") &&
      out["masters"]["file"].is_string()) {
    ojson& file = out["masters"]["file"];
    file = Rebase(file.get<std::string>(), document.base_directory, directory);
  }
  out.erase("operations");
  if (!document.operations.empty()) {
    ojson ops = ojson::array();
    for (const StyleOperation& op : document.operations) ops.push_back(OperationToJson(op));
    out["operations"] = std::move(ops);
  }
  return out;
}

ojson ParseValue(const std::string& text) {
  ojson value = ojson::parse(text, nullptr, false);
  if (value.is_discarded()) return ojson(text);
  return value;
}

// ---------------------------------------------------------------------------------------------
// Session

Session::Session() {
  history_.push_back(Entry{Document{}, "empty", nullptr});
  worker_ = std::thread([this] { WorkerLoop(); });
}

Session::~Session() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    if (cancel_) cancel_->store(true);
  }
  wake_.notify_all();
  worker_.join();
}

Session::File Session::Read(const std::string& path) {
  // Read once (a regular file under the JSON size cap), checked by the library's reader first,
  // for the CLI's messages (syntax errors with line and column, fields by name, the nesting
  // limit); only then is the same text parsed again in order (nlohmann's recursive parser never
  // sees a document deeper than the reader's limit).
  File file;
  file.path = path;
  std::string text;
  if (!ReadFile(path, &text, &file.error)) return file;
  Hairstyle style;
  std::vector<StyleOperation> operations;
  const std::string base = std::filesystem::path(path).parent_path().string();
  if (!ParseHairstyleText(text, base.empty() ? "." : base, &style, &operations, &file.error)) {
    file.error = path + ": " + file.error;
    return file;
  }
  file.json = ojson::parse(text, nullptr, false);
  if (file.json.is_discarded() || !file.json.is_object()) {
    file.error = path + ": not a JSON object";
    return file;
  }
  file.body = style.body;
  return file;
}

bool Session::Open(const File& file, std::string* error) {
  if (!file.error.empty()) {
    *error = file.error;
    return false;
  }
  const std::string directory = std::filesystem::path(file.path).parent_path().string();
  // The body just read serves the document's parse and the worker's (a fresh read: the file
  // may have changed since an earlier open).
  const std::vector<CachedBodyEntry> kept = std::move(bodies_);
  bodies_.clear();
  RememberBody(file.json, directory, file.body);
  if (!OpenDocument(file.json, directory, file.path, error)) {
    bodies_ = kept;
    return false;
  }
  path_ = file.path;
  return true;
}

bool Session::OpenDocument(const ojson& json, const std::string& base_directory,
                           const std::string& name, std::string* error) {
  Hairstyle style;
  std::vector<StyleOperation> operations;
  const nlohmann::json plain = json;
  std::string why;
  if (!ParseHairstyle(plain, base_directory, CachedBody(json, base_directory), &style, &why) ||
      !ParseStyleOperations(plain, &operations, &why)) {
    *error = name + ": " + why;
    return false;
  }
  RememberBody(json, base_directory, style.body);
  Document document;
  document.parameters = json;
  document.parameters.erase("operations");
  document.operations = std::move(operations);
  document.base_directory = base_directory;
  history_.clear();
  cursor_ = -1;
  path_.clear();
  PushEntry(std::move(document), "open " + std::filesystem::path(name).filename().string());
  saved_cursor_ = cursor_;
  return true;
}

std::vector<std::string> LengthFields(const ojson& parameters) {
  const auto hair = parameters.find("hair");
  if (hair != parameters.end() && hair->is_object()) {
    const auto length = hair->find("length");
    if (length != hair->end() && length->is_object() && !length->empty()) {
      std::vector<std::string> fields;
      for (const auto& [region, value] : length->items()) fields.push_back("hair.length." + region);
      return fields;
    }
  }
  return {"hair.length"};
}

ojson Session::Parameter(const std::string& field) const {
  const ojson* node = &CurrentDocument().parameters;
  for (const std::string& key : SplitField(field)) {
    if (!node->is_object() || !node->contains(key)) return ojson();
    node = &(*node)[key];
  }
  return *node;
}

bool Session::SetParameter(const std::string& field, const ojson& value, std::string* error) {
  const std::vector<std::string> keys = SplitField(field);
  if (keys.empty() || field == "operations") {
    *error = "set: expected a field of the hairstyle, got \"" + field + "\"";
    return false;
  }
  Document document = CurrentDocument();
  ojson* node = &document.parameters;
  for (size_t k = 0; k + 1 < keys.size(); ++k) {
    if (!node->contains(keys[k])) (*node)[keys[k]] = ojson::object();
    node = &(*node)[keys[k]];
    if (!node->is_object()) {
      *error = field + ": " + keys[k] + " is not an object";
      return false;
    }
  }
  (*node)[keys.back()] = value;
  Hairstyle style;
  std::string why;
  if (!ParseHairstyle(nlohmann::json(document.parameters), document.base_directory,
                      CachedBody(document.parameters, document.base_directory), &style, &why)) {
    *error = why;
    return false;
  }
  RememberBody(document.parameters, document.base_directory, style.body);
  PushEntry(std::move(document), "set " + field + " = " + value.dump());
  return true;
}

bool Session::AddOperation(const StyleOperation& operation, std::string* error) {
  if (!operation.IsValid(error)) return false;
  std::shared_ptr<const HairState> hair =
      history_[cursor_].state ? history_[cursor_].state : shown_;
  if (hair) {
    const int masters = static_cast<int>(hair->styled.masters.models.size());
    if (!operation.selection.IsValid(masters, error)) return false;
    // Dry needs a selected wet master, wet a selected dry one: checked on the shown hair when it
    // is the current entry's (otherwise the worker reports it).
    if (hair == history_[cursor_].state &&
        (operation.kind == StyleOperation::Kind::kWet ||
         operation.kind == StyleOperation::Kind::kDry)) {
      const bool want_wet = operation.kind == StyleOperation::Kind::kDry;
      bool any = false;
      for (int i = 0; i < masters && !any; ++i) {
        any = operation.selection.Selects(i, hair->styled.masters.roots[i]) &&
              IsWet(hair->styled, i) == want_wet;
      }
      if (!any) {
        *error = want_wet ? "dry: the hair is not wet (wet it first)"
                          : "wet: the hair is already wet (dry it first)";
        return false;
      }
    }
  }
  Document document = CurrentDocument();
  document.operations.push_back(operation);
  std::string label = OperationName(operation.kind);
  if (!operation.selection.indices.empty()) {
    label += " (" + std::to_string(operation.selection.indices.size()) + " brushed masters)";
  }
  PushEntry(std::move(document), label);
  return true;
}

std::shared_ptr<const Body> Session::CachedBody(const ojson& parameters,
                                                const std::string& base_directory) const {
  const auto it = parameters.find("body");
  if (it == parameters.end()) return nullptr;
  for (const CachedBodyEntry& e : bodies_) {
    if (e.base_directory == base_directory && e.key == *it) return e.body;
  }
  return nullptr;
}

void Session::RememberBody(const ojson& parameters, const std::string& base_directory,
                           std::shared_ptr<const Body> body) {
  const auto it = parameters.find("body");
  if (it == parameters.end() || !body || CachedBody(parameters, base_directory) == body) return;
  bodies_.push_back(CachedBodyEntry{*it, base_directory, std::move(body)});
  if (bodies_.size() > 4) bodies_.erase(bodies_.begin());
}

void Session::PushEntry(Document document, std::string label) {
  history_.resize(cursor_ + 1);  // a new edit drops the redo branch
  if (saved_cursor_ > cursor_) saved_cursor_ = -1;
  history_.push_back(Entry{std::move(document), std::move(label), nullptr});
  cursor_ = static_cast<int>(history_.size()) - 1;
  Schedule(cursor_);
}

bool Session::Undo() {
  if (!CanUndo()) return false;
  --cursor_;
  ShowOrSchedule();
  return true;
}

bool Session::Redo() {
  if (!CanRedo()) return false;
  ++cursor_;
  ShowOrSchedule();
  return true;
}

bool Session::Save(const std::string& path, std::string* error, bool overwrite) {
  const std::string directory = std::filesystem::path(path).parent_path().string();
  const ojson json = DocumentToJson(CurrentDocument(), directory);
  if (!WriteFileAtomically(path, json.dump(2) + "\n", overwrite, error)) return false;
  saved_cursor_ = cursor_;
  path_ = path;
  return true;
}

void Session::New() {
  Schedule(-1);  // cancel a running solve
  history_.clear();
  history_.push_back(Entry{Document{}, "empty", nullptr});
  cursor_ = 0;
  saved_cursor_ = 0;
  path_.clear();
  shown_.reset();
  brush.clear();
}

bool Session::UpToDate() const { return shown_ && history_[cursor_].state == shown_; }

std::string Session::LastError() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_error_;
}

std::vector<std::string> Session::HistoryLabels() const {
  std::vector<std::string> labels;
  for (const Entry& e : history_) labels.push_back(e.label);
  return labels;
}

bool Session::Busy() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pending_ || running_ || !finished_.empty();
}

std::shared_ptr<const HairState> Session::Preview() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (preview_generation_ != scheduled_generation_ || shown_generation_ == scheduled_generation_) {
    return nullptr;
  }
  return preview_;
}

void Session::Progress(int* done, int* total, std::string* what) const {
  std::lock_guard<std::mutex> lock(mutex_);
  *done = running_ ? progress_done_.load() : 0;
  *total = running_ ? progress_total_.load() : 0;
  *what = running_ ? progress_what_ : "";
}

// ---------------------------------------------------------------------------------------------
// The worker

Session::PreviewPublisher::PreviewPublisher(Session* session, std::uint64_t generation,
                                            double seconds, bool eager)
    : session_(session),
      generation_(generation),
      seconds_(seconds),
      eager_(eager),
      last_(std::chrono::steady_clock::now()) {}

bool Session::PreviewPublisher::Due() const {
  return eager_ || SecondsSince(last_) >= seconds_;
}

template <class Shape>
void Session::PreviewPublisher::Publish(const Hairstyle& style, const HairstyleMasters& masters,
                                        const Shape& shape) {
  const size_t n = masters.models.size();
  if (lines_.size() != n) {
    lines_.assign(n, {});
    final_.assign(n, 0);
  }
  std::vector<Vec3> points;
  for (size_t i = 0; i < n; ++i) {
    if (final_[i]) continue;
    points.clear();
    final_[i] = shape(static_cast<int>(i), &points) ? 1 : 0;
    lines_[i].resize(points.size());
    for (size_t k = 0; k < points.size(); ++k) lines_[i][k] = points[k].cast<float>();
  }
  Send(style, masters);
}

void Session::PreviewPublisher::PublishStyled(const StyledHair& styled) {
  std::fill(final_.begin(), final_.end(), 0);
  Publish(styled.style, styled.masters, [&](int i, std::vector<Vec3>* points) {
    *points = SampleCentreline(styled.masters.models[i], styled.solutions[i].curvatures, 2);
    return true;
  });
}

void Session::PreviewPublisher::Send(const Hairstyle& style, const HairstyleMasters& masters) {
  auto preview = std::make_shared<HairState>();
  preview->styled.style = style;
  preview->styled.masters = masters;
  preview->stats.what = "solving";
  preview->stats.masters = static_cast<int>(masters.models.size());
  auto curves = std::make_shared<HairCurves>();
  for (size_t i = 0; i < lines_.size(); ++i) {
    preview->stats.resolved += final_[i] ? 1 : 0;
    const size_t count = std::max<size_t>(2, lines_[i].size());
    curves->point_counts.push_back(static_cast<std::uint32_t>(count));
    if (lines_[i].size() < 2) {
      curves->points.insert(curves->points.end(), 2, masters.roots[i].position.cast<float>());
    } else {
      curves->points.insert(curves->points.end(), lines_[i].begin(), lines_[i].end());
    }
    curves->widths.insert(curves->widths.end(), count, 8e-5f);  // drawn a pixel wide anyway
  }
  static std::atomic<std::uint64_t> preview_serial{1u << 30};
  preview->strands_id = ++preview_serial;
  preview->strands = std::move(curves);
  if (session_->preview_listener_) session_->preview_listener_(preview);
  {
    std::lock_guard<std::mutex> lock(session_->mutex_);
    session_->preview_ = std::move(preview);
    session_->preview_generation_ = generation_;
  }
  last_ = std::chrono::steady_clock::now();
  eager_ = false;
  if (session_->wake_ui_) session_->wake_ui_();
}

void Session::ShowOrSchedule() {
  const std::shared_ptr<const HairState>& state = history_[cursor_].state;
  if (state && state->strands) {
    shown_ = state;
    Schedule(-1);  // cancel a stale solve
  } else {
    Schedule(cursor_);
  }
}

void Session::Schedule(int entry) {
  std::lock_guard<std::mutex> lock(mutex_);
  // A newer edit cancels the running solve and replaces a pending one.
  if (cancel_) cancel_->store(true);
  if (cancel_ || pending_) ++cancelled_;
  scheduled_generation_ = ++generation_;
  pending_.reset();
  preview_.reset();
  if (entry < 0) return;
  auto job = std::make_unique<JobData>();
  job->entry = entry;
  job->generation = generation_;
  job->document = history_[entry].document;
  job->body = CachedBody(job->document.parameters, job->document.base_directory);
  for (const Entry& e : history_) {
    if (e.state) job->solved.push_back(Candidate{e.document, e.state});
  }
  job->cancel = std::make_shared<std::atomic<bool>>(false);
  pending_ = std::move(job);
  wake_.notify_all();
}

void Session::WorkerLoop() {
  while (true) {
    std::unique_ptr<JobData> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || pending_; });
      if (stop_) return;
      job = std::move(pending_);
      running_ = true;
      cancel_ = job->cancel;
      progress_done_ = 0;
      progress_total_ = 0;
      progress_what_ = "solving";
    }
    std::shared_ptr<HairState> state;
    std::string error;
    const bool ok = Compute(*job, &state, &error);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      running_ = false;
      cancel_.reset();
      // A cancelled job leaves nothing; a failed one its message.
      if (ok || !error.empty()) {
        finished_.push_back(Finished{job->entry, job->generation, state, error});
      }
    }
    idle_.notify_all();
    if (wake_ui_) wake_ui_();
  }
}

bool Session::Poll() {
  std::vector<Finished> finished;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finished.swap(finished_);
  }
  bool changed = false;
  for (Finished& f : finished) {
    // Only the result of the last scheduled job counts: an older one belongs to an entry that
    // was undone or replaced since.
    if (f.generation != scheduled_generation_) continue;
    if (f.entry < 0 || f.entry >= static_cast<int>(history_.size())) continue;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!f.error.empty()) {
      last_error_ = history_[f.entry].label + ": " + f.error;
      preview_.reset();  // the failed solve's masters are not shown any more
      continue;
    }
    last_error_.clear();
    history_[f.entry].state = f.state;
    if (f.entry == cursor_) {
      shown_ = f.state;
      shown_generation_ = f.generation;
      changed = true;
    }
  }
  // Keep the strands of a few entries only (tens of MB each); the others keep their masters
  // and re-grow the wisps when shown again.
  int kept = 0;
  for (int k = static_cast<int>(history_.size()) - 1; k >= 0; --k) {
    std::shared_ptr<const HairState>& state = history_[k].state;
    if (!state || !state->strands || state == shown_ || ++kept <= 4) continue;
    auto light = std::make_shared<HairState>(*state);
    light->strands.reset();
    state = std::move(light);
  }
  return changed;
}

void Session::Wait() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [this] { return !pending_ && !running_; });
  }
  Poll();
}

bool Session::Compute(const JobData& job, std::shared_ptr<HairState>* out, std::string* error) {
  const Document& target = job.document;
  const std::atomic<bool>& cancel = *job.cancel;
  const std::vector<Candidate>& candidates = job.solved;
  const auto start = std::chrono::steady_clock::now();
  auto state = std::make_shared<HairState>();
  SolveStats& stats = state->stats;
  BatchOptions batch;
  batch.threads = threads_;
  batch.cancel = &cancel;
  batch.progress = [this](int done, int total) {
    progress_done_ = done;
    progress_total_ = total;
  };
  const auto set_what = [this](const std::string& what) {
    std::lock_guard<std::mutex> lock(mutex_);
    progress_what_ = what;
  };
  // A fresh file (nothing solved before, nothing on screen): its first masters are shown as
  // soon as the first (smaller) block is solved.
  const bool fresh = candidates.empty();
  PreviewPublisher preview(this, job.generation, preview_seconds_, fresh);

  // 1. The closest solved entry with the same parameters whose operations are a prefix of the
  //    target's: only the remaining operations run, from its equilibrium.
  const HairState* from = nullptr;
  size_t done_ops = 0;
  for (const auto& [document, s] : candidates) {
    if (document.parameters != target.parameters ||
        document.base_directory != target.base_directory || !s) {
      continue;
    }
    const size_t n = document.operations.size();
    if (n > target.operations.size()) continue;
    bool prefix = true;
    for (size_t k = 0; k < n && prefix; ++k) {
      prefix = SameOperation(document.operations[k], target.operations[k]);
    }
    if (prefix && (!from || n >= done_ops)) {
      from = s.get();
      done_ops = n;
    }
  }

  if (from) {
    state->base = from->base;
    state->styled = from->styled;
  } else {
    // 2. A new groom: build the masters and solve those whose model changed.
    // The groom to reuse: the most recent candidate (its body shared when "body" is unchanged).
    const HairState* previous = nullptr;
    const Document* previous_document = nullptr;
    for (const auto& [document, s] : candidates) {
      if (s && s->base) {
        previous = s.get();
        previous_document = &document;
      }
    }
    // The body read by the UI thread's checks (Session::CachedBody), else the previous groom's
    // when "body" is unchanged, else read here.
    std::shared_ptr<const Body> body = job.body;
    if (!body && previous) {
      const auto a = target.parameters.find("body");
      const auto b = previous_document->parameters.find("body");
      if (a != target.parameters.end() && b != previous_document->parameters.end() && *a == *b &&
          target.base_directory == previous_document->base_directory) {
        body = previous->styled.style.body;
      }
    }
    Hairstyle style;
    std::string why;
    set_what("reading the hairstyle");
    if (!ParseHairstyle(nlohmann::json(target.parameters), target.base_directory, body, &style,
                        &why)) {
      *error = why;
      return false;
    }
    const bool same_solver = previous && previous_document &&
                             target.parameters.value("solver", ojson()) ==
                                 previous_document->parameters.value("solver", ojson());
    auto groom = std::make_shared<Groom>();
    set_what("building masters");
    if (!BuildMasters(style, &groom->masters, &why)) {
      *error = why;
      return false;
    }
    const int n = static_cast<int>(groom->masters.models.size());
    groom->solutions.resize(n);
    std::vector<int> todo;
    // Where each master's solve starts: the natural shape, or an explicit master's start.
    const std::vector<VecX>& starts = groom->masters.start_curvatures;
    const auto start_of = [](const HairstyleMasters& m, int i) {
      return m.start_curvatures.empty() ? VecX() : m.start_curvatures[i];
    };
    for (int i = 0; i < n; ++i) {
      if (same_solver && previous->base &&
          static_cast<int>(previous->base->masters.models.size()) == n &&
          SameModel(groom->masters.models[i], previous->base->masters.models[i]) &&
          start_of(groom->masters, i).size() == start_of(previous->base->masters, i).size() &&
          start_of(groom->masters, i) == start_of(previous->base->masters, i)) {
        groom->solutions[i] = previous->base->solutions[i];
        ++stats.reused;
      } else {
        todo.push_back(i);
      }
    }
    // The masters are published as they are solved (Preview): the not yet solved ones in the
    // shape shown before this edit (the previous hair's master, when it has as many), else a
    // stub at the root.
    std::vector<char> solved_yet(n, 0);
    for (int i = 0; i < n; ++i) solved_yet[i] = groom->solutions[i].curvatures.size() > 0;
    const StyledHair* before =
        previous && static_cast<int>(previous->styled.masters.models.size()) == n
            ? &previous->styled
            : nullptr;
    const auto publish_groom = [&] {
      preview.Publish(style, groom->masters, [&](int i, std::vector<Vec3>* points) {
        if (solved_yet[i]) {
          *points = SampleCentreline(groom->masters.models[i], groom->solutions[i].curvatures, 2);
        } else if (before) {
          *points = SampleCentreline(before->masters.models[i], before->solutions[i].curvatures, 2);
        }
        return solved_yet[i] != 0;
      });
    };
    // Blocks of masters between cancellation checks (the same solves as one SolveStrands call).
    set_what("solving masters");
    // The first block of a fresh file is 8 masters: its first picture sooner.
    for (size_t begin = 0, end = 0; begin < todo.size(); begin = end) {
      if (cancel.load()) return false;
      end = std::min(todo.size(), begin + (fresh && begin == 0 ? 8 : 32));
      std::vector<StrandModel> models;
      std::vector<VecX> warm;
      for (size_t k = begin; k < end; ++k) {
        models.push_back(groom->masters.models[todo[k]]);
        if (!starts.empty()) warm.push_back(starts[todo[k]]);
      }
      BatchOptions b;
      b.threads = threads_;
      std::vector<StrandSolution> solved =
          SolveStrands(models, style.solver, b, starts.empty() ? nullptr : &warm);
      for (size_t k = begin; k < end; ++k) {
        stats.iterations += solved[k - begin].summary.iterations;
        groom->solutions[todo[k]] = std::move(solved[k - begin]);
        solved_yet[todo[k]] = 1;
      }
      progress_done_ = static_cast<int>(end);
      progress_total_ = static_cast<int>(todo.size());
      if (preview.Due()) publish_groom();
    }
    stats.resolved = static_cast<int>(todo.size());
    stats.what = "groom";
    if (!MakeStyledHair(style, *groom, &state->styled, &why)) {
      *error = why;
      return false;
    }
    state->base = std::move(groom);
  }

  // 3. The remaining operations, each warm-started from the previous equilibrium.
  for (size_t k = done_ops; k < target.operations.size(); ++k) {
    if (cancel.load()) return false;
    const StyleOperation& op = target.operations[k];
    set_what(std::string("re-solving: ") + OperationName(op.kind));
    OperationReport report;
    std::string why;
    if (!ApplyOperation(&state->styled, op, batch, nullptr, &report, &why)) {
      if (cancel.load()) return false;
      *error = "operations[" + std::to_string(k) + "]: " + why;
      return false;
    }
    if (preview.Due()) preview.PublishStyled(state->styled);
    stats.what = report.name;
    // Clump and frizz change wisps only: their strands are not master solves.
    if (op.kind != StyleOperation::Kind::kClump && op.kind != StyleOperation::Kind::kFrizz) {
      stats.resolved += report.strands;
    }
    stats.iterations += report.iterations;
    if (!stats.message.empty()) stats.message += "; ";
    stats.message += report.message;
  }
  if (cancel.load()) return false;
  stats.solve_seconds = SecondsSince(start);
  // The masters solved, the children not yet grown: shown when the edit has been running long
  // enough to publish (or has published before).
  if (preview.Due()) preview.PublishStyled(state->styled);
  set_what("growing wisps");
  const auto wisp_start = std::chrono::steady_clock::now();
  // Only the wisps of the masters that changed since `from` are regrown (RegrowWisps, the same
  // bits as growing them all); a new groom grows every wisp.
  std::vector<int> changed;
  // Not after a cut: cut strands are clipped (StyledHair::strand_cuts) and no longer have the
  // fixed layout RegrowWisps writes into.
  bool partial = from && from->strands &&
                 from->styled.masters.models.size() == state->styled.masters.models.size() &&
                 from->styled.strand_cuts.empty() && state->styled.strand_cuts.empty();
  for (size_t i = 0; partial && i < state->styled.masters.models.size(); ++i) {
    const StyledHair& a = from->styled;
    const StyledHair& b = state->styled;
    if (!SameModel(a.masters.models[i], b.masters.models[i]) ||
        a.solutions[i].curvatures != b.solutions[i].curvatures ||
        a.masters.wisp_radii[i] != b.masters.wisp_radii[i] ||
        MasterWispOptions(a.masters, i).tip_scale != MasterWispOptions(b.masters, i).tip_scale ||
        MasterWispOptions(a.masters, i).frizz_amplitude !=
            MasterWispOptions(b.masters, i).frizz_amplitude) {
      changed.push_back(static_cast<int>(i));
    }
  }
  std::shared_ptr<HairCurves> strands;
  std::string why;
  if (partial) {
    strands = std::make_shared<HairCurves>(*from->strands);
    partial = RegrowWisps(state->styled.style, state->styled.masters, state->styled.solutions,
                          changed, strands.get(), &why);
  }
  if (partial) {
    state->regrown_from = from->strands_id;
    state->regrown = std::move(changed);
    stats.regrown = static_cast<int>(state->regrown.size());
  } else {
    strands = std::make_shared<HairCurves>();
    if (!StyledStrands(state->styled, strands.get(), &why)) {
      *error = why;
      return false;
    }
    stats.regrown = -1;
  }
  static std::atomic<std::uint64_t> serial{0};
  state->strands_id = ++serial;
  state->strands = std::move(strands);
  stats.wisp_seconds = SecondsSince(wisp_start);
  FillStatus(state.get());
  if (stats.what.empty()) stats.what = "unchanged";
  stats.seconds = SecondsSince(start);
  *out = std::move(state);
  return true;
}

}  // namespace ringlet::studio
