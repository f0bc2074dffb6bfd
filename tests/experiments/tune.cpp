// `glintlab tune` as a user runs it: the CLI, Optuna (Debian's python3-optuna) with its SQLite and
// journal-file storages, several workers under GNU parallel, a worker killed mid-trial, and a
// one-node Slurm cluster (slurm-wlm + munge, configured here in a temporary folder) running the
// job-array recipes (experiments/README.md) for `run --shard` + `merge` and for `tune`.
#include "core/material/glint_model.h"
#include "core/util/json_check.h"
#include "experiments/tune/tune.h"
#include "tests/support/csv.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

const char* kTiny = R"({"name": "tune-tiny", "resolution": [48, 27],
 "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 32, "amplitude": 0.4, "wavelength": 5},
           "sky": {"turbidity": 3, "sky_intensity": 0.5, "sun_elevation_deg": 25, "sun_azimuth_deg": 30,
                   "sun_intensity": 6}},
 "camera_path": {"type": "orbit", "fps": 30, "frames": 4, "center": [0, 0, 0], "radius": 3.6252, "height": 1.6905,
                 "start_deg": 180, "end_deg": 183, "fov": 40},
 "material": {"preset": "thesis-hdri-match", "noise_scale": 400, "glint_sigma": 0.002, "I_glints": [20, 20, 20],
              "sigmoid_a": 2, "sigmoid_b": 6},
 "variants": [{"name": "no-aa"}, {"name": "taa", "aa": "taa"}],
 "reference": {"grid": 2}, "metrics": ["deltaE2000"],
 "output": {"exr": false, "png": false, "every": 1}})";

struct Result {
  int code = -1;
  std::string output;
};

// Runs a shell command line, stdout and stderr captured.
Result sh(const std::string& cmd) {
  Result r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

// `glintlab tune` on the tiny experiment: alpha and clamp of its TAA, two objectives.
std::string tune_cmd(const fs::path& root, const fs::path& study, int trials, const std::string& extra = "") {
  return std::string(GLINTLAB_CLI) + " tune " + q(root / "tiny.json") +
         " --base taa --space taa.alpha=0.02:0.5:log --space taa.clamp=none,variance"
         " --objectives flicker_ratio,deltaE2000 --trials " +
         std::to_string(trials) + " --study " + q(study) + " --cache " + q(root / "cache") + " " + extra;
}

using Row = std::map<std::string, std::string>;

std::vector<Row> read_csv(const fs::path& p) { return glintlab::test::read_csv_rows(p); }

size_t count_state(const std::vector<Row>& rows, const std::string& state) {
  size_t n = 0;
  for (const Row& r : rows) n += r.at("state") == state;
  return n;
}

class Tune : public ::testing::Test {
 protected:
  void SetUp() override {
    if (sh("/usr/bin/python3 -c 'import optuna'").code != 0)
      GTEST_SKIP() << "python3-optuna is not installed (./bootstrap.sh installs it)";
    std::ofstream(root() / "tiny.json") << kTiny;
  }
  const fs::path& root() { return tmp_.path(); }
  glintlab::test::TempDir tmp_{"tune"};
};

}  // namespace

TEST_F(Tune, BadSpaceIsAnErrorNamingTheKeyBeforeAnyTrial) {
  const fs::path study = root() / "s";
  auto expect_bad = [&](const std::string& space, const std::vector<std::string>& words) {
    const Result r = sh(std::string(GLINTLAB_CLI) + " tune " + q(root() / "tiny.json") + " --base taa --space " + space +
                        " --objectives deltaE2000 --trials 2 --study " + q(study) + " --cache " + q(root() / "cache"));
    EXPECT_EQ(r.code, 2) << space << "\n" << r.output;
    for (const auto& w : words) EXPECT_NE(r.output.find(w), std::string::npos) << space << ": no \"" << w << "\" in\n" << r.output;
    EXPECT_FALSE(fs::exists(study / "trials")) << "a trial ran for " << space;
  };
  expect_bad("taa.no_such=0:1", {"taa.no_such", "alpha"});             // unknown key: the allowed ones listed
  expect_bad("taa.alpha=0.5:2", {"taa.alpha", "out of range"});        // beyond what the schema allows
  expect_bad("taa.alpha=0.5:0.1", {"taa.alpha", "lo must be below hi"});
  expect_bad("taa.clamp=none,sometimes", {"taa.clamp", "sometimes", "variance"});
  expect_bad("taa.alpha=0:0.5:log", {"log range needs lo > 0"});
  const Result base = sh(std::string(GLINTLAB_CLI) + " tune " + q(root() / "tiny.json") +
                         " --base nope --space taa.alpha=0.1:0.2 --objectives deltaE2000 --trials 2 --study " + q(study));
  EXPECT_EQ(base.code, 2);
  EXPECT_NE(base.output.find("no-aa, taa"), std::string::npos) << base.output;
  const Result obj = sh(std::string(GLINTLAB_CLI) + " tune " + q(root() / "tiny.json") +
                        " --base taa --space taa.alpha=0.1:0.2 --objectives ssim --trials 2 --study " + q(study));
  EXPECT_EQ(obj.code, 2);
  EXPECT_NE(obj.output.find("temporal_error_mc"), std::string::npos) << obj.output;
  // An objective the experiment's "metrics" list leaves out (tiny.json measures only deltaE2000).
  const Result unmeasured = sh(std::string(GLINTLAB_CLI) + " tune " + q(root() / "tiny.json") +
                               " --base taa --space taa.alpha=0.1:0.2 --objectives flip --trials 2 --study " + q(study));
  EXPECT_EQ(unmeasured.code, 2);
  EXPECT_NE(unmeasured.output.find("\"flip\" is not measured"), std::string::npos) << unmeasured.output;
  // An empty item in the list is a typo, not one objective fewer.
  const Result empty = sh(std::string(GLINTLAB_CLI) + " tune " + q(root() / "tiny.json") +
                          " --base taa --space taa.alpha=0.1:0.2 --objectives deltaE2000,,flicker_ratio --trials 1"
                          " --study " + q(study) + " --cache " + q(root() / "cache"));
  EXPECT_EQ(empty.code, 2) << empty.output;
  EXPECT_NE(empty.output.find("--objectives: an empty name"), std::string::npos) << empty.output;
  EXPECT_FALSE(fs::exists(study / "trials"));
}

// A glint model's own parameter given without a range is searched over its declared range (the
// model's declaration, shaders/glint/models/); a key the base variant's model does not declare is refused.
TEST(TuneSpace, AGlintModelParameterAloneSearchesItsDeclaredRange) {
  nlohmann::json e = nlohmann::json::parse(kTiny);
  e["variants"][1]["material"] = {{"glint_model", "zirr"}};
  glintlab::TuneOptions o;
  o.base = "taa";
  o.objectives = {"deltaE2000"};
  o.trials = 1;
  o.space = {"material.glints.size_variation", "material.glints.half_vector_blend"};
  const nlohmann::json d = glintlab::tune_definition(o, e, "tiny.json");
  const glintlab::core::GlintParameter* sv = glintlab::core::find_builtin_glint_model("zirr")->parameter("size_variation");
  ASSERT_NE(sv, nullptr);
  EXPECT_EQ(d["space"][0]["kind"], "float");
  EXPECT_EQ(d["space"][0]["lo"].get<double>(), sv->lo);
  EXPECT_EQ(d["space"][0]["hi"].get<double>(), sv->hi);
  EXPECT_EQ(d["space"][1]["kind"], "choice");
  EXPECT_EQ(d["space"][1]["choices"], nlohmann::json::array({false, true}));
  o.space = {"material.glints.k"};
  try {
    glintlab::tune_definition(o, e, "tiny.json");
    ADD_FAILURE() << "accepted a parameter zirr does not declare";
  } catch (const glintlab::ConfigError& err) {
    EXPECT_NE(std::string(err.what()).find("zirr"), std::string::npos) << err.what();
  }
}

TEST_F(Tune, TwoTrialsAreDeterministicWithAFixedSeedAndAnotherStudyIsRefused) {
  const Result a = sh(tune_cmd(root(), root() / "a", 2, "--seed 7"));
  ASSERT_EQ(a.code, 0) << a.output;
  const Result b = sh(tune_cmd(root(), root() / "b", 2, "--seed 7"));
  ASSERT_EQ(b.code, 0) << b.output;
  const auto ra = read_csv(root() / "a" / "trials.csv"), rb = read_csv(root() / "b" / "trials.csv");
  ASSERT_EQ(ra.size(), 2u);
  ASSERT_EQ(rb.size(), 2u);
  for (size_t i = 0; i < 2; ++i)
    for (const char* k : {"state", "taa.alpha", "taa.clamp", "flicker_ratio", "deltaE2000"})
      EXPECT_EQ(ra[i].at(k), rb[i].at(k)) << "trial " << i << " " << k;
  EXPECT_TRUE(fs::exists(root() / "a" / "pareto.json"));
  EXPECT_TRUE(fs::exists(root() / "a" / "tune_report.html"));
  // The same folder for another study (another base, space or objectives) is refused.
  const Result other = sh(std::string(GLINTLAB_CLI) + " tune " + q(root() / "tiny.json") +
                          " --base taa --space taa.gamma=0.5:2 --objectives deltaE2000 --trials 2 --study " +
                          q(root() / "a") + " --cache " + q(root() / "cache"));
  EXPECT_EQ(other.code, 2) << other.output;
  EXPECT_NE(other.output.find("holds another study"), std::string::npos) << other.output;
  // A larger budget needs --resume, and then only the missing trials run.
  EXPECT_EQ(sh(tune_cmd(root(), root() / "a", 3, "--seed 7")).code, 2);
  const Result more = sh(tune_cmd(root(), root() / "a", 3, "--seed 7 --resume"));
  ASSERT_EQ(more.code, 0) << more.output;
  EXPECT_EQ(count_state(read_csv(root() / "a" / "trials.csv"), "COMPLETE"), 3u);
}

TEST_F(Tune, WorkersUnderGnuParallelShareOneStudyAndStopAtExactlyN) {
  if (sh("command -v parallel").code != 0) GTEST_SKIP() << "GNU parallel is not installed (./bootstrap.sh installs it)";
  const fs::path study = root() / "p";
  // The reference once, so both workers start on the same footing.
  ASSERT_EQ(sh(tune_cmd(root(), root() / "warm", 1)).code, 0);
  const Result r = sh("parallel --will-cite -N0 -j 4 --halt now,fail=1 " + tune_cmd(root(), study, 6) + " ::: 1 2 3 4");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = read_csv(study / "trials.csv");
  EXPECT_EQ(count_state(rows, "COMPLETE"), 6u);
  std::set<std::string> numbers, workers, settings;
  for (const Row& row : rows) {
    EXPECT_TRUE(numbers.insert(row.at("trial")).second) << "trial " << row.at("trial") << " twice";
    if (row.at("state") == "COMPLETE") {
      EXPECT_TRUE(settings.insert(row.at("taa.alpha") + " " + row.at("taa.clamp")).second)
          << "trial " << row.at("trial") << " repeats another's settings";
      workers.insert(row.at("worker"));
      EXPECT_TRUE(fs::exists(study / "trials" / (std::string(4 - row.at("trial").size(), '0') + row.at("trial")) / "run" /
                             "summary.json"));
    }
  }
  EXPECT_GE(workers.size(), 2u) << "the trials should come from more than one worker";
}

TEST_F(Tune, AWorkerKilledMidTrialLosesOnlyThatTrialWhichIsRetried) {
  const fs::path study = root() / "k";
  ASSERT_EQ(sh(tune_cmd(root(), root() / "warm", 1)).code, 0);  // the reference cached
  const std::string cmd = tune_cmd(root(), study, 3);
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setpgid(0, 0);  // its own process group: the driver and its `glintlab run` die together
    freopen("/dev/null", "w", stderr);
    freopen("/dev/null", "w", stdout);
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid, pid);
  // Kill it while its second trial renders.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(study / "trials" / "0001" / "run.log") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  kill(-pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(fs::exists(study / "trials" / "0001")) << "the worker did not reach its second trial";
  // Another worker on the same study: the dead worker's trial is marked FAIL and its settings run again.
  const Result r = sh(cmd);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("stale"), std::string::npos) << r.output;
  const auto rows = read_csv(study / "trials.csv");
  EXPECT_EQ(count_state(rows, "COMPLETE"), 3u);
  std::string killed_alpha;
  for (const Row& row : rows)
    if (row.at("state") == "FAIL") killed_alpha = row.at("taa.alpha");
  ASSERT_FALSE(killed_alpha.empty()) << "no FAIL row for the killed trial";
  bool retried = false;
  for (const Row& row : rows)
    if (row.at("state") == "COMPLETE" && !row.at("retry_of").empty() && row.at("taa.alpha") == killed_alpha)
      retried = true;
  EXPECT_TRUE(retried) << "the killed trial's settings were not run again";
  // The new worker samples with a seed of its own: no finished trial's settings come again.
  std::set<std::string> settings;
  for (const Row& row : rows)
    if (row.at("state") == "COMPLETE") {
      EXPECT_TRUE(settings.insert(row.at("taa.alpha") + " " + row.at("taa.clamp")).second)
          << "trial " << row.at("trial") << " repeats the settings of another";
    }
}

// Two workers of one `tune` draw distinct settings (each its own sampler seed): 4 trials, 4 points.
TEST_F(Tune, WorkersDrawDistinctSettings) {
  ASSERT_EQ(sh(tune_cmd(root(), root() / "warm", 1)).code, 0);  // the reference cached
  const Result r = sh(tune_cmd(root(), root() / "w", 4, "--workers 2"));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = read_csv(root() / "w" / "trials.csv");
  EXPECT_EQ(count_state(rows, "COMPLETE"), 4u);
  std::set<std::string> settings;
  for (const Row& row : rows)
    EXPECT_TRUE(settings.insert(row.at("taa.alpha") + " " + row.at("taa.clamp")).second)
        << "trial " << row.at("trial") << " repeats the settings of another";
}

// A study's storage damaged, empty or gone: exit 2 naming the file (never a traceback, never a silent
// fresh start over trials/0000); a journal whose last line was cut by a killed writer goes on.
TEST_F(Tune, DamagedOrMissingStorageIsAnErrorNamingTheFile) {
  const fs::path study = root() / "d";
  ASSERT_EQ(sh(tune_cmd(root(), study, 1)).code, 0);
  auto expect_refused = [&](const std::string& what, const std::string& extra, const std::vector<std::string>& says) {
    const Result r = sh(tune_cmd(root(), study, 2, extra));
    EXPECT_EQ(r.code, 2) << what << "\n" << r.output;
    for (const auto& w : says) EXPECT_NE(r.output.find(w), std::string::npos) << what << ": no \"" << w << "\" in\n" << r.output;
    EXPECT_EQ(r.output.find("Traceback"), std::string::npos) << what << "\n" << r.output;
  };
  auto random_bytes = [](const fs::path& p) {
    std::mt19937 rng(39);
    std::string bytes(8192, '\0');
    for (char& c : bytes) c = char(rng() & 0xff);
    std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
  };
  const std::string db = (study / "study.db").string();
  random_bytes(study / "study.db");
  expect_refused("a study.db of random bytes", "--resume", {db, "cannot be read as an Optuna study"});
  std::ofstream(study / "study.db", std::ios::trunc).close();
  expect_refused("an empty study.db", "--resume", {"--resume", "an empty " + db});
  fs::remove(study / "study.db");
  expect_refused("no study.db", "--resume", {"--resume", "no " + db});
  expect_refused("no study.db beside trials/", "", {"holds trials/", "no " + db});
  EXPECT_EQ(read_csv(study / "trials.csv").size(), 1u);  // nothing started over

  const fs::path journal_study = root() / "j";
  ASSERT_EQ(sh(tune_cmd(root(), journal_study, 2, "--storage journal")).code, 0);
  const fs::path journal = journal_study / "study.journal";
  fs::resize_file(journal, fs::file_size(journal) - 5);  // the last line cut, as by a killed writer
  const Result resumed = sh(tune_cmd(root(), journal_study, 3, "--storage journal --resume"));
  ASSERT_EQ(resumed.code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("its last line was cut"), std::string::npos) << resumed.output;
  EXPECT_EQ(count_state(read_csv(journal_study / "trials.csv"), "COMPLETE"), 3u);
  random_bytes(journal);
  const Result damaged = sh(tune_cmd(root(), journal_study, 4, "--storage journal --resume"));
  EXPECT_EQ(damaged.code, 2) << damaged.output;
  EXPECT_NE(damaged.output.find(journal.string()), std::string::npos) << damaged.output;
  EXPECT_EQ(damaged.output.find("Traceback"), std::string::npos) << damaged.output;
}

namespace {

// A one-node Slurm cluster in a temporary folder: munged with its own key and socket, slurmctld and
// slurmd on ports of their own, every path in the folder; torn down with the object.
class SlurmCluster {
 public:
  explicit SlurmCluster(const fs::path& dir) : dir_(dir) {
    char host[256] = {};
    gethostname(host, sizeof host - 1);
    const int port = 20000 + int(getpid() % 2000) * 2;
    fs::create_directories(dir / "state");
    fs::create_directories(dir / "spool");
    sh("dd if=/dev/urandom of=" + q(dir / "munge.key") + " bs=1024 count=1 && chmod 400 " + q(dir / "munge.key"));
    const Result m = sh("munged --force --key-file=" + q(dir / "munge.key") + " --socket=" + q(dir / "munge.sock") +
                        " --pid-file=" + q(dir / "munged.pid") + " --log-file=" + q(dir / "munged.log") +
                        " --seed-file=" + q(dir / "munge.seed"));
    if (m.code != 0) {
      why_ = "munged did not start: " + m.output;
      return;
    }
    std::ofstream c(dir / "slurm.conf");
    const std::string d = dir.string();
    c << "ClusterName=glintlab\nSlurmctldHost=" << host << "\nSlurmUser=root\nSlurmdUser=root\n"
      << "SlurmctldPort=" << port << "\nSlurmdPort=" << port + 1 << "\nAuthType=auth/munge\nAuthInfo=socket=" << d
      << "/munge.sock\nCredType=cred/munge\nStateSaveLocation=" << d << "/state\nSlurmdSpoolDir=" << d
      << "/spool\nSlurmctldPidFile=" << d << "/slurmctld.pid\nSlurmdPidFile=" << d << "/slurmd.pid\n"
      << "SlurmctldLogFile=" << d << "/slurmctld.log\nSlurmdLogFile=" << d << "/slurmd.log\n"
      << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\nSelectType=select/cons_tres\n"
      << "SelectTypeParameters=CR_Core\nSchedulerType=sched/builtin\nReturnToService=2\nMpiDefault=none\n"
      << "JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n"
      << "NodeName=" << host << " CPUs=" << std::thread::hardware_concurrency() << " State=UNKNOWN\n"
      << "PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES\n";
    c.close();
    setenv("SLURM_CONF", (dir / "slurm.conf").c_str(), 1);
    const Result ctl = sh("slurmctld -i"), node = sh("slurmd");
    if (ctl.code != 0 || node.code != 0) {
      why_ = "slurmctld/slurmd did not start: " + ctl.output + node.output;
      return;
    }
    for (int i = 0; i < 300 && why_.empty(); ++i) {
      if (sh("sinfo -h -o %t").output.find("idle") != std::string::npos) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    why_ = "the node never became idle: " + sh("sinfo; tail -5 " + q(dir / "slurmctld.log") + " " +
                                               q(dir / "slurmd.log")).output;
  }
  ~SlurmCluster() {
    sh("scontrol shutdown");
    for (const char* pid : {"slurmd.pid", "slurmctld.pid", "munged.pid"})
      sh("test -f " + q(dir_ / pid) + " && kill $(cat " + q(dir_ / pid) + ")");
    unsetenv("SLURM_CONF");
  }
  // Empty when the cluster runs, else why not.
  const std::string& why_not() const { return why_; }

 private:
  fs::path dir_;
  std::string why_;
};

}  // namespace

// The Slurm recipes of experiments/README.md, end to end on a real (one-node) cluster: a job array of `run --shard
// k/2` tasks and a merge job after it; a job array of two `tune` workers sharing a journal-file study.
TEST_F(Tune, SlurmJobArraysRunShardsWithAMergeAndTuneWorkers) {
  if (sh("command -v slurmctld && command -v slurmd && command -v munged && command -v sbatch").code != 0)
    GTEST_SKIP() << "slurm-wlm and munge are not installed (./bootstrap.sh installs them)";
  if (geteuid() != 0) GTEST_SKIP() << "a one-node Slurm cluster runs its daemons as root here; this user is not root";
  SlurmCluster cluster(root() / "slurm");
  ASSERT_TRUE(cluster.why_not().empty()) << cluster.why_not();
  const std::string env = std::string("GLINTLAB=") + GLINTLAB_CLI + " ";
  const std::string scripts = std::string(GLINTLAB_SOURCE_DIR) + "/experiments/slurm/";
  // Shards, then the merge as a job that depends on the array.
  const Result jid = sh(env + "sbatch --parsable --array=1-2 -o " + q(root() / "shard-%a.log") + " " + scripts +
                        "shard.sh " + q(root() / "tiny.json") + " " + q(root() / "run") + " " + q(root() / "cache"));
  ASSERT_EQ(jid.code, 0) << jid.output;
  const std::string id = jid.output.substr(0, jid.output.find_first_of(";\n"));
  const Result merge = sh("timeout 300 sbatch --wait --dependency=afterok:" + id + " -o " + q(root() / "merge.log") +
                          " --wrap \"" + GLINTLAB_CLI + " merge " + (root() / "run-").string() + "* --out " +
                          (root() / "run").string() + " --no-report\"");  // the recipe's glob
  ASSERT_EQ(merge.code, 0) << merge.output << sh("cat " + q(root() / "shard-1.log") + " " + q(root() / "merge.log")).output;
  const auto rows = read_csv(root() / "run" / "frames.csv");
  EXPECT_EQ(rows.size(), 8u) << "2 variants x 4 frames, each once";
  std::set<std::string> seen;
  for (const Row& r : rows) EXPECT_TRUE(seen.insert(r.at("variant") + "/" + r.at("frame")).second);
  // Two tune workers as an array job.
  const Result t = sh(env + "timeout 600 sbatch --wait --array=1-2 -o " + q(root() / "tune-%a.log") + " " + scripts +
                      "tune.sh " + q(root() / "tiny.json") +
                      " --base taa --space taa.alpha=0.02:0.5:log --space taa.clamp=none,variance"
                      " --objectives flicker_ratio,deltaE2000 --trials 4 --study " +
                      q(root() / "study") + " --cache " + q(root() / "cache"));
  ASSERT_EQ(t.code, 0) << t.output << sh("cat " + q(root() / "tune-1.log")).output;
  const auto trials = read_csv(root() / "study" / "trials.csv");
  EXPECT_EQ(count_state(trials, "COMPLETE"), 4u);
  std::set<std::string> settings;  // the two tasks' workers sample with seeds of their own
  for (const Row& row : trials)
    if (row.at("state") == "COMPLETE") {
      EXPECT_TRUE(settings.insert(row.at("taa.alpha") + " " + row.at("taa.clamp")).second)
          << "trial " << row.at("trial") << " repeats another's settings";
    }
  EXPECT_TRUE(fs::exists(root() / "study" / "study.journal"));
}
