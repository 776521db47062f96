// --slurm: the scripts written for a job array and its merge, run by sh
// with a stand-in strata and sbatch that record their arguments, so that
// what reaches strata is checked word for word, whatever the paths hold.
#include "campaign/slurm.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

#include <gtest/gtest.h>

#include "campaign/campaign_test_support.h"

namespace strata::campaign {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

// A path with what a shell would take for code if it were not quoted.
const std::string kNasty = "it's a \"spec\" $(touch pwned) `touch pwned2` ; & | * \\n\nnext line";

// An executable file at path that writes its arguments, NUL-separated, to
// $FAKE_ARGS and exits with $FAKE_EXIT (default 0), printing $FAKE_OUT.
void write_recorder(const std::string& path) {
  std::ofstream(path) << "#!/bin/sh\n"
                         "printf '%s\\0' \"$@\" >> \"$FAKE_ARGS\"\n"
                         "printf '%s\\n' \"${FAKE_OUT:-}\"\n"
                         "exit \"${FAKE_EXIT:-0}\"\n";
  ::chmod(path.c_str(), 0755);
}

// Every argument the recorder was given, call after call.
std::vector<std::string> recorded(const std::string& file) {
  const std::string text = testing::read_text(file);
  std::vector<std::string> words;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\0') {
      words.push_back(text.substr(start, i - start));
      start = i + 1;
    }
  }
  return words;
}

// Runs `sh script` in dir with the environment assignments env (sh words);
// its exit code.
int run_sh(const std::string& dir, const std::string& env, const std::string& script) {
  const std::string cmd = "cd " + shell_quote(dir) + " && env " + env + " /bin/sh " + shell_quote(script) +
                          " >/dev/null 2>" + shell_quote(dir + "/sh.err");
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Sets (or, with nullptr, unsets) an environment variable for a scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    value ? ::setenv(name, value, 1) : ::unsetenv(name);
  }
  ~ScopedEnv() { old_ ? ::setenv(name_, old_->c_str(), 1) : ::unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

struct Fixture {
  TempDir tmp;
  std::string root = tmp.file(kNasty);
  std::string strata, spec, dir, args;
  SlurmOptions options;

  Fixture() {
    fs::create_directories(root + "/bin " + kNasty);
    strata = root + "/bin " + kNasty + "/strata";
    write_recorder(strata);
    spec = tmp.write(kNasty + "/campaign " + kNasty + ".toml", "");
    dir = root + "/out " + kNasty;
    args = tmp.file("args");
    options.strata = strata;
    options.spec = spec;
    options.dir = dir;
    options.shards = 3;
    options.cpus_per_task = 2;
    options.task_args = {"--keep-logs", "failed"};
    options.spec_args = {"--max-cases", "50"};
  }
};

TEST(CampaignSlurm, ShellQuoteMakesOneWordOfAnything) {
  EXPECT_EQ("'plain'", shell_quote("plain"));
  EXPECT_EQ("''", shell_quote(""));
  EXPECT_EQ("'it'\\''s'", shell_quote("it's"));
  EXPECT_EQ("'$(x) \"y\"'", shell_quote("$(x) \"y\""));
}

TEST(CampaignSlurm, ATaskRunsItsShardWithThePathsAsTheyAre) {
  Fixture f;
  auto scripts = slurm_scripts(f.options);
  ASSERT_TRUE(scripts.ok()) << scripts.error().message;
  const std::string& array = scripts.value().array;
  EXPECT_NE(std::string::npos, array.find("\n#SBATCH --array=0-2\n")) << array;
  EXPECT_NE(std::string::npos, array.find("\n#SBATCH --cpus-per-task=2\n")) << array;
  EXPECT_NE(std::string::npos, array.find("\n#SBATCH --output=slurm-%A_%a.out\n")) << array;
  EXPECT_EQ(std::string::npos, array.find("--partition")) << "no partition asked for";
  ASSERT_TRUE(write_slurm_scripts(f.dir, scripts.value()).ok());
  for (const char* name : {"campaign.sbatch", "merge.sbatch", "submit.sh"}) {
    struct stat st {};
    ASSERT_EQ(0, ::stat((f.dir + "/" + name).c_str(), &st)) << name;
    EXPECT_TRUE(st.st_mode & S_IXUSR) << name << " is executable";
  }

  const std::string env = "FAKE_ARGS=" + shell_quote(f.args) + " SLURM_ARRAY_TASK_ID=1";
  EXPECT_EQ(0, run_sh(f.dir, env, f.dir + "/campaign.sbatch")) << testing::read_text(f.dir + "/sh.err");
  const std::vector<std::string> expected{"campaign",         f.spec, "--shard", "1/3",         "--out",
                                          f.dir + "/shard-1", "-j",   "2",       "--keep-logs", "failed",
                                          "--max-cases",      "50"};
  EXPECT_EQ(expected, recorded(f.args));
  EXPECT_FALSE(fs::exists(f.dir + "/pwned")) << "a path ran as code";
  EXPECT_FALSE(fs::exists(f.dir + "/pwned2")) << "a path ran as code";

  // Slurm's CPUs per task, when it sets them, are the task's -j.
  fs::remove(f.args);
  EXPECT_EQ(0, run_sh(f.dir, env + " SLURM_CPUS_PER_TASK=5", f.dir + "/campaign.sbatch"));
  EXPECT_EQ("5", recorded(f.args).at(7));
}

TEST(CampaignSlurm, ATaskWithFailingCasesSucceedsAndAnyOtherErrorFailsIt) {
  Fixture f;
  auto scripts = slurm_scripts(f.options);
  ASSERT_TRUE(scripts.ok());
  ASSERT_TRUE(write_slurm_scripts(f.dir, scripts.value()).ok());
  const std::string env = "FAKE_ARGS=" + shell_quote(f.args) + " SLURM_ARRAY_TASK_ID=0";
  EXPECT_EQ(0, run_sh(f.dir, env + " FAKE_EXIT=1", f.dir + "/campaign.sbatch"));
  EXPECT_EQ(65, run_sh(f.dir, env + " FAKE_EXIT=65", f.dir + "/campaign.sbatch"));
  EXPECT_EQ(143, run_sh(f.dir, env + " FAKE_EXIT=143", f.dir + "/campaign.sbatch"));
  // Not an array task: refused, nothing run.
  fs::remove(f.args);
  EXPECT_NE(0, run_sh(f.dir, "FAKE_ARGS=" + shell_quote(f.args), f.dir + "/campaign.sbatch"));
  EXPECT_FALSE(fs::exists(f.args));
}

TEST(CampaignSlurm, TheMergeJoinsEveryShardIntoMerged) {
  Fixture f;
  auto scripts = slurm_scripts(f.options);
  ASSERT_TRUE(scripts.ok());
  ASSERT_TRUE(write_slurm_scripts(f.dir, scripts.value()).ok());
  EXPECT_EQ(0, run_sh(f.dir, "FAKE_ARGS=" + shell_quote(f.args), f.dir + "/merge.sbatch"))
      << testing::read_text(f.dir + "/sh.err");
  const std::vector<std::string> expected{
      "campaign",         f.spec,  "--merge",         f.dir + "/shard-0", f.dir + "/shard-1",
      f.dir + "/shard-2", "--out", f.dir + "/merged", "--max-cases",      "50"};
  EXPECT_EQ(expected, recorded(f.args));
  EXPECT_EQ(7, run_sh(f.dir, "FAKE_EXIT=7 FAKE_ARGS=" + shell_quote(f.args), f.dir + "/merge.sbatch"))
      << "the merge's exit code is the job's";
}

TEST(CampaignSlurm, SubmitShAndSubmitSlurmMakeTheMergeDependOnTheArray) {
  Fixture f;
  const ScopedEnv no_conf("SLURM_CONF", nullptr);
  f.options.partition = "debug";
  f.options.time = "0-01:30:00";
  f.options.sbatch_args = {"--account=ocean"};
  auto scripts = slurm_scripts(f.options);
  ASSERT_TRUE(scripts.ok()) << scripts.error().message;
  for (const std::string* s : {&scripts.value().array, &scripts.value().merge}) {
    EXPECT_NE(std::string::npos, s->find("\n#SBATCH --partition=debug\n#SBATCH --time=0-01:30:00\n"
                                         "#SBATCH --account=ocean\n"))
        << *s;
  }
  ASSERT_TRUE(write_slurm_scripts(f.dir, scripts.value()).ok());
  const std::string bin = f.tmp.file("sbatch-bin");
  fs::create_directories(bin);
  write_recorder(bin + "/sbatch");

  const std::string env =
      "PATH=" + shell_quote(bin + ":/usr/bin:/bin") + " FAKE_ARGS=" + shell_quote(f.args) + " FAKE_OUT='4242;cluster'";
  EXPECT_EQ(0, run_sh(f.dir, env, f.dir + "/submit.sh")) << testing::read_text(f.dir + "/sh.err");
  const std::vector<std::string> expected{"--parsable",           "--chdir=" + f.dir, f.dir + "/campaign.sbatch",
                                          "--parsable",           "--chdir=" + f.dir, "--dependency=afterok:4242",
                                          f.dir + "/merge.sbatch"};
  EXPECT_EQ(expected, recorded(f.args));

  // --submit: the same two calls.
  fs::remove(f.args);
  ::setenv("FAKE_ARGS", f.args.c_str(), 1);
  ::setenv("FAKE_OUT", "77", 1);
  auto jobs = submit_slurm(f.dir, bin + "/sbatch", 30);
  ASSERT_TRUE(jobs.ok()) << jobs.error().message;
  EXPECT_EQ("77", jobs.value().array_id);
  EXPECT_EQ("77", jobs.value().merge_id);
  std::vector<std::string> expected77 = expected;
  expected77[5] = "--dependency=afterok:77";
  EXPECT_EQ(expected77, recorded(f.args));

  // sbatch failing: its exit and its message.
  std::ofstream(bin + "/sbatch") << "#!/bin/sh\necho 'sbatch: error: invalid partition specified: debug' >&2\nexit 1\n";
  auto failed = submit_slurm(f.dir, bin + "/sbatch", 30);
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(std::string::npos, failed.error().message.find("failed (exit 1): sbatch: error: invalid partition"))
      << failed.error().message;
  ::unsetenv("FAKE_ARGS");
  ::unsetenv("FAKE_OUT");
}

TEST(CampaignSlurm, ValuesThatCannotBeWrittenSafelyAreRefusedByName) {
  Fixture f;
  auto refused = [&](auto change, const std::string& says) {
    SlurmOptions o = f.options;
    change(o);
    auto r = slurm_scripts(o);
    ASSERT_FALSE(r.ok()) << says;
    EXPECT_EQ(core::ErrorCode::InvalidInput, r.error().code);
    EXPECT_NE(std::string::npos, r.error().message.find(says)) << r.error().message;
  };
  refused([](SlurmOptions& o) { o.partition = "a b"; }, "--partition 'a b'");
  refused([](SlurmOptions& o) { o.partition = "x\n#SBATCH --wrap=y"; }, "--partition");
  refused([](SlurmOptions& o) { o.time = "5 min"; }, "--time '5 min': not a Slurm time");
  refused([](SlurmOptions& o) { o.sbatch_args = {"--account=x\nrm -rf /"}; }, "--sbatch");
  refused([](SlurmOptions& o) { o.sbatch_args = {"account=x"}; }, "--sbatch 'account=x'");
  refused([](SlurmOptions& o) { o.spec = "campaign.toml"; }, "the spec must be an absolute path");
  refused([](SlurmOptions& o) { o.shards = 0; }, "--shards 0");
  for (const char* ok : {"90", "30:00", "1:30:00", "2-12", "2-12:30", "2-12:30:00", "UNLIMITED"}) {
    SlurmOptions o = f.options;
    o.time = ok;
    EXPECT_TRUE(slurm_scripts(o).ok()) << ok;
  }
}

TEST(CampaignSlurm, TheFolderIsNewOrAnEarlierSlurmCampaign) {
  Fixture f;
  auto scripts = slurm_scripts(f.options);
  ASSERT_TRUE(scripts.ok());
  const std::string other = f.tmp.file("other");
  fs::create_directories(other);
  f.tmp.write("other/notes.txt", "mine");
  auto r = write_slurm_scripts(other, scripts.value());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(std::string::npos, r.error().message.find("holds no campaign.sbatch")) << r.error().message;
  fs::create_symlink(other, f.tmp.file("link"));
  EXPECT_FALSE(write_slurm_scripts(f.tmp.file("link"), scripts.value()).ok());
  ASSERT_TRUE(write_slurm_scripts(f.dir, scripts.value()).ok());
  fs::create_directories(f.dir + "/shard-0");
  EXPECT_TRUE(write_slurm_scripts(f.dir, scripts.value()).ok()) << "written again over an earlier one";
}

TEST(CampaignSlurm, SbatchsMessagesSayWhenThereIsNoSlurmToSubmitTo) {
  // Slurm 22.05's sbatch without slurm.conf or a DNS SRV record, then with
  // a controller that does not answer.
  EXPECT_EQ(SubmitProblem::NoCluster, sbatch_problem("sbatch: error: resolve_ctls_from_dns_srv: res_nsearch error: "
                                                     "Unknown host\nsbatch: error: fetch_config: DNS SRV lookup "
                                                     "failed\nsbatch: fatal: Could not establish a configuration "
                                                     "source\n"));
  EXPECT_EQ(SubmitProblem::NoCluster, sbatch_problem("sbatch: fatal: Could not establish a configuration source\n"));
  EXPECT_EQ(SubmitProblem::NoController, sbatch_problem("sbatch: error: Batch job submission failed: Unable to contact "
                                                        "slurm controller (connect failure)\n"));
  EXPECT_EQ(SubmitProblem::Other, sbatch_problem("sbatch: error: invalid partition specified: debug\n"));
  EXPECT_EQ(SubmitProblem::Other, sbatch_problem(""));

  Fixture f;
  auto scripts = slurm_scripts(f.options);
  ASSERT_TRUE(scripts.ok()) << scripts.error().message;
  ASSERT_TRUE(write_slurm_scripts(f.dir, scripts.value()).ok());
  const std::string sbatch = f.tmp.file("sbatch");
  std::ofstream(sbatch) << "#!/bin/sh\necho run >> \"$FAKE_ARGS\"\n"
                           "echo 'sbatch: error: Batch job submission failed: Unable to contact slurm controller "
                           "(connect failure)' >&2\nexit 1\n";
  ::chmod(sbatch.c_str(), 0755);
  const ScopedEnv args("FAKE_ARGS", f.args.c_str());
  {
    const ScopedEnv no_conf("SLURM_CONF", nullptr);
    auto down = submit_slurm(f.dir, sbatch, 30);
    ASSERT_FALSE(down.ok());
    EXPECT_EQ(SubmitProblem::NoController, down.error().problem) << down.error().message;
    EXPECT_NE(std::string::npos, down.error().message.find("Unable to contact slurm controller"));
  }
  // SLURM_CONF naming no file: NoCluster, and sbatch is not run (it would
  // retry the file for a minute).
  fs::remove(f.args);
  const ScopedEnv missing("SLURM_CONF", f.tmp.file("no such slurm.conf").c_str());
  auto none = submit_slurm(f.dir, sbatch, 30);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(SubmitProblem::NoCluster, none.error().problem);
  EXPECT_NE(std::string::npos, none.error().message.find("no such slurm.conf', which is no file"))
      << none.error().message;
  EXPECT_FALSE(fs::exists(f.args)) << "sbatch ran";
}

TEST(CampaignSlurm, SbatchParsableOutputGivesTheJobId) {
  EXPECT_EQ("123", parse_sbatch_job_id("123\n").value());
  EXPECT_EQ("123", parse_sbatch_job_id("123;cluster\n").value());
  EXPECT_FALSE(parse_sbatch_job_id("").ok());
  EXPECT_FALSE(parse_sbatch_job_id("Submitted batch job 12\n").ok());
}

TEST(CampaignSlurm, FindOnPathFindsAnExecutableOnly) {
  TempDir tmp;
  write_recorder(tmp.file("tool"));
  tmp.write("plain", "");
  const std::string old = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", ("/nonexistent:" + tmp.path()).c_str(), 1);
  EXPECT_EQ(tmp.file("tool"), find_on_path("tool"));
  EXPECT_EQ("", find_on_path("plain"));
  EXPECT_EQ("", find_on_path("sbatch-that-is-not-there"));
  ::setenv("PATH", old.c_str(), 1);
}

}  // namespace
}  // namespace strata::campaign
