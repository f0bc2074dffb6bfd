// A run killed at any moment (SIGKILL) continues with --resume and ends with
// every (variant, frame) row exactly once and the metrics of an uninterrupted
// run; shards joined by merge give the same; concurrent writers of the
// reference cache never corrupt it.
#include "experiments/sources/reference_cache.h"
#include "experiments/runner/runner.h"

#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace glintlab;

namespace {

const char* kExperiment = R"({
  "name": "resume-test",
  "resolution": [64, 36],
  "scene": {"mesh": {"type": "wavy", "size": 10, "tessellation": 16, "amplitude": 0.4, "wavelength": 5}},
  "camera_path": {"type": "orbit", "fps": 30, "frames": 10, "center": [0, 0, 0], "radius": 3.6,
                  "height": 1.7, "start_deg": 180, "end_deg": 195, "fov": 40},
  "material": {"preset": "thesis-default", "noise_scale": 400, "glint_sigma": 0.002, "sigmoid_b": 6},
  "variants": [{"name": "no-aa"}, {"name": "ssaa", "aa": "ssaa", "ssaa_grid": 2}, {"name": "taa", "aa": "taa"}],
  "reference": {"grid": 3},
  "metrics": ["deltaE2000", "flip"],
  "output": {"exr": false, "png": true, "every": 3, "contact_sheet": true}
})";

// frames.csv as (variant, frame) -> column -> cell, without the columns that
// measure time (they differ between any two runs).
using Table = std::map<std::pair<std::string, int>, std::map<std::string, std::string>>;
Table read_table(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) header.push_back(c);
  }
  Table t;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    EXPECT_EQ(cells.size(), header.size()) << line;
    auto key = std::make_pair(cells[0], std::stoi(cells[1]));
    EXPECT_EQ(t.count(key), 0u) << "row " << cells[0] << " " << cells[1] << " twice";
    for (size_t i = 0; i < header.size() && i < cells.size(); ++i) {
      const std::string& h = header[i];
      if (h.rfind("gpu_ms", 0) == 0 || h == "wall_ms" || h == "reference_cached") continue;
      t[key][h] = cells[i];
    }
  }
  return t;
}

RunOptions options(const fs::path& dir, const fs::path& exp, const fs::path& cache) {
  RunOptions o;
  o.experiment = exp.string();
  o.out_dir = dir.string();
  o.cache_dir = cache.string();
  o.validation = true;
  o.report = false;
  return o;
}

size_t journal_lines(const fs::path& dir) {
  std::ifstream in(dir / "records.jsonl");
  size_t n = 0;
  std::string line;
  while (std::getline(in, line)) ++n;
  return n;
}

}  // namespace

TEST(Resume, KilledRunResumesToTheSameRowsAndMetrics) {
  const glintlab::test::TempDir root_tmp("kill");
  const fs::path root = root_tmp.path();
  std::ofstream(root / "e.json") << kExperiment;
  // The uninterrupted run.
  std::ostringstream log;
  ASSERT_EQ(run_experiment(options(root / "whole", root / "e.json", root / "cache"), log), 0) << log.str();
  const Table whole = read_table(root / "whole" / "frames.csv");
  ASSERT_EQ(whole.size(), 30u);

  // The same run as a user starts it, killed with SIGKILL after a few records
  // (its own cache, so that it has references to render and does not finish first).
  const fs::path killed = root / "killed";
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string out = killed.string(), exp = (root / "e.json").string(), cache = (root / "cache2").string();
    freopen("/dev/null", "w", stderr);
    execl(GLINTLAB_CLI, GLINTLAB_CLI, "run", exp.c_str(), "--out", out.c_str(), "--cache", cache.c_str(),
          "--no-report", static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (journal_lines(killed) < 8 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run finished before it could be killed";
  const size_t done = journal_lines(killed);
  EXPECT_GE(done, 8u);
  EXPECT_FALSE(fs::exists(killed / "frames.csv"));

  // A torn last line, as a kill in the middle of a write leaves it.
  { std::ofstream(killed / "records.jsonl", std::ios::app) << R"({"type": "frame", "variant": 1, "fra)"; }

  RunOptions o = options(killed, root / "e.json", root / "cache2");
  o.resume = true;
  std::ostringstream log2;
  ASSERT_EQ(run_experiment(o, log2), 0) << log2.str();
  EXPECT_NE(log2.str().find("dropped 1 incomplete line"), std::string::npos) << log2.str();
  EXPECT_NE(log2.str().find("resume:"), std::string::npos) << log2.str();
  EXPECT_EQ(read_table(killed / "frames.csv"), whole);
  EXPECT_TRUE(fs::exists(killed / "contact_sheet.png"));

  // Resuming a finished run does nothing and changes nothing.
  std::ostringstream log3;
  ASSERT_EQ(run_experiment(o, log3), 0) << log3.str();
  EXPECT_EQ(read_table(killed / "frames.csv"), whole);

  // A resume with other settings is refused.
  RunOptions other = o;
  other.width = 32;
  other.height = 18;
  std::ostringstream log4;
  EXPECT_EQ(run_experiment(other, log4), 2) << log4.str();
  EXPECT_NE(log4.str().find("other settings"), std::string::npos) << log4.str();
}

TEST(Resume, ShardsMergeIntoTheSingleRun) {
  const glintlab::test::TempDir root_tmp("shards");
  const fs::path root = root_tmp.path();
  std::ofstream(root / "e.json") << kExperiment;
  std::ostringstream log;
  ASSERT_EQ(run_experiment(options(root / "whole", root / "e.json", root / "cache"), log), 0) << log.str();
  std::vector<std::string> dirs;
  for (int k = 0; k < 3; ++k) {
    RunOptions o = options(root / ("shard" + std::to_string(k)), root / "e.json", root / "cache");
    o.shard_index = k;
    o.shard_count = 3;
    std::ostringstream l;
    ASSERT_EQ(run_experiment(o, l), 0) << l.str();
    dirs.push_back(o.out_dir);
  }
  std::ostringstream lm;
  ASSERT_EQ(merge_runs(dirs, (root / "merged").string(), false, lm), 0) << lm.str();
  EXPECT_EQ(read_table(root / "merged" / "frames.csv"), read_table(root / "whole" / "frames.csv"));
  auto summary = [](const fs::path& p) {
    std::ifstream in(p / "summary.json");
    nlohmann::json j = nlohmann::json::parse(in);
    nlohmann::json m;
    for (const auto& v : j["variants"]) m[v["name"].get<std::string>()] = v["metrics"];
    return m;
  };
  EXPECT_EQ(summary(root / "merged"), summary(root / "whole"));
  EXPECT_TRUE(fs::exists(root / "merged" / "taa" / "frame_0009.png"));

  // A missing or doubled shard is refused.
  std::ostringstream l2;
  EXPECT_EQ(merge_runs({dirs[0], dirs[2]}, (root / "bad").string(), false, l2), 2);
  EXPECT_NE(l2.str().find("shard(s) 2/3 missing"), std::string::npos) << l2.str();
  std::ostringstream l3;
  EXPECT_EQ(merge_runs({dirs[0], dirs[0], dirs[1]}, (root / "bad").string(), false, l3), 2);
  // --out naming a shard, or a folder inside one, is refused before anything is written (it would copy
  // the shard's folders over themselves).
  const std::string shard0 = dirs[0];
  const std::string records = [&] {
    std::ifstream in(fs::path(shard0) / "records.jsonl");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  for (const std::string& out : {shard0, shard0 + "/", (fs::path(shard0) / "merged").string()}) {
    std::ostringstream l4;
    EXPECT_EQ(merge_runs(dirs, out, false, l4), 2) << out;
    EXPECT_NE(l4.str().find("the shard folder " + shard0), std::string::npos) << l4.str();
  }
  EXPECT_FALSE(fs::exists(fs::path(shard0) / "merged"));
  std::ifstream in(fs::path(shard0) / "records.jsonl");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), records);
}

TEST(ReferenceCache, ConcurrentWritersNeverCorruptAnEntry) {
  const glintlab::test::TempDir dir_tmp("cache");
  const fs::path dir = dir_tmp.path();
  ReferenceCache cache(dir.string());
  Image img(32, 16, 4);
  for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i) * 0.25f;
  const std::string key(32, 'c');
  std::atomic<int> bad{0}, corrupt{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 50; ++i) cache.store(key, img);
    });
  threads.emplace_back([&] {
    for (int i = 0; i < 200; ++i) {
      bool c = false;
      auto got = cache.load(key, &c);
      corrupt += c;
      if (got && got->data != img.data) ++bad;
    }
  });
  for (auto& t : threads) t.join();
  EXPECT_EQ(bad.load(), 0);
  EXPECT_EQ(corrupt.load(), 0);
  EXPECT_TRUE(cache.load(key).has_value());
}

// A journal that is not a regular file is refused at once (exit 2, naming it), before anything
// renders: a FIFO would block every reader forever, a folder is no journal. `run`, `run --resume` and
// `merge` alike; nothing is written into the folder.
TEST(Resume, AJournalThatIsNotARegularFileIsRefused) {
  const glintlab::test::TempDir tmp("journal-kind");
  const fs::path exp = tmp.path() / "exp.json";
  std::ofstream(exp) << kExperiment;
  for (const char* kind : {"FIFO", "folder"}) {
    const fs::path out = tmp.path() / (std::string("out-") + kind);
    fs::create_directories(out);
    const fs::path journal = out / "records.jsonl";
    if (std::string(kind) == "FIFO")
      ASSERT_EQ(::mkfifo(journal.c_str(), 0644), 0);
    else
      fs::create_directories(journal);
    for (const bool resume : {false, true}) {
      RunOptions o = options(out, exp, tmp.path() / "cache");
      o.resume = resume;
      std::ostringstream log;
      EXPECT_EQ(run_experiment(o, log), 2) << kind << " " << log.str();
      EXPECT_NE(log.str().find(journal.string()), std::string::npos) << log.str();
      EXPECT_NE(log.str().find(std::string("a ") + kind), std::string::npos) << log.str();
    }
    std::ostringstream log;
    EXPECT_EQ(merge_runs({out.string()}, (tmp.path() / "merged").string(), false, log), 2) << log.str();
    EXPECT_NE(log.str().find(std::string("a ") + kind), std::string::npos) << log.str();
    size_t entries = 0;
    for (const auto& e : fs::directory_iterator(out)) entries += e.path().filename() != "records.jsonl";
    EXPECT_EQ(entries, 0u) << kind;  // nothing written beside it
  }
}
