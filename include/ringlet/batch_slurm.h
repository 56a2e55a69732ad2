// Slurm job arrays for `ringlet batch` (docs/batch.md, "Slurm"): the script that runs a batch
// spec's items as the tasks of one job array, each task one shard (`ringlet batch SPEC -o OUTDIR
// --shard $SLURM_ARRAY_TASK_ID/N`), and the tasks whose items are not all done yet (to resubmit
// them with `sbatch --array=IDS`). The items, their bytes and the bookkeeping are batch.h's: a
// task only picks its shard.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ringlet/batch.h"

namespace ringlet {

/// Most tasks of one array: ParseShard's bound on N.
inline constexpr std::int64_t kMaxSlurmTasks = 1000000;
/// The tasks of an array by default at most: Slurm's default MaxArraySize is 1001 (task ids 0
/// to 1000), so the default array submits on a cluster that kept it.
inline constexpr std::int64_t kDefaultSlurmMaxTasks = 1000;

/// The number of array tasks for `items` items: `tasks` when > 0, else ceil(items /
/// items_per_task) when items_per_task > 0, else the fewest tasks of at most
/// ceil(items / kDefaultSlurmMaxTasks) items each (at most 1000 tasks). Every task then gets
/// ShardRange's contiguous block of at most ceil(items / tasks) items. False with one line naming
/// the option ("--slurm-tasks", "--slurm-items-per-task") when both are given, or when the tasks
/// would be fewer than 1, more than the items or more than kMaxSlurmTasks.
bool SlurmTaskCount(std::int64_t items, std::int64_t tasks, std::int64_t items_per_task,
                    std::int64_t* count, std::string* error);

/// What the job-array script says.
struct SlurmArrayOptions {
  std::string binary;      ///< the ringlet executable, absolute
  std::string spec_path;   ///< the spec, absolute
  std::string output_dir;  ///< the dataset's directory, absolute
  std::string log_dir;     ///< where the tasks' logs go (must exist when they start), absolute
  BatchRange items;        ///< the items the array runs
  /// Pass `--items A:B` to every task (the array runs part of the spec).
  bool items_option = false;
  std::int64_t spec_count = 0;             ///< the spec's items (for the script's comment)
  std::int64_t tasks = 1;                  ///< N: task ids 0 to N - 1, task K runs shard K/N
  int throttle = 0;                        ///< at most this many tasks at once (`%M`); 0: no limit
  int cpus_per_task = 1;                   ///< --cpus-per-task, and the threads of each item
  std::string time = "01:00:00";           ///< --time: each task's time limit, as sbatch takes it
  std::string job_name = "ringlet-batch";  ///< --job-name (`%x` in the log file names)
  std::string partition, account;          ///< empty: the site's defaults
  std::vector<std::string> extra;          ///< further `#SBATCH` options, each "--name[=value]"
};

/// Checks a Slurm time limit as sbatch --time takes it: "M", "M:S", "H:M:S", "D-H", "D-H:M",
/// "D-H:M:S" (decimal digits) or "UNLIMITED" / "INFINITE"; not 0. False with one line.
bool CheckSlurmTime(const std::string& text, std::string* error);

/// Checks a value that goes on an `#SBATCH` line as is (a partition, an account, a job name, a
/// log directory): not empty, printable ASCII without spaces, quotes, backslashes or `%` (sbatch
/// does not unquote directives, and `%` is a file-name pattern). False with one line naming
/// `option`.
bool CheckSlurmWord(const std::string& option, const std::string& value, std::string* error);

/// Checks an extra `#SBATCH` option: "--name" or "--name=value", the name of lower-case letters,
/// digits and '-', the value printable ASCII without spaces or quotes; not one the script sets
/// itself (--array, --output, --error, --job-name, --cpus-per-task, --ntasks, --time,
/// --partition, --account: they have their own options). False with one line.
bool CheckSlurmExtraOption(const std::string& option, std::string* error);

/// The job-array script (bash): `#SBATCH` lines (--job-name, --array=0-(N-1)[%M], --ntasks=1,
/// --cpus-per-task, --time, --output=LOG_DIR/%x-%A_%a.out, partition, account, extras), then one
/// command, `exec BINARY batch SPEC -o OUTDIR [--items A:B] --shard $SLURM_ARRAY_TASK_ID/N
/// --threads ${SLURM_CPUS_PER_TASK:-C}` with the paths single-quoted. Deterministic.
std::string SlurmArrayScript(const SlurmArrayOptions& options);

/// The tasks (of `tasks` shards of `items`) with an item whose folder in outdir has no `done`
/// marker, ascending.
std::vector<std::int64_t> UnfinishedSlurmTasks(const std::string& outdir, const BatchRange& items,
                                               std::int64_t tasks);

/// Task ids as sbatch --array takes them: ascending ids with runs of consecutive ids as ranges,
/// "0,3-5,9"; "" for none.
std::string SlurmArrayIds(const std::vector<std::int64_t>& ids);

}  // namespace ringlet
