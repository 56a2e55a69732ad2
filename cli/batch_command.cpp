// `ringlet batch SPEC -o OUTDIR [--shard K/N] [--items A:B]`: a dataset of grooms (docs/batch.md).
// The library resolves and runs each item (batch.h); this command only picks its share of the
// items, skips those done, appends manifest lines and prints progress and a summary. With
// --slurm-script it writes a Slurm job array of such runs instead, and with --slurm-unfinished
// it prints the array's tasks that are not done (batch_slurm.h).
//
// Exit codes: 0 every item of the share is done (or was already), 2 some item failed or was
// flagged (the others are written), 1 bad usage or spec (nothing is written). SIGINT / SIGTERM:
// the item being run is abandoned (nothing of it is written), the summary printed, and the
// process ends by the same signal; a rerun continues where it stopped.
#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "commands.h"
#include "format.h"
#include "outputs.h"
#include "ringlet/atomic_file.h"
#include "ringlet/batch.h"
#include "ringlet/batch_slurm.h"

namespace ringlet::cli {
namespace {

struct BatchArgs {
  std::string spec_path;
  std::string output_dir;
  std::string shard;
  std::string items;
  bool plan = false;
  bool quiet = false;
  int threads = 0;
  CLI::Option* threads_option = nullptr;
  // Slurm (docs/batch.md, "Slurm").
  std::string slurm_script;  // "" or "-": stdout
  CLI::Option* slurm_script_option = nullptr;
  bool slurm_unfinished = false;
  std::int64_t slurm_tasks = 0, slurm_items_per_task = 0;
  int slurm_throttle = 0, slurm_cpus = 1;
  std::string slurm_time = "01:00:00", slurm_job_name, slurm_partition, slurm_account,
              slurm_log_dir;
  std::vector<std::string> slurm_options;
  std::vector<CLI::Option*> slurm_only;  // the options that need --slurm-script
};

// Set by SIGINT / SIGTERM (async-signal-safe: a lock-free atomic store).
std::atomic<bool> g_stop{false};
volatile std::sig_atomic_t g_signal = 0;
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void OnStopSignal(int signal) {
  g_signal = signal;
  g_stop.store(true);
}

void InstallStopHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  for (const int signal : {SIGINT, SIGTERM}) {
    struct sigaction old {};
    sigaction(signal, nullptr, &old);
    if (old.sa_handler == SIG_IGN) continue;  // nohup: stays ignored
    sigaction(signal, &action, nullptr);
  }
}

// The manifest of a share: manifest-all.jsonl, manifest-items-A-B.jsonl,
// manifest-shard-K-of-N.jsonl or manifest-items-A-B-shard-K-of-N.jsonl.
std::string ManifestName(const BatchArgs& args, const BatchRange& items, int k, int n) {
  std::string name = "manifest";
  if (!args.items.empty())
    name += Format("-items-%lld-%lld", static_cast<long long>(items.begin),
                   static_cast<long long>(items.end));
  if (!args.shard.empty()) name += Format("-shard-%d-of-%d", k, n);
  if (args.items.empty() && args.shard.empty()) name += "-all";
  return name + ".jsonl";
}

// The spec's own text as OUTDIR/spec.json, so that a dataset says what made it; a directory
// holding another spec's dataset is refused (its items would be mixed with ours).
bool RecordSpec(const std::string& outdir, const std::string& spec_path, std::string* error) {
  std::string text;
  if (!ReadFile(spec_path, &text, error)) return false;
  const std::string copy = (std::filesystem::path(outdir) / "spec.json").string();
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::string existing, why;
    std::error_code ec;
    if (std::filesystem::exists(copy, ec)) {
      if (!ReadFile(copy, &existing, error)) return false;
      if (existing != text) {
        *error = DisplayPath(outdir) + ": holds the dataset of another spec (its spec.json " +
                 "differs from " + DisplayPath(spec_path) + "); give another output directory";
        return false;
      }
      return true;
    }
    if (WriteFileAtomically(copy, text, false, &why)) return true;
    // Another process wrote it meanwhile: compare again.
    if (attempt == 1) {
      *error = why;
      return false;
    }
  }
  return true;
}

int RunPlan(const BatchSpec& spec, const BatchRange& range) {
  for (std::int64_t k = range.begin; k < range.end; ++k) {
    const BatchItem item = ResolveBatchItem(spec, k);
    nlohmann::json line = {{"item", item.index}, {"name", item.name}};
    for (const auto& member : item.parameters.items()) line[member.key()] = member.value();
    std::printf("%s\n", line.dump().c_str());
  }
  return kExitSuccess;
}

// The spec's own text equals outdir/spec.json, or outdir has none (nothing is written).
bool SpecMatches(const std::string& outdir, const std::string& spec_path, std::string* error) {
  const std::string copy = (std::filesystem::path(outdir) / "spec.json").string();
  std::error_code ec;
  if (!std::filesystem::exists(copy, ec)) return true;
  std::string text, existing;
  if (!ReadFile(spec_path, &text, error) || !ReadFile(copy, &existing, error)) return false;
  if (existing != text) {
    *error = DisplayPath(outdir) + ": holds the dataset of another spec (its spec.json differs " +
             "from " + DisplayPath(spec_path) + ")";
    return false;
  }
  return true;
}

// A job name from the spec's file name: "ringlet-NAME" with NAME's characters outside
// [A-Za-z0-9._-] as '_'.
std::string DefaultJobName(const std::string& spec_path) {
  std::string name = "ringlet-" + std::filesystem::path(spec_path).stem().string();
  for (char& c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '.' || c == '_' || c == '-';
    if (!plain) c = '_';
  }
  return name;
}

// --slurm-script [FILE] and --slurm-unfinished (docs/batch.md, "Slurm").
int RunSlurm(const BatchArgs& args, const BatchSpec& spec, const BatchRange& items) {
  namespace fs = std::filesystem;
  std::string error;
  const bool script = args.slurm_script_option->count() > 0;
  const char* mode = script ? "--slurm-script" : "--slurm-unfinished";
  if (script && args.slurm_unfinished) {
    PrintError("--slurm-script and --slurm-unfinished: give one of them");
    return kExitBadInput;
  }
  if (!args.shard.empty() || args.plan || args.threads_option->count() > 0) {
    PrintError(std::string(!args.shard.empty() ? "--shard"
                           : args.plan         ? "--plan"
                                               : "--threads") +
               ": not with " + mode +
               " (each task of the array runs its own shard, with --slurm-cpus-per-task threads)");
    return kExitBadInput;
  }
  if (args.output_dir.empty()) {
    PrintError(std::string("--output is required with ") + mode);
    return kExitBadInput;
  }
  std::int64_t tasks = 0;
  if (!SlurmTaskCount(items.end - items.begin, args.slurm_tasks, args.slurm_items_per_task, &tasks,
                      &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  std::error_code ec;
  const fs::path outdir = fs::absolute(args.output_dir, ec).lexically_normal();
  if (ec) {
    PrintError(DisplayPath(args.output_dir) + ": cannot make the path absolute: " + ec.message());
    return kExitBadInput;
  }
  if (fs::exists(outdir, ec) && !fs::is_directory(outdir, ec)) {
    PrintError(DisplayPath(args.output_dir) + ": exists and is not a directory");
    return kExitBadInput;
  }
  if (!SpecMatches(outdir.string(), args.spec_path, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!script) {
    const std::vector<std::int64_t> ids = UnfinishedSlurmTasks(outdir.string(), items, tasks);
    if (!ids.empty()) std::printf("%s\n", SlurmArrayIds(ids).c_str());
    if (!args.quiet) {
      std::fprintf(stderr, "batch: %zu of %lld tasks unfinished%s\n", ids.size(),
                   static_cast<long long>(tasks),
                   ids.empty() ? "" : " (resubmit them with sbatch --array=IDS SCRIPT)");
    }
    return kExitSuccess;
  }

  SlurmArrayOptions options;
  options.binary = fs::read_symlink("/proc/self/exe", ec).string();
  if (ec || options.binary.empty()) {
    PrintError("--slurm-script: cannot find the ringlet executable's path (/proc/self/exe): " +
               ec.message());
    return kExitBadInput;
  }
  options.spec_path = fs::absolute(args.spec_path, ec).lexically_normal().string();
  options.output_dir = outdir.string();
  options.log_dir = args.slurm_log_dir.empty()
                        ? (outdir / "slurm-logs").string()
                        : fs::absolute(args.slurm_log_dir, ec).lexically_normal().string();
  options.items = items;
  options.items_option = !args.items.empty();
  options.spec_count = spec.count;
  options.tasks = tasks;
  options.throttle = args.slurm_throttle;
  options.cpus_per_task = args.slurm_cpus;
  options.time = args.slurm_time;
  options.job_name =
      args.slurm_job_name.empty() ? DefaultJobName(args.spec_path) : args.slurm_job_name;
  options.partition = args.slurm_partition;
  options.account = args.slurm_account;
  options.extra = args.slurm_options;
  const bool ok =
      CheckSlurmTime(options.time, &error) &&
      CheckSlurmWord("--slurm-job-name", options.job_name, &error) &&
      (options.partition.empty() ||
       CheckSlurmWord("--slurm-partition", options.partition, &error)) &&
      (options.account.empty() || CheckSlurmWord("--slurm-account", options.account, &error)) &&
      CheckSlurmWord(args.slurm_log_dir.empty() ? "--slurm-log-dir (default OUTDIR/slurm-logs)"
                                                : "--slurm-log-dir",
                     options.log_dir, &error);
  if (!ok) {
    PrintError(error);
    return kExitBadInput;
  }
  for (const std::string& extra : options.extra) {
    if (!CheckSlurmExtraOption(extra, &error)) {
      PrintError(error);
      return kExitBadInput;
    }
  }
  const bool to_stdout = args.slurm_script.empty() || args.slurm_script == "-";
  if (!to_stdout && !CheckReplaceable(args.slurm_script, true, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  // The dataset's directory with its spec.json (another spec's dataset is refused now, not when
  // the tasks start), and the log directory: Slurm does not create it, and a task whose log
  // cannot be opened fails without a word.
  fs::create_directories(outdir, ec);
  if (ec) {
    PrintError(DisplayPath(outdir.string()) + ": cannot create the directory: " + ec.message());
    return kExitBadInput;
  }
  if (!RecordSpec(outdir.string(), args.spec_path, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  fs::create_directories(options.log_dir, ec);
  if (ec) {
    PrintError(DisplayPath(options.log_dir) + ": cannot create the directory: " + ec.message());
    return kExitBadInput;
  }
  const std::string text = SlurmArrayScript(options);
  if (to_stdout) {
    std::fputs(text.c_str(), stdout);
    return kExitSuccess;
  }
  if (!WriteFileAtomically(args.slurm_script, text, true, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!args.quiet) {
    const std::int64_t length = items.end - items.begin;
    std::printf("slurm: %lld items in %lld tasks of at most %lld -> %s (submit: sbatch %s)\n",
                static_cast<long long>(length), static_cast<long long>(tasks),
                static_cast<long long>((length + tasks - 1) / tasks), args.slurm_script.c_str(),
                args.slurm_script.c_str());
  }
  return kExitSuccess;
}

int RunBatch(const BatchArgs& args) {
  std::string error;
  BatchSpec spec;
  if (!LoadBatchSpec(args.spec_path, &spec, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  BatchRange items{0, spec.count};
  if (!args.items.empty() && !ParseItemRange(args.items, spec.count, &items, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  int k = 0, n = 1;
  if (!args.shard.empty() && !ParseShard(args.shard, &k, &n, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (args.slurm_script_option->count() > 0 || args.slurm_unfinished) {
    return RunSlurm(args, spec, items);
  }
  for (const CLI::Option* option : args.slurm_only) {
    if (option->count() > 0) {
      PrintError(option->get_name() + ": needs --slurm-script or --slurm-unfinished");
      return kExitBadInput;
    }
  }
  const BatchRange range = ShardRange(items, k, n);
  if (args.plan) return RunPlan(spec, range);
  if (args.output_dir.empty()) {
    PrintError("--output is required (or --plan to print the items without running them)");
    return kExitBadInput;
  }
  std::error_code ec;
  const std::filesystem::path outdir(args.output_dir);
  if (std::filesystem::exists(outdir, ec) && !std::filesystem::is_directory(outdir, ec)) {
    PrintError(DisplayPath(args.output_dir) + ": exists and is not a directory");
    return kExitBadInput;
  }
  std::filesystem::create_directories(outdir, ec);
  if (ec) {
    PrintError(DisplayPath(args.output_dir) + ": cannot create the directory: " + ec.message());
    return kExitBadInput;
  }
  if (!RecordSpec(args.output_dir, args.spec_path, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  const std::string manifest = (outdir / ManifestName(args, items, k, n)).string();

  InstallStopHandlers();
  const auto start = std::chrono::steady_clock::now();
  const std::int64_t total = range.end - range.begin;
  long done = 0, flagged = 0, failed = 0, skipped = 0, run = 0;
  for (std::int64_t index = range.begin; index < range.end && !g_stop.load(); ++index) {
    const std::string name = BatchItemName(index);
    const std::int64_t position = index - range.begin + 1;
    if (BatchItemDone(args.output_dir, name)) {
      ++skipped;
      continue;
    }
    const BatchItem item = ResolveBatchItem(spec, index);
    const auto item_start = std::chrono::steady_clock::now();
    BatchItemResult result = RunBatchItem(spec, item, args.threads, &g_stop);
    if (g_stop.load()) break;  // abandoned: nothing of it is written or recorded
    if (result.status != BatchItemResult::Status::kFailed) {
      const int written = WriteBatchItem(args.output_dir, item, result, &error);
      if (written == 0) {
        ++skipped;  // another process finished it meanwhile
        continue;
      }
      if (written < 0) {
        result.status = BatchItemResult::Status::kFailed;
        result.error = error;
      }
    }
    ++run;
    switch (result.status) {
      case BatchItemResult::Status::kDone:
        ++done;
        break;
      case BatchItemResult::Status::kFlagged:
        ++flagged;
        break;
      case BatchItemResult::Status::kFailed:
        ++failed;
        break;
    }
    if (!AppendManifestLine(manifest, BatchManifestLine(item, result), &error)) {
      PrintWarning(error);
    }
    if (!args.quiet) {
      const double elapsed = SecondsSince(start);
      const double rate = run / elapsed;
      const std::int64_t left = total - position;
      std::printf("%s %s in %s (%lld/%lld; %.3g items/s, about %s left)\n", name.c_str(),
                  BatchStatusName(result.status), FormatSeconds(SecondsSince(item_start)).c_str(),
                  static_cast<long long>(position), static_cast<long long>(total), rate,
                  FormatSeconds(static_cast<double>(left) / rate).c_str());
      std::fflush(stdout);
      if (result.status == BatchItemResult::Status::kFailed) {
        PrintWarning(name + ": " + result.error);
      }
    }
  }
  const bool stopped = g_stop.load();
  if (!args.quiet) {
    std::printf(
        "batch: %lld items [%lld, %lld) of %lld: %ld done, %ld flagged, %ld failed, %ld "
        "skipped%s in %s -> %s\n",
        static_cast<long long>(total), static_cast<long long>(range.begin),
        static_cast<long long>(range.end), static_cast<long long>(spec.count), done, flagged,
        failed, skipped, stopped ? " (stopped by a signal)" : "",
        FormatSeconds(SecondsSince(start)).c_str(), args.output_dir.c_str());
    std::fflush(stdout);
  }
  if (stopped) {
    // End by the signal, as an uncaught one would (exit status 128 + signal in a shell).
    const int signal = g_signal != 0 ? static_cast<int>(g_signal) : SIGTERM;
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
  return failed + flagged > 0 ? kExitUnsolved : kExitSuccess;
}

}  // namespace

Command AddBatchCommand(CLI::App* parent) {
  auto args = std::make_shared<BatchArgs>();
  CLI::App* app = parent->add_subcommand(
      "batch",
      "Make a dataset of grooms from a batch spec (docs/batch.md): each item in its own folder "
      "of OUTDIR, written all or nothing; items already done are skipped. Exit code 0 when every "
      "item of the share is done, 2 when some failed or were flagged (unconverged or unstable "
      "masters), 1 on bad usage or spec (nothing is written).");
  app->add_option("spec", args->spec_path, "Batch spec (JSON, see docs/batch.md)")->required();
  app->add_option("-o,--output", args->output_dir, "Output directory (created if missing)");
  app->add_option("--shard", args->shard,
                  "Run shard K of N (0 <= K < N): the K-th of N contiguous blocks of the items");
  app->add_option("--items", args->items, "Run items A to B - 1 only (A:B)");
  app->add_flag("--plan", args->plan,
                "Print the resolved items (one JSON line each) without running them");
  args->threads_option =
      app->add_option("--threads", args->threads,
                      "Worker threads per item (default 0: all cores); the files do not depend on "
                      "it")
          ->check(CLI::Range(0, 1024));
  app->add_flag("-q,--quiet", args->quiet,
                "Print no progress or summary (errors still go to stderr)");
  // Slurm job arrays (docs/batch.md, "Slurm").
  args->slurm_script_option =
      app->add_option("--slurm-script", args->slurm_script,
                      "Write a Slurm job-array script to FILE (stdout without FILE, or '-') that "
                      "runs the items (of --items) in tasks, task K as --shard K/N; runs nothing. "
                      "Creates OUTDIR and its log directory")
          ->expected(0, 1)
          ->type_name("[FILE]");
  app->add_flag("--slurm-unfinished", args->slurm_unfinished,
                "Print the array's task ids with items not done yet (\"3,7-9\", nothing when all "
                "are done), for sbatch --array=IDS; give the same --items and task options as "
                "for --slurm-script");
  auto slurm = [&](CLI::Option* option) {
    args->slurm_only.push_back(option);
    return option;
  };
  slurm(app->add_option("--slurm-tasks", args->slurm_tasks,
                        "Array tasks N (default: the fewest of at most ceil(items / 1000) items "
                        "each, so at most 1000 tasks)"))
      ->check(CLI::Range(std::int64_t{1}, kMaxSlurmTasks));
  slurm(app->add_option("--slurm-items-per-task", args->slurm_items_per_task,
                        "At most M items per task (N = ceil(items / M))"))
      ->check(CLI::Range(std::int64_t{1}, kMaxBatchItems));
  slurm(app->add_option("--slurm-throttle", args->slurm_throttle,
                        "At most M tasks running at once (--array=0-(N-1)%M)"))
      ->check(CLI::Range(1, 1000000));
  slurm(app->add_option("--slurm-cpus-per-task", args->slurm_cpus,
                        "CPUs per task, and threads per item (default 1)"))
      ->check(CLI::Range(1, 1024));
  slurm(app->add_option("--slurm-time", args->slurm_time,
                        "Time limit per task, as sbatch --time (default 01:00:00)"));
  slurm(app->add_option("--slurm-job-name", args->slurm_job_name,
                        "Job name (default ringlet-SPECNAME)"));
  slurm(app->add_option("--slurm-partition", args->slurm_partition, "Partition (sbatch -p)"));
  slurm(app->add_option("--slurm-account", args->slurm_account, "Account (sbatch -A)"));
  slurm(app->add_option("--slurm-log-dir", args->slurm_log_dir,
                        "Directory of the tasks' logs (default OUTDIR/slurm-logs)"));
  slurm(app->add_option("--slurm-option", args->slurm_options,
                        "A further #SBATCH option, as --slurm-option=--name=value (repeatable: "
                        "--slurm-option=--mem=2G --slurm-option=--qos=low)"))
      ->allow_extra_args(false);
  return Command{app, [args] { return RunBatch(*args); }};
}

}  // namespace ringlet::cli
