// The run report end to end: a small real run (lavapipe, validation on), its
// report.html written by write_report, then opened in a real headless browser
// (Debian's chromium) that counts the images that decoded and the inline SVG
// plots that laid out. A broken image fails the test (checked on a copy with
// one image corrupted). Chromium missing is a failure, not a skip: CI
// installs it through bootstrap.sh. Also: the exit codes of bad input and of
// a Python without matplotlib, and the `report` command's wiring.
#include "experiments/cli/commands.h"
#include "experiments/report/report.h"
#include "experiments/runner/runner.h"

#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;
using namespace glintlab;
using nlohmann::json;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// Sets an environment variable for the lifetime of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_)
      ::setenv(name_, old_.c_str(), 1);
    else
      ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

// 64x36, 3 frames of an orbit over glinting sand: no AA, 2x2 SSAA and TAA
// against a 2x2-sample reference; PNG previews of every frame.
json tiny_experiment() {
  return {{"name", "report-test"},
          {"description", "Report test: three variants on a tiny orbit."},
          {"resolution", {64, 36}},
          {"scene",
           {{"mesh", {{"type", "wavy"}, {"size", 10}, {"tessellation", 32}, {"amplitude", 0.4}, {"wavelength", 5}}},
            {"sky",
             {{"turbidity", 3}, {"sky_intensity", 0.5}, {"sun_elevation_deg", 25}, {"sun_azimuth_deg", 30},
              {"sun_intensity", 6}}}}},
          {"camera_path",
           {{"type", "orbit"}, {"fps", 30}, {"frames", 3}, {"center", {0, 0, 0}}, {"radius", 3.6252},
            {"height", 1.6905}, {"start_deg", 180}, {"end_deg", 182}, {"fov", 40}}},
          {"frames", 3},
          {"material",
           {{"preset", "thesis-hdri-match"}, {"noise_scale", 400}, {"glint_sigma", 0.002}, {"I_glints", {20, 20, 20}},
            {"sigmoid_a", 2}, {"sigmoid_b", 6}}},
          {"variants",
           {{{"name", "no-aa"}, {"aa", "none"}},
            {{"name", "ssaa-2x2"}, {"aa", "ssaa"}, {"ssaa_grid", 2}},
            {{"name", "taa"}, {"aa", "taa"}}}},
          {"reference", {{"grid", 2}}},
          {"output", {{"exr", false}, {"png", true}, {"every", 1}}}};
}

// Runs the tiny experiment in `dir`; returns the run directory.
fs::path tiny_run(const fs::path& dir) {
  write_text(dir / "e.json", tiny_experiment().dump(2));
  RunOptions opt;
  opt.experiment = (dir / "e.json").string();
  opt.out_dir = (dir / "out").string();
  opt.cache_dir = (dir / "cache").string();
  opt.validation = true;
  std::ostringstream log;
  const int rc = run_experiment(opt, log);
  EXPECT_EQ(rc, 0) << log.str();
  return dir / "out";
}

std::string chromium_path() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (::access(p, X_OK) == 0) return p;
  return "";
}

// Opens `page` in headless chromium and returns the DOM after load (stdout of
// --dump-dom); its stderr goes to `err_file`.
std::string dump_dom(const fs::path& page, const fs::path& work, const fs::path& err_file, int& rc) {
  const fs::path profile = work / "chromium-profile";
  fs::remove_all(profile);
  fs::create_directories(profile);
  const fs::path dom = work / "dom.html";
  const std::string cmd = "timeout 120 " + chromium_path() +
                          " --headless --no-sandbox --disable-gpu --disable-background-networking"
                          " --disable-component-update --disable-sync --no-first-run --disable-extensions"
                          " --user-data-dir='" + profile.string() + "' --virtual-time-budget=5000 --dump-dom 'file://" +
                          page.string() + "' > '" + dom.string() + "' 2> '" + err_file.string() + "'";
  rc = std::system(cmd.c_str());
  return read_text(dom);
}

// The report with a script that, after the load event, writes how many <img>
// decoded (naturalWidth > 0) of how many, and how many inline SVG plots have
// a laid-out size.
std::string with_checker(const std::string& report) {
  const std::string script =
      "<script>window.addEventListener('load', function () {"
      " var im = Array.prototype.slice.call(document.images);"
      " var ok = im.filter(function (i) { return i.complete && i.naturalWidth > 0 && i.naturalHeight > 0; }).length;"
      " var sv = Array.prototype.slice.call(document.querySelectorAll('div.plot > svg'));"
      " var shown = sv.filter(function (s) { var r = s.getBoundingClientRect(); return r.width > 100 && r.height > 50; }).length;"
      " var p = document.createElement('pre'); p.id = 'glintlab-check';"
      " p.textContent = 'CHECK ' + 'images=' + ok + '/' + im.length + ' plots=' + shown + '/' + sv.length + ' END';"
      " document.body.appendChild(p); });</script>";
  std::string page = report;
  const size_t at = page.rfind("</body>");
  EXPECT_NE(at, std::string::npos) << "report.html has no </body>";
  page.insert(at == std::string::npos ? page.size() : at, script);
  return page;
}

struct Counts {
  int images_ok = -1, images = -1, plots_shown = -1, plots = -1;
};

Counts parse_check(const std::string& dom) {
  Counts c;
  std::smatch m;
  static const std::regex re("CHECK images=(\\d+)/(\\d+) plots=(\\d+)/(\\d+) END");
  const size_t at = dom.find("CHECK images=");
  if (at == std::string::npos) return c;
  const std::string tail = dom.substr(at, 200);
  if (std::regex_search(tail, m, re)) {
    c.images_ok = std::stoi(m[1]);
    c.images = std::stoi(m[2]);
    c.plots_shown = std::stoi(m[3]);
    c.plots = std::stoi(m[4]);
  }
  return c;
}

}  // namespace

TEST(Report, EveryImageAndPlotLoadsInHeadlessChromium) {
  const std::string chromium = chromium_path();
  ASSERT_FALSE(chromium.empty()) << "chromium not found at /usr/bin/chromium: this test opens report.html in a real "
                                    "headless browser; install Debian's chromium package (./bootstrap.sh does)";
  const glintlab::test::TempDir dir_tmp("run");
  const fs::path dir = dir_tmp.path();
  const fs::path out = tiny_run(dir);
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  fs::remove(out / "report.html");
  std::ostringstream log;
  ASSERT_EQ(write_report(out.string(), log), 0) << log.str();
  ASSERT_TRUE(fs::exists(out / "report.html")) << log.str();
  const std::string report = read_text(out / "report.html");

  // Self-contained: every src is a data URI, no stylesheet or script is
  // loaded from anywhere.
  for (size_t at = report.find("src="); at != std::string::npos; at = report.find("src=", at + 4)) {
    const std::string value = report.substr(at + 4, 6);
    EXPECT_TRUE(value == "'data:" || value == "\"data:") << "not a data URI: " << report.substr(at, 80);
  }
  EXPECT_EQ(report.find("<link"), std::string::npos);
  EXPECT_EQ(report.find("<script"), std::string::npos);
  // What a reader needs to place the run.
  const json summary = json::parse(read_text(out / "summary.json"));
  for (const std::string& s : {summary["device"].get<std::string>(), summary["glintlab_version"].get<std::string>(),
                               std::string("report-test"), std::string("64×36"), std::string("no-aa"),
                               std::string("ssaa-2x2"), std::string("taa"), std::string("Pareto"),
                               std::string("temporal score"), std::string("flicker excess"),
                               std::string("temporal lag"), std::string("ΔE00")})
    EXPECT_NE(report.find(s), std::string::npos) << "report.html does not mention " << s;
  // The glint density as a ratio to the truth's, in the table and as a Pareto panel, wherever the
  // truth has glints.
  bool truth_has_glints = false;
  for (const auto& v : summary["variants"])
    if (v["metrics"].contains("glint_density_ref") && v["metrics"]["glint_density_ref"]["mean"].get<double>() > 0)
      truth_has_glints = true;
  ASSERT_TRUE(truth_has_glints) << "the test's run should show glints";
  // The truth's noise floor beside its facts, with the value summary.json holds.
  const auto& floor = summary["references"][0]["floor"];
  ASSERT_TRUE(floor.contains("deltaE2000")) << summary["references"][0].dump();
  EXPECT_NE(report.find("its noise floor"), std::string::npos);
  char floor_text[32];
  std::snprintf(floor_text, sizeof floor_text, "ΔE00 %.3g", floor["deltaE2000"].get<double>());
  EXPECT_NE(report.find(floor_text), std::string::npos) << floor_text;
  EXPECT_NE(report.find(" · floor "), std::string::npos) << "the floor beside the table's figures";
  EXPECT_NE(report.find("glint density ratio"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "figures" / "pareto_glint_density_ratio.svg"));
  // Plots also as SVG and PDF beside the report.
  for (const char* name : {"pareto", "pareto_deltaE2000", "pareto_flip", "pareto_temporal_score", "per_frame"}) {
    const fs::path svg = out / "figures" / (std::string(name) + ".svg");
    const fs::path pdf = out / "figures" / (std::string(name) + ".pdf");
    ASSERT_TRUE(fs::exists(svg)) << svg;
    ASSERT_TRUE(fs::exists(pdf)) << pdf;
    EXPECT_NE(read_text(svg).find("<svg"), std::string::npos) << svg;
    EXPECT_EQ(read_text(pdf).rfind("%PDF", 0), 0u) << pdf;
  }
  EXPECT_TRUE(fs::exists(out / "figures" / "glint_crops.png"));

  // The browser: every image decodes, every plot lays out.
  const glintlab::test::TempDir work_tmp("browser");
  const fs::path work = work_tmp.path();
  write_text(work / "check.html", with_checker(report));
  int rc = 0;
  const std::string dom = dump_dom(work / "check.html", work, work / "chromium.err", rc);
  ASSERT_EQ(rc, 0) << "chromium failed; its stderr:\n" << read_text(work / "chromium.err");
  const Counts c = parse_check(dom);
  ASSERT_GE(c.images, 0) << "the page's check did not run; chromium stderr:\n" << read_text(work / "chromium.err");
  // Region overview, one crop per variant and the reference, two animations.
  EXPECT_GE(c.images, 1 + 4 + 2);
  EXPECT_EQ(c.images_ok, c.images) << "broken images in report.html";
  EXPECT_GE(c.plots, 3) << "expected the Pareto, per-frame and per-pass plots as inline SVG";
  EXPECT_EQ(c.plots_shown, c.plots);

  // The check itself: the same page with one image's data corrupted must
  // count it as broken.
  std::string broken = with_checker(report);
  const size_t png = broken.find("data:image/png;base64,");
  ASSERT_NE(png, std::string::npos);
  broken.replace(png + 22, 12, "AAAAAAAAAAAA");
  write_text(work / "broken.html", broken);
  const Counts b = parse_check(dump_dom(work / "broken.html", work, work / "chromium.err", rc));
  EXPECT_EQ(b.images, c.images);
  EXPECT_EQ(b.images_ok, c.images - 1) << "the browser check did not notice a broken image";
  std::cout << "report.html in chromium: " << c.images_ok << "/" << c.images << " images decoded, " << c.plots_shown
            << "/" << c.plots << " SVG plots laid out; with one image corrupted: " << b.images_ok << "/" << b.images
            << "\n";
  fs::remove_all(work);
  if (!HasFailure()) fs::remove_all(dir);
}

TEST(Report, BadInputIsExitCode2) {
  const glintlab::test::TempDir dir_tmp("bad");
  const fs::path dir = dir_tmp.path();
  std::ostringstream log;
  EXPECT_EQ(write_report((dir / "no-such-dir").string(), log), 2);
  EXPECT_NE(log.str().find("no such directory"), std::string::npos) << log.str();
  log.str("");
  EXPECT_EQ(write_report(dir.string(), log), 2);  // exists, but no summary.json
  EXPECT_NE(log.str().find("summary.json"), std::string::npos) << log.str();
  // A summary.json that is not a glintlab summary: the script names the key.
  write_text(dir / "summary.json", R"({"schema": "something-else"})");
  log.str("");
  EXPECT_EQ(write_report(dir.string(), log), 2) << log.str();
  EXPECT_NE(log.str().find("\"schema\""), std::string::npos) << log.str();
  // Through the command line as `glintlab report DIR` (main.cpp adds it).
  CLI::App app;
  int exit_code = -1;
  add_report_command(app, exit_code);
  const std::string missing = (dir / "no-such-dir").string();
  std::vector<std::string> args = {missing, "report"};  // CLI11 parses a reversed vector
  app.parse(args);
  EXPECT_EQ(exit_code, 2);
  fs::remove_all(dir);
}

TEST(Report, MissingPythonOrModuleIsExitCode4AndNamesThePackage) {
  // The interpreter and its modules are checked before the run is read.
  const glintlab::test::TempDir out_tmp("no-python");
  const fs::path out = out_tmp.path();
  write_text(out / "summary.json", R"({"schema": "glintlab-summary/1", "variants": []})");
  {
    ScopedEnv py("GLINTLAB_PYTHON", "/nonexistent/python3");
    std::ostringstream log;
    EXPECT_EQ(write_report(out.string(), log), 4);
    EXPECT_NE(log.str().find("python3-matplotlib"), std::string::npos) << log.str();
  }
  {
    // A matplotlib that fails to import shadows the real one.
    const glintlab::test::TempDir fake_tmp("fake-modules");
    const fs::path fake = fake_tmp.path();
    fs::create_directories(fake / "matplotlib");
    write_text(fake / "matplotlib" / "__init__.py", "raise ImportError('hidden by the glintlab report test')\n");
    ScopedEnv path("PYTHONPATH", fake.string());
    std::ostringstream log;
    EXPECT_EQ(write_report(out.string(), log), 4);
    EXPECT_NE(log.str().find("matplotlib"), std::string::npos) << log.str();
    EXPECT_NE(log.str().find("python3-matplotlib"), std::string::npos) << log.str();
    fs::remove_all(fake);
  }
  fs::remove_all(out);
}

// The Pareto front does not rank errors apart that lie within the truth's noise floor: a variant that
// costs more and is better by less than the floor is not Pareto-optimal, one better beyond it is; with
// no floor the front is the plain one. The report's own function, run by Python.
TEST(Report, TheParetoFrontDoesNotRankWithinTheNoiseFloor) {
  const test::TempDir tmp("report_pareto_floor");
  const fs::path script = tmp.path() / "front.py";
  write_text(script,
             "import sys\n"
             "sys.path.insert(0, sys.argv[1])\n"
             "import glintlab_report as g\n"
             "pts = [(1.0, 1.0, 'cheap'), (2.0, 0.95, 'close'), (3.0, 0.5, 'better')]\n"
             "names = lambda f: ','.join(p[2] for p in f)\n"
             "print(names(g.pareto_front(pts)))\n"
             "print(names(g.pareto_front(pts, {'cheap': 0.1, 'close': 0.1, 'better': 0.1})))\n"
             "print(names(g.pareto_front(pts, {'cheap': 0.6, 'close': 0.6, 'better': 0.6})))\n");
  const fs::path out = tmp.path() / "out.txt";
  const std::string cmd = "python3 " + script.string() + " " +
                          (fs::path(GLINTLAB_SOURCE_DIR) / "experiments" / "report").string() + " > " + out.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_EQ(read_text(out), "cheap,close,better\ncheap,better\ncheap\n");
}
