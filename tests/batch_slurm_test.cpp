// Slurm job-array scripts (batch_slurm.h, docs/batch.md, "Slurm"): the number of tasks and the
// items per task; the checks of the options that go on #SBATCH lines; the script, run by bash
// with a stand-in binary that prints its arguments (bash is the judge of the quoting); the
// unfinished tasks of a dataset and their --array syntax. tests/slurm_test.sh submits the
// script to a real Slurm.
#include "ringlet/batch_slurm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace ringlet {
namespace {

namespace fs = std::filesystem;

std::int64_t Tasks(std::int64_t items, std::int64_t tasks, std::int64_t per_task) {
  std::int64_t n = -1;
  std::string error;
  EXPECT_TRUE(SlurmTaskCount(items, tasks, per_task, &n, &error)) << error;
  return n;
}

TEST(SlurmArray, TaskCountDefaultsToAtMostAThousandTasks) {
  EXPECT_EQ(Tasks(12, 0, 0), 12);      // one item each
  EXPECT_EQ(Tasks(1000, 0, 0), 1000);  // still one each
  EXPECT_EQ(Tasks(1001, 0, 0), 501);   // 2 each: ceil(1001 / 2)
  EXPECT_EQ(Tasks(2500, 0, 0), 834);   // 3 each: ceil(2500 / 3)
  EXPECT_EQ(Tasks(kMaxBatchItems, 0, 0), 1000);
  EXPECT_EQ(Tasks(12, 3, 0), 3);
  EXPECT_EQ(Tasks(12, 0, 5), 3);  // 5, 5, 2 -> ShardRange: 4, 4, 4
  EXPECT_EQ(Tasks(12, 0, 100), 1);
}

TEST(SlurmArray, NoShardHasMoreItemsThanAsked) {
  // ShardRange's blocks of ceil(L / M) tasks hold at most M items, and cover [0, L) once.
  for (const std::int64_t length : {1, 7, 12, 100, 1001, 99991}) {
    for (const std::int64_t per_task : {1, 2, 3, 7, 1000}) {
      const std::int64_t n = Tasks(length, 0, per_task);
      std::int64_t next = 0;
      for (std::int64_t k = 0; k < n; ++k) {
        const BatchRange shard =
            ShardRange(BatchRange{0, length}, static_cast<int>(k), static_cast<int>(n));
        EXPECT_EQ(shard.begin, next);
        EXPECT_GE(shard.end - shard.begin, 1) << length << " " << per_task << " " << k;
        EXPECT_LE(shard.end - shard.begin, per_task) << length << " " << per_task << " " << k;
        next = shard.end;
      }
      EXPECT_EQ(next, length);
    }
  }
}

TEST(SlurmArray, BadTaskCountsAreOneLineNamingTheOption) {
  std::int64_t n = 0;
  std::string error;
  EXPECT_FALSE(SlurmTaskCount(12, 13, 0, &n, &error));
  EXPECT_EQ(error, "--slurm-tasks: 13 tasks for 12 items: expected at most one task per item");
  EXPECT_FALSE(SlurmTaskCount(12, 3, 4, &n, &error));
  EXPECT_NE(error.find("--slurm-tasks and --slurm-items-per-task"), std::string::npos) << error;
  EXPECT_FALSE(SlurmTaskCount(kMaxBatchItems, 0, 1, &n, &error));
  EXPECT_NE(error.find("--slurm-items-per-task: 1000000000 tasks: expected at most 1000000"),
            std::string::npos)
      << error;
}

TEST(SlurmArray, TimeLimitsAsSbatchTakesThem) {
  std::string error;
  for (const char* good : {"30", "30:00", "1:00:00", "01:00:00", "2-0", "2-12:30", "2-12:30:00",
                           "UNLIMITED", "infinite", "0:30"}) {
    EXPECT_TRUE(CheckSlurmTime(good, &error)) << good << ": " << error;
  }
  for (const char* bad :
       {"", "0", "00:00:00", "1h", "1:2:3:4", "-1", "1-", ":30", "1::0", "1 hour", "0-0"}) {
    error.clear();
    EXPECT_FALSE(CheckSlurmTime(bad, &error)) << bad;
    EXPECT_EQ(error.rfind("--slurm-time: ", 0), 0U) << error;
  }
}

TEST(SlurmArray, WordsAndExtraOptionsForSbatchLines) {
  std::string error;
  EXPECT_TRUE(CheckSlurmWord("--slurm-partition", "gpu-a100", &error));
  EXPECT_TRUE(CheckSlurmWord("--slurm-log-dir", "/scratch/me/logs", &error));
  for (const char* bad : {"", "two words", "a'b", "a\"b", "a%b", "a\nb", "a$b"}) {
    error.clear();
    EXPECT_FALSE(CheckSlurmWord("--slurm-account", bad, &error)) << bad;
    EXPECT_EQ(error.rfind("--slurm-account: ", 0), 0U) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;  // one line, whatever the value
  }
  for (const char* good : {"--mem=2G", "--qos=low", "--exclusive", "--mail-type=END,FAIL",
                           "--constraint=skylake|icelake"}) {
    EXPECT_TRUE(CheckSlurmExtraOption(good, &error)) << good << ": " << error;
  }
  for (const char* bad : {"mem=2G", "-p", "--", "--Mem=2G", "--mem=2 G", "--mem='2G'"}) {
    error.clear();
    EXPECT_FALSE(CheckSlurmExtraOption(bad, &error)) << bad;
    EXPECT_EQ(error.rfind("--slurm-option: expected", 0), 0U) << error;
  }
  for (const char* own : {"--array=0-3", "--time=5", "--output=x", "--cpus-per-task=2"}) {
    EXPECT_FALSE(CheckSlurmExtraOption(own, &error)) << own;
    EXPECT_NE(error.find("is set by the script itself"), std::string::npos) << error;
  }
}

class SlurmScriptTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ringlet_slurm_script_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST_F(SlurmScriptTest, DirectivesAndTheCommandAsBashRunsIt) {
  // A stand-in binary in a folder whose name needs quoting: prints its arguments, one a line.
  const fs::path odd = dir_ / "it's a $dir \"x\"";
  fs::create_directories(odd);
  const fs::path binary = odd / "ringlet";
  {
    std::ofstream out(binary);
    out << "#!/bin/sh\nprintf '%s\\n' \"$@\"\n";
  }
  fs::permissions(binary, fs::perms::owner_all);
  SlurmArrayOptions options;
  options.binary = binary.string();
  options.spec_path = (odd / "spec 1.json").string();
  options.output_dir = (odd / "out").string();
  options.log_dir = "/scratch/logs";
  options.items = BatchRange{2, 10};
  options.items_option = true;
  options.spec_count = 12;
  options.tasks = 4;
  options.throttle = 2;
  options.cpus_per_task = 3;
  options.time = "0-2:00:00";
  options.job_name = "ringlet-small";
  options.partition = "short";
  options.account = "hair";
  options.extra = {"--mem=2G"};
  const std::string text = SlurmArrayScript(options);
  EXPECT_EQ(text.rfind("#!/bin/bash\n", 0), 0U);
  std::vector<std::string> directives;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("#SBATCH ", 0) == 0) directives.push_back(line.substr(8));
  }
  const std::vector<std::string> expected = {
      "--job-name=ringlet-small", "--array=0-3%2",    "--ntasks=1",
      "--cpus-per-task=3",        "--time=0-2:00:00", "--output=/scratch/logs/%x-%A_%a.out",
      "--partition=short",        "--account=hair",   "--mem=2G"};
  EXPECT_EQ(directives, expected);
  // sbatch reads directives up to the first command: every #SBATCH line comes before it.
  const size_t first_command = text.find("\nset -u\n");
  ASSERT_NE(first_command, std::string::npos);
  EXPECT_LT(text.rfind("#SBATCH"), first_command);

  const std::string script = (dir_ / "job.sh").string();
  std::ofstream(script) << text;
  const std::string printed = (dir_ / "printed.txt").string();
  const std::string command = "env SLURM_ARRAY_TASK_ID=2 SLURM_CPUS_PER_TASK=5 bash '" + script +
                              "' > '" + printed + "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const std::vector<std::string> args = {
      "batch", options.spec_path, "-o",  options.output_dir, "--items",
      "2:10",  "--shard",         "2/4", "--threads",        "5"};
  EXPECT_EQ(Lines(printed), args);
  // Without SLURM_CPUS_PER_TASK the threads are --cpus-per-task's.
  const std::string bare = "env -u SLURM_CPUS_PER_TASK SLURM_ARRAY_TASK_ID=0 bash '" + script +
                           "' > '" + printed + "' 2>&1";
  ASSERT_EQ(std::system(bare.c_str()), 0) << bare;
  EXPECT_EQ(Lines(printed).back(), "3");
  // Run outside an array: the script says so and fails, running nothing.
  const std::string outside =
      "env -u SLURM_ARRAY_TASK_ID bash '" + script + "' > '" + printed + "' 2>&1";
  EXPECT_NE(std::system(outside.c_str()), 0);
  const std::vector<std::string> said = Lines(printed);
  ASSERT_EQ(said.size(), 1U);
  EXPECT_NE(said[0].find("SLURM_ARRAY_TASK_ID: is not set: submit this script with sbatch"),
            std::string::npos)
      << said[0];
}

TEST_F(SlurmScriptTest, WholeSpecWithoutItemsOptionOrThrottle) {
  SlurmArrayOptions options;
  options.binary = "/opt/ringlet/bin/ringlet";
  options.spec_path = "/data/spec.json";
  options.output_dir = "/data/out";
  options.log_dir = "/data/out/slurm-logs";
  options.items = BatchRange{0, 12};
  options.spec_count = 12;
  options.tasks = 12;
  const std::string text = SlurmArrayScript(options);
  EXPECT_NE(text.find("\n#SBATCH --array=0-11\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("--partition"), std::string::npos) << text;
  EXPECT_EQ(text.find("--account"), std::string::npos) << text;
  EXPECT_NE(text.find("\nexec '/opt/ringlet/bin/ringlet' batch '/data/spec.json' -o '/data/out' "
                      "--shard \"${SLURM_ARRAY_TASK_ID}/12\" --threads "
                      "\"${SLURM_CPUS_PER_TASK:-1}\"\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(SlurmArrayScript(options), text);  // deterministic
}

TEST_F(SlurmScriptTest, UnfinishedTasksFromTheDoneMarkers) {
  // Items [0, 10) in 4 tasks: ShardRange gives [0, 2), [2, 5), [5, 7), [7, 10).
  const BatchRange items{0, 10};
  for (int index = 0; index < 10; ++index) {
    if (index == 3 || index == 9) continue;
    const fs::path folder = dir_ / BatchItemName(index);
    fs::create_directories(folder);
    std::ofstream(folder / "done").flush();
  }
  fs::create_directories(dir_ / BatchItemName(9));  // a folder without done is not done
  EXPECT_EQ(UnfinishedSlurmTasks(dir_.string(), items, 4), (std::vector<std::int64_t>{1, 3}));
  EXPECT_EQ(UnfinishedSlurmTasks(dir_.string(), items, 10), (std::vector<std::int64_t>{3, 9}));
  EXPECT_EQ(UnfinishedSlurmTasks(dir_.string(), BatchRange{4, 9}, 5),
            (std::vector<std::int64_t>{}));
  EXPECT_EQ(UnfinishedSlurmTasks((dir_ / "missing").string(), items, 4),
            (std::vector<std::int64_t>{0, 1, 2, 3}));
}

TEST(SlurmArray, ArrayIdsAsSbatchTakesThem) {
  EXPECT_EQ(SlurmArrayIds({}), "");
  EXPECT_EQ(SlurmArrayIds({4}), "4");
  EXPECT_EQ(SlurmArrayIds({0, 1, 2, 5, 7, 8}), "0-2,5,7-8");
  EXPECT_EQ(SlurmArrayIds({1, 3, 5}), "1,3,5");
}

}  // namespace
}  // namespace ringlet
