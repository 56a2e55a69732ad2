// Slurm job-array scripts for `ringlet batch` (batch_slurm.h, docs/batch.md, "Slurm").
#include "ringlet/batch_slurm.h"

#include <cstdint>
#include <string>
#include <vector>

#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

bool AllDigits(const std::string& text) {
  if (text.empty() || text.size() > 9) return false;
  for (const char c : text) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

// 'text' for bash: single quotes, each ' written as '\''.
std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

// Printable ASCII, no space, quote, backslash (or '%' unless allowed).
bool PlainWord(const std::string& text, bool allow_percent) {
  for (const char c : text) {
    if (c <= ' ' || c > '~' || c == '"' || c == '\'' || c == '\\' || c == '`' || c == '$' ||
        (c == '%' && !allow_percent)) {
      return false;
    }
  }
  return !text.empty();
}

}  // namespace

bool SlurmTaskCount(std::int64_t items, std::int64_t tasks, std::int64_t items_per_task,
                    std::int64_t* count, std::string* error) {
  if (tasks > 0 && items_per_task > 0) {
    *error = "--slurm-tasks and --slurm-items-per-task: give one of them (each sets the other)";
    return false;
  }
  std::int64_t n = 0;
  if (tasks > 0) {
    if (tasks > items) {
      *error = "--slurm-tasks: " + std::to_string(tasks) + " tasks for " + std::to_string(items) +
               " items: expected at most one task per item";
      return false;
    }
    n = tasks;
  } else {
    const std::int64_t per_task = items_per_task > 0
                                      ? items_per_task
                                      : (items + kDefaultSlurmMaxTasks - 1) / kDefaultSlurmMaxTasks;
    n = (items + per_task - 1) / per_task;
  }
  if (n > kMaxSlurmTasks) {
    *error = (tasks > 0 ? "--slurm-tasks: " : "--slurm-items-per-task: ") + std::to_string(n) +
             " tasks: expected at most " + std::to_string(kMaxSlurmTasks) +
             " (give more items per task)";
    return false;
  }
  *count = n;
  return true;
}

bool CheckSlurmTime(const std::string& text, std::string* error) {
  if (text == "UNLIMITED" || text == "INFINITE" || text == "unlimited" || text == "infinite") {
    return true;
  }
  // [D-]a[:b[:c]] with digits; "D-H", "D-H:M", "D-H:M:S"; or "M", "M:S", "H:M:S".
  std::string rest = text;
  const size_t dash = rest.find('-');
  bool ok = true;
  if (dash != std::string::npos) {
    ok = AllDigits(rest.substr(0, dash));
    rest = rest.substr(dash + 1);
  }
  std::vector<std::string> parts;
  size_t start = 0;
  while (ok) {
    const size_t colon = rest.find(':', start);
    parts.push_back(
        rest.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  ok = ok && !parts.empty() && parts.size() <= 3;
  bool nonzero = false;
  for (const std::string& part : parts) {
    ok = ok && AllDigits(part);
    nonzero = nonzero || part.find_first_not_of('0') != std::string::npos;
  }
  if (dash != std::string::npos) {
    nonzero = nonzero || text.substr(0, dash).find_first_not_of('0') != std::string::npos;
  }
  if (!ok || !nonzero) {
    *error =
        "--slurm-time: expected a time limit as sbatch --time takes it (minutes, M:S, H:M:S, "
        "D-H, D-H:M, D-H:M:S or UNLIMITED), not zero, got \"" +
        DisplayPath(text) + "\"";
    return false;
  }
  return true;
}

bool CheckSlurmWord(const std::string& option, const std::string& value, std::string* error) {
  if (!PlainWord(value, false)) {
    *error = option +
             ": expected a non-empty word of printable ASCII without spaces, quotes, "
             "backslashes, '$' or '%' (it goes on an #SBATCH line as is), got \"" +
             DisplayPath(value) + "\"";
    return false;
  }
  return true;
}

bool CheckSlurmExtraOption(const std::string& option, std::string* error) {
  const size_t equals = option.find('=');
  const std::string name = option.substr(0, equals);
  bool ok = name.size() > 2 && name.compare(0, 2, "--") == 0;
  for (size_t i = 2; ok && i < name.size(); ++i) {
    const char c = name[i];
    ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-';
  }
  if (ok && equals != std::string::npos) ok = PlainWord(option.substr(equals + 1), true);
  if (!ok) {
    *error =
        "--slurm-option: expected an sbatch option as --name or --name=value (no spaces or "
        "quotes), got \"" +
        DisplayPath(option) + "\"";
    return false;
  }
  for (const char* own : {"--array", "--output", "--error", "--job-name", "--cpus-per-task",
                          "--ntasks", "--time", "--partition", "--account"}) {
    if (name == own) {
      *error = "--slurm-option: " + name +
               " is set by the script itself (give --slurm-tasks, --slurm-items-per-task, "
               "--slurm-throttle, --slurm-cpus-per-task, --slurm-time, --slurm-job-name, "
               "--slurm-partition, --slurm-account or --slurm-log-dir instead)";
      return false;
    }
  }
  return true;
}

std::string SlurmArrayScript(const SlurmArrayOptions& o) {
  const std::int64_t length = o.items.end - o.items.begin;
  const std::int64_t most = (length + o.tasks - 1) / o.tasks;
  const std::int64_t least = length / o.tasks;
  std::string s = "#!/bin/bash\n";
  s += "# A Slurm job array made by `ringlet batch --slurm-script` (docs/batch.md, \"Slurm\"):\n";
  s += "# items " + std::to_string(o.items.begin) + " to " + std::to_string(o.items.end - 1) +
       " of the " + std::to_string(o.spec_count) + " of " + DisplayPath(o.spec_path) + "\n";
  s += "# in " + std::to_string(o.tasks) + " tasks of " +
       (least == most ? std::to_string(most)
                      : std::to_string(least) + " or " + std::to_string(most)) +
       (most == 1 ? " item" : " items") + " each (task K runs --shard K/" +
       std::to_string(o.tasks) + ").\n";
  s += "# Submit: sbatch THIS_FILE. Resubmit the unfinished tasks (cancelled, timed out, failed\n";
  s += "# nodes; items already done are skipped): sbatch --array=IDS THIS_FILE, IDS from\n";
  s += "#   ringlet batch SPEC -o OUTDIR --slurm-unfinished (with the same --items and\n";
  s += "#   --slurm-tasks / --slurm-items-per-task as this script).\n";
  s += "#SBATCH --job-name=" + o.job_name + "\n";
  s += "#SBATCH --array=0-" + std::to_string(o.tasks - 1) +
       (o.throttle > 0 ? "%" + std::to_string(o.throttle) : std::string()) + "\n";
  s += "#SBATCH --ntasks=1\n";
  s += "#SBATCH --cpus-per-task=" + std::to_string(o.cpus_per_task) + "\n";
  s += "#SBATCH --time=" + o.time + "\n";
  s += "#SBATCH --output=" + o.log_dir + "/%x-%A_%a.out\n";
  if (!o.partition.empty()) s += "#SBATCH --partition=" + o.partition + "\n";
  if (!o.account.empty()) s += "#SBATCH --account=" + o.account + "\n";
  for (const std::string& extra : o.extra) s += "#SBATCH " + extra + "\n";
  s += "set -u\n";
  s += ": \"${SLURM_ARRAY_TASK_ID:?is not set: submit this script with sbatch (it is a job "
       "array)}\"\n";
  s += "exec " + ShellQuote(o.binary) + " batch " + ShellQuote(o.spec_path) + " -o " +
       ShellQuote(o.output_dir);
  if (o.items_option) {
    s += " --items " + std::to_string(o.items.begin) + ":" + std::to_string(o.items.end);
  }
  s += " --shard \"${SLURM_ARRAY_TASK_ID}/" + std::to_string(o.tasks) +
       "\" --threads \"${SLURM_CPUS_PER_TASK:-" + std::to_string(o.cpus_per_task) + "}\"\n";
  return s;
}

std::vector<std::int64_t> UnfinishedSlurmTasks(const std::string& outdir, const BatchRange& items,
                                               std::int64_t tasks) {
  std::vector<std::int64_t> ids;
  for (std::int64_t k = 0; k < tasks; ++k) {
    const BatchRange shard = ShardRange(items, static_cast<int>(k), static_cast<int>(tasks));
    for (std::int64_t index = shard.begin; index < shard.end; ++index) {
      if (!BatchItemDone(outdir, BatchItemName(index))) {
        ids.push_back(k);
        break;
      }
    }
  }
  return ids;
}

std::string SlurmArrayIds(const std::vector<std::int64_t>& ids) {
  std::string text;
  for (size_t i = 0; i < ids.size();) {
    size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    if (!text.empty()) text += ",";
    text += std::to_string(ids[i]);
    if (j > i) text += "-" + std::to_string(ids[j]);
    i = j + 1;
  }
  return text;
}

}  // namespace ringlet
