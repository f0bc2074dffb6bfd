// Throughput of the renderer and the metrics on the current Vulkan device,
// measured in one run so that ratios between rows are meaningful (GPU
// timestamps; median of N timed frames after warm-up; variants timed
// round-robin so that drift in the machine's load spreads over all of them).
//   1. Surface pass at 640x360 and 1280x720: the floor (same geometry and
//      passes, a trivial fragment shader), the full sand material and the
//      variants with features compiled out; per row ms/frame, its spread (the
//      interquartile range of the frames over their median), Mpix/s, the
//      ratio to the full material, and what the material itself costs (row
//      minus floor) and the floor's share of the row. Then floor, full and
//      far only on the same surface with 32 triangles, their ratios among
//      themselves: what the floor is when geometry costs nothing. Floor and
//      full also with every mesh chunk drawn (no culling), and how many
//      triangles culling drew.
//   1b. Terrain: the default experiment's dunes from its flyover, floor and
//      material on the full grid with every chunk drawn, culled, and on the
//      grid adapted to the camera path: what culling and the adaptive grid save.
//   2. The reference: ms per sample of a grid x grid reference frame against a
//      1-spp frame's, and a geometry-bound case (a small image, many samples).
//   3. The TAA resolve against the surface pass of the same frame; the surface pass and resolve of taau at
//      render scale 1/2, and its surface pass on the 32-triangle surface (cost set by pixels); fsr2's resolve
//      at 1/2; and on the default experiment's dunes the surface pass of native TAA, of taau at 1/2
//      on the output's grid and on the render resolution's (mesh_lod), and at 1/4: what fewer pixels save;
//      the floors (no material) of native and of taau 1/2 on the render grid, and the material above them.
//   4. Every per-frame metric of one 640x360 variant frame against a 2x2-sample
//      render of the same frame (its reference): ms per metric.
//   5. `glintlab measure` end to end on files: a 1920x1080 test sequence against
//      its reference (float EXR, ZIP, with a motion sequence in the `pixels`
//      convention), flicker + ΔE00 (`--metrics deltaE2000,flicker`), EXR decoding
//      included (the next frame is decoded while one is measured): frames/s of the
//      whole, and ms and frames/s per metric group and for reading a frame; then
//      the same with every group of statistics, as `run` measures.
//   6. Start-up: `glintlab compare` on a 16x16 pair of float EXR files, `glintlab check` of a
//      summary against itself, `glintlab measure` of the README's Blender sequence (--no-report)
//      and `glintlab --help`, each in a fresh process, interleaved: median wall and CPU (user +
//      system) ms, and each one's CPU over --help's.
// The scene is fixed here (the close orbit over a wavy plane the figures in the
// README were taken on), independent of the default experiment.
// Usage: glintlab_bench [--device NAME|INDEX] [--frames N] [--size W H]
//                       [--only surface|terrain|reference|taa|metrics|measure|startup]
//                       [--smoke]
// --smoke runs every section once at tiny sizes (its figures mean nothing): the test
// bench.smoke runs it with the validation layers on (GLINTLAB_VALIDATION=1), so
// that every path of the bench is exercised in CI; a validation message exits 1.
#include "core/material/program.h"
#include "core/util/allocator.h"
#include "core/render/frame_graph.h"
#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "core/render/taa_pass.h"
#include "core/render/taa_resolve.h"
#include "core/scene/camera_path.h"
#include "core/scene/mesh.h"
#include "core/vk/vk_context.h"
#include "experiments/runner/measure.h"
#include "metrics/vector_math.h"
#include "experiments/sources/variant_factory.h"
#include "metrics/color/image_io.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"
#include "metrics/flip.h"
#include "metrics/frame_metrics.h"
#include "metrics/parallel.h"
#include "metrics/stats.h"

#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <map>
#include <memory>
#include <string>
#include <thread>

using namespace glintlab;

namespace {

const char* kScene = R"({
  "name": "bench",
  "resolution": [640, 360],
  "scene": {
    "mesh": {"type": "wavy", "size": 10, "tessellation": 128, "amplitude": 0.4, "wavelength": 5},
    "sky": {"turbidity": 3, "sky_intensity": 0.5, "sun_elevation_deg": 25, "sun_azimuth_deg": 30, "sun_intensity": 6}
  },
  "camera_path": "orbit-close",
  "frames": 2,
  "material": {"preset": "thesis-hdri-match", "noise_scale": 400, "glint_sigma": 0.002, "I_glints": [20, 20, 20],
               "sigmoid_a": 2, "sigmoid_b": 6},
  "variants": [{"name": "no-aa"}, {"name": "taa", "aa": "taa"}]
})";

struct Case {
  std::string name;
  core::MaterialProgram program;
  bool single_sample = true;  // one opaque draw (as the runner renders 1-spp frames); false: SSAA's path for
                              // several samples, drawn opaque into the pass's image and added by a resolve
  bool coarse = false;        // the same surface with the fewest triangles (what the floor is without geometry)
  bool cull = true;           // draw only the mesh chunks the view can see
};

metrics::Statistics statistics(const std::vector<double>& v) {
  metrics::Statistics s;
  for (double x : v) s.add(x);
  return s;
}

// Nearest-rank median (metrics/stats.h; NaN for no values).
double median(const std::vector<double>& v) { return statistics(v).percentile(0.5); }

// The interquartile range as a share of the median: how far apart the frames of one row lie.
double spread(const std::vector<double>& v) {
  const metrics::Statistics s = statistics(v);
  return 100.0 * (s.percentile(0.75) - s.percentile(0.25)) / s.percentile(0.5);
}

// GPU ms per pass of each graph over `frames` frames after two warm-up ones, the graphs' frames interleaved
// (so that drift in the machine's load spreads over all of them): per graph, per pass name.
std::vector<std::map<std::string, std::vector<double>>> time_passes(const std::vector<RenderSetup*>& setups,
                                                                    const std::vector<core::FrameInputs>& in,
                                                                    int frames) {
  std::vector<std::map<std::string, std::vector<double>>> per(setups.size());
  for (int i = 0; i < frames + 2; ++i)
    for (size_t c = 0; c < setups.size(); ++c) {
      const core::FrameResult r = setups[c]->graph->execute(in[c]);
      if (i >= 2)
        for (const auto& t : r.timings) per[c][t.pass].push_back(t.gpu_ms);
    }
  return per;
}

// `v` as the built-in resolve `name` (taau, fsr2) at render scale 1/2 with its default jitter (halton_fsr2).
VariantSpec upscaler_half(VariantSpec v, const char* name = "taau") {
  v.render_scale = 0.5;
  v.taa = core::TaaSettings(*core::find_builtin_taa_resolve(name));
  v.taa.jitter = core::JitterSequence::HaltonFsr2;
  return v;
}

core::FrameInputs inputs(const ExperimentSpec& spec, const SceneData& data, int w, int h,
                         const std::vector<glm::vec2>& offsets) {
  core::FrameInputs in;
  in.uniforms = frame_uniforms(spec.path.frame(0, w, h), data.env, w, h, data.env_texture.mips_rgba.size());
  in.samples = core::samples_for(spec.path, 0, w, h, offsets);
  return in;
}

// The measure section: `glintlab measure` on files, each run in a process of its own that starts as
// the command does. Every process here is forked from one launcher, itself forked at the bench's
// start, before any thread exists: glibc hands the heap arenas of finished threads to new ones, and
// in such an arena every decoded frame comes in fresh pages (run in the bench's own process after
// the other sections, reading a 1080p float frame took 237 ms instead of about 70).
namespace fs = std::filesystem;

// Runs fn in a fresh process forked from this one; false if it failed (fn returns false or throws).
template <typename Fn>
bool in_child(Fn&& fn) {
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid < 0) return false;
  if (pid == 0) {
    int rc = 1;
    try {
      rc = fn() ? 0 : 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: measure section: %s\n", e.what());
    }
    std::fflush(stdout);
    std::fflush(stderr);
    ::_exit(rc);
  }
  int status = 0;
  return ::waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// A sequence a renderer might write: a smooth texture moving 1.5 px right and 0.5 px down a frame,
// with sparse bright sparkles that the test redraws at random every frame (the flicker to find).
void write_measure_sequence(const fs::path& dir, int w, int h, int frames, bool half) {
  const metrics::ColorManager cm;
  for (const char* sub : {"ref", "test", "motion"}) fs::create_directories(dir / sub);
  const double vx = 1.5, vy = 0.5;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < frames; ++k) {
    Image ref(w, h, 4, 1.0f), test(w, h, 4, 1.0f), motion(w, h, 4, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double sx = x - vx * k, sy = y - vy * k;  // the surface point under pixel (x, y)
        const double t = 0.4 + 0.25 * std::sin(0.05 * sx) * std::cos(0.07 * sy) + 0.1 * std::sin(0.31 * sx + 0.17 * sy);
        for (int c = 0; c < 3; ++c) ref.at(x, y, c) = test.at(x, y, c) = float(t * (1.0 - 0.1 * c));
        float* m = motion.px(x, y);
        m[0] = float(vx), m[1] = float(vy), m[2] = 1.0f, m[3] = 1.0f;
      }
    for (int i = 0; i < w * h / 500; ++i) {
      const int x = int(u(rng) * (w - 1)), y = int(u(rng) * (h - 1));
      for (int c = 0; c < 3; ++c) test.at(x, y, c) += 20.0f;
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.exr", k);
    const auto chroma = cm.chromaticities("lin_rec709");
    metrics::write_exr((dir / "ref" / name).string(), ref, chroma, half);
    metrics::write_exr((dir / "test" / name).string(), test, chroma, half);
    metrics::write_exr_data((dir / "motion" / name).string(), motion);
  }
}

// `glintlab measure --metrics LIST` of the sequence in dir (its first `frames` frames; the outputs in
// dir/out), as the command runs it (its allocator settings included). The wall time, start-up included.
double run_measure(const fs::path& dir, int frames, const std::vector<std::string>& metrics_list) {
  tune_allocator_for_rendering();  // as main() of the glintlab CLI
  MeasureOptions o;
  o.reference = (dir / "ref").string();
  o.tests = {{"test", (dir / "test").string(), ""}};
  o.motion = (dir / "motion").string();
  o.metrics = metrics_list;
  o.first = 0;
  o.last = frames - 1;
  o.out_dir = (dir / "out").string();
  o.report = false;
  std::error_code ec;
  fs::remove_all(o.out_dir, ec);
  std::ostringstream log;
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = measure_sequences(o, log);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (rc != 0) throw std::runtime_error("glintlab measure exited " + std::to_string(rc) + "\n" + log.str());
  return wall_s;
}

// The per-frame times of a run on their threads, from its summary.json.
void print_measure_stages(const fs::path& summary_path, int frames) {
  std::ifstream in(summary_path);
  const nlohmann::json s = nlohmann::json::parse(in);
  const auto mean = [](const nlohmann::json& st) { return st.value("mean", 0.0); };
  std::printf("  per frame, on their threads (the %d-frame run's means):\n", frames);
  std::printf("  %-24s %8.2f ms  %7.2f frames/s\n", "read a test frame", mean(s["variants"][0]["wall_ms"]),
              1000.0 / mean(s["variants"][0]["wall_ms"]));
  std::printf("  %-24s %8.2f ms  %7.2f frames/s\n", "read a reference frame", mean(s["references"][0]["wall_ms"]),
              1000.0 / mean(s["references"][0]["wall_ms"]));
  for (auto it = s["metric_ms_per_metric"].begin(); it != s["metric_ms_per_metric"].end(); ++it)
    if (it.key() != "convert")
      std::printf("  %-24s %8.2f ms  %7.2f frames/s\n", it.key().c_str(), mean(it.value()), 1000.0 / mean(it.value()));
  std::printf("  %-24s %8.2f ms  %7.2f frames/s\n", "all metrics of a frame", mean(s["metric_ms_per_frame"]),
              1000.0 / mean(s["metric_ms_per_frame"]));
}

// One format: the sequence written, then measured with ΔE00 and flicker (the `measure` goal's pair:
// `--metrics deltaE2000,flicker`), 2 frames and all of them, each in a fresh process (the difference is
// the time a frame takes once the command has started), then all of them again with every group of
// statistics (`--metrics deltaE2000`: glint statistics and pooled error too, as `run` measures).
bool measure_section(const fs::path& dir, int w, int h, int frames, bool half) {
  if (!in_child([&] { return write_measure_sequence(dir, w, h, frames, half), true; })) return false;
  ::sync();  // the files on disk before the runs, so that their writing-back does not share the cores
  const std::vector<std::string> goal = {"deltaE2000", "flicker"}, every = {"deltaE2000"};
  const fs::path two = dir / "two_frames_s";
  if (!in_child([&] { return bool(std::ofstream(two) << run_measure(dir, 2, goal)); })) return false;
  const bool ok = in_child([&] {
    const double wall_s = run_measure(dir, frames, goal);
    double wall2_s = 0;
    std::ifstream(two) >> wall2_s;
    const double per_frame_s = (wall_s - wall2_s) / (frames - 2);
    std::printf("\nmeasure: one %dx%d test sequence against its reference (%s RGBA EXR, ZIP; motion float RGBA in "
                "the pixels convention), --metrics deltaE2000,flicker, %ld metric threads, vector math %s; each "
                "run a fresh process, start-up, headers and hashing included:\n"
                "  %d frames  %6.2f s wall  %5.2f frames/s\n  2 frames   %6.2f s wall\n",
                w, h, half ? "half" : "float", metrics::metric_threads(), metrics::vector_math_isa(), frames, wall_s,
                frames / wall_s, wall2_s);
    if (per_frame_s > 0)
      std::printf("  a frame once started (the difference): %.1f ms, %.2f frames/s\n", 1000.0 * per_frame_s,
                  1.0 / per_frame_s);
    print_measure_stages(dir / "out" / "summary.json", frames);
    return true;
  });
  return ok && in_child([&] {
    const double wall_s = run_measure(dir, frames, every);
    std::printf("  the same with every group of statistics (--metrics deltaE2000: glint statistics and pooled "
                "error too):\n  %d frames  %6.2f s wall  %5.2f frames/s\n",
                frames, wall_s, frames / wall_s);
    print_measure_stages(dir / "out" / "summary.json", frames);
    return true;
  });
}

// The launcher: forked at the bench's start, it waits for the section's turn (or the bench's end).
class MeasureProcess {
 public:
  void start(int w, int h, int frames, const std::string& keep) {
    int fd[2];
    if (::pipe(fd) != 0) throw std::runtime_error("measure section: pipe failed");
    std::fflush(stdout);
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("measure section: fork failed");
    if (pid_ == 0) {
      ::close(fd[1]);
      char go = 0;
      bool ok = true;
      if (::read(fd[0], &go, 1) == 1 && go == 'g') {
        char tmpl[] = "/tmp/glintlab_bench_measure_XXXXXX";
        const char* made = keep.empty() ? ::mkdtemp(tmpl) : keep.c_str();
        if (!made) {
          std::fprintf(stderr, "error: measure section: cannot make a folder under /tmp\n");
          ::_exit(1);
        }
        const fs::path top(made);
        for (bool half : {false, true}) ok = measure_section(top / (half ? "half" : "float"), w, h, frames, half) && ok;
        std::error_code ec;
        if (keep.empty()) fs::remove_all(top, ec);
        else
          for (const char* f : {"float", "half"}) fs::remove_all(top / f / "out", ec), fs::remove(top / f / "two_frames_s", ec);
      }
      std::fflush(stdout);
      ::_exit(ok ? 0 : 1);
    }
    ::close(fd[0]);
    go_ = fd[1];
  }
  // Lets the launcher run the section and waits for it; false if it failed.
  bool run() {
    if (pid_ <= 0) return true;
    std::fflush(stdout);
    const char go = 'g';
    const bool sent = ::write(go_, &go, 1) == 1;
    ::close(go_);
    go_ = -1;
    int status = 0;
    const pid_t pid = pid_;
    pid_ = 0;
    return sent && ::waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  }
  ~MeasureProcess() {  // not run (an earlier error): the launcher sees the pipe close and exits
    if (go_ >= 0) ::close(go_);
    if (pid_ > 0) ::waitpid(pid_, nullptr, 0);
  }

 private:
  pid_t pid_ = 0;
  int go_ = -1;
};

// ---- the start-up section: the glintlab CLI (GLINTLAB_CLI) in fresh processes.
struct ProcessCost {
  double wall_ms = 0, cpu_ms = 0;  // cpu: user + system of the process
};

// Runs `args` with stdout and stderr to /dev/null; the exit code must be 0.
ProcessCost spawn_timed(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t io;
  posix_spawn_file_actions_init(&io);
  posix_spawn_file_actions_addopen(&io, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&io, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = posix_spawn(&pid, argv[0], &io, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&io);
  if (rc != 0) throw std::runtime_error("startup section: cannot start " + args[0]);
  int status = 0;
  rusage ru{};
  if (::wait4(pid, &status, 0, &ru) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("startup section: " + args[0] + " " + args[1] + " failed");
  ProcessCost c;
  c.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  c.cpu_ms = (double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e6 + double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec)) / 1e3;
  return c;
}

void startup_section(int runs) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("glintlab-bench-startup-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  Image ref(16, 16, 3), test(16, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) {
        ref.at(x, y, c) = 0.1f + 0.05f * float((x + y + c) % 7);
        test.at(x, y, c) = ref.at(x, y, c) * (1.0f + 0.02f * float((x * y + c) % 5));
      }
  const metrics::ColorManager cm;
  const auto chroma = cm.chromaticities("lin_rec709");
  const std::string r = (dir / "ref.exr").string(), t = (dir / "test.exr").string();
  metrics::write_exr(r, ref, chroma);
  metrics::write_exr(t, test, chroma);
  const std::string summary = std::string(GLINTLAB_SOURCE_DIR) + "/results/baselines/regression.json";
  struct Command {
    const char* name;
    std::vector<std::string> args;
    std::vector<ProcessCost> costs;
  };
  // The README's measure of a Blender sequence: eight 80x45 multilayer EXR frames with their vectors.
  const std::string cycles = std::string(GLINTLAB_SOURCE_DIR) + "/tests/data/blender/";
  std::vector<Command> commands = {
      {"glintlab --help", {GLINTLAB_CLI, "--help"}, {}},
      {"glintlab compare 16x16", {GLINTLAB_CLI, "compare", t, r}, {}},
      {"glintlab check", {GLINTLAB_CLI, "check", summary, summary}, {}},
      {"glintlab measure Cycles",
       {GLINTLAB_CLI, "measure", "--reference", cycles + "ref/frame_####.exr:ViewLayer.Combined", "--test",
        "spp1=" + cycles + "spp1/frame_####.exr:ViewLayer.Combined", "--motion-from", "reference",
        "--motion-convention", "blender", "--out", (dir / "measure").string(), "--no-report"},
       {}}};
  for (int i = 0; i < runs + 1; ++i)  // the first round warms the page cache and is not counted
    for (Command& c : commands) {
      const ProcessCost cost = spawn_timed(c.args);
      if (i > 0) c.costs.push_back(cost);
    }
  auto median_of = [](const std::vector<ProcessCost>& v, double ProcessCost::*field) {
    std::vector<double> x;
    for (const auto& c : v) x.push_back(c.*field);
    return median(x);
  };
  const double help_cpu = median_of(commands[0].costs, &ProcessCost::cpu_ms);
  std::printf("\nstart-up: each command in a fresh process, %d interleaved runs (median)\n", runs);
  std::printf("  %-24s %9s %9s %14s\n", "command", "wall ms", "CPU ms", "CPU / --help");
  for (const Command& c : commands) {
    const double cpu = median_of(c.costs, &ProcessCost::cpu_ms);
    std::printf("  %-24s %9.1f %9.1f %14.2f\n", c.name, median_of(c.costs, &ProcessCost::wall_ms), cpu, cpu / help_cpu);
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

int bench(int argc, char** argv) {
  if (!std::getenv("GLINTLAB_BENCH_DEFAULT_MALLOC")) tune_allocator_for_rendering();  // as the glintlab CLI does
  std::string device;
  int frames = 10;
  std::string only;
  std::vector<int> size;
  bool smoke = false;
  std::string keep;
  CLI::App app("glintlab_bench: throughput of the renderer and the metrics on a Vulkan device (GPU timestamps)");
  app.add_option("--device", device, "Vulkan device: index or part of its name (default: lavapipe)");
  app.add_option("--frames", frames, "timed frames per case (median; default 10)")->check(CLI::Range(1, 100000));
  app.add_option("--size", size, "one size W H for the surface, terrain and TAA sections (default: 640x360 and "
                                 "1280x720)")
      ->expected(2)
      ->check(CLI::Range(1, 16384));
  app.add_option("--only", only, "run one section")
      ->check(CLI::IsMember({"surface", "terrain", "reference", "taa", "metrics", "measure", "startup"}));
  app.add_option("--measure-files", keep, "the measure section writes its sequences into DIR/float and DIR/half "
                                          "and keeps them (for profiling `glintlab measure` alone)");
  app.add_flag("--smoke", smoke, "every section once at tiny sizes, to check that the bench runs (figures "
                                 "meaningless)");
  CLI11_PARSE(app, argc, argv);
  const int measure_frames = smoke ? 3 : std::max(4, frames);  // two runs: 2 frames and these
  MeasureProcess measure_process;
  if (only.empty() || only == "measure") measure_process.start(smoke ? 64 : 1920, smoke ? 36 : 1080, measure_frames, keep);
  std::vector<std::pair<int, int>> sizes = {{640, 360}, {1280, 720}};
  if (smoke) {
    frames = 1;
    sizes = {{64, 36}};
  }
  if (!size.empty()) sizes = {{size[0], size[1]}};
  ExperimentSpec spec = ExperimentSpec::from_json(nlohmann::json::parse(kScene), "<bench scene>");
  metrics::ColorManager cm;
  SceneData data = build_scene(spec, cm);
  core::VkContext ctx(core::ContextOptions{device, core::VkContext::validation_requested_by_env()});
  core::SceneGpu scene(ctx, data.mesh, data.env_texture);
  core::MeshSpec coarse_spec = spec.mesh;
  coarse_spec.tessellation = 4;
  const core::Mesh coarse_mesh = core::build_mesh(coarse_spec);
  core::SceneGpu coarse_scene(ctx, coarse_mesh, data.env_texture);
  const char* lp_threads = std::getenv("LP_NUM_THREADS");
  std::printf("device: %s (LP_NUM_THREADS=%s)%s\nscene: wavy plane (%zu triangles), orbit-close frame 0, "
              "thesis-hdri-match sand with glints; %d timed frames after 2 warm-up (median)\n",
              ctx.info().name.c_str(), lp_threads ? lp_threads : "unset",
              ctx.validation_enabled() ? ", validation layers on (timings not representative)" : "",
              data.mesh.indices.size() / 3, frames);

  // ---- 1. surface pass: floor, full material, pruned variants
  const core::SandParams base = to_working_space(spec.variants.front().material, spec.working_space, cm);
  auto sand = [&](core::SandParams p, double lo, double hi) {
    return core::sand_program(p, {lo, hi, "final"}, core::ProgramRole::Variant);
  };
  std::vector<Case> cases;
  cases.push_back({"floor (geometry and passes only)", core::geometry_only_program()});
  cases.push_back({"full (close+far+transition)", sand(base, 0.0, 1e30)});
  cases.push_back({"floor, as one sample of SSAA", core::geometry_only_program(), false});
  cases.push_back({"full, as one sample of SSAA", sand(base, 0.0, 1e30), false});
  cases.push_back({"as the scene needs", core::sand_program(base, data.range, core::ProgramRole::Variant)});
  core::SandParams no_t = base;
  no_t.T = 0;
  cases.push_back({"T = 0 (no transmission)", sand(no_t, 0.0, 1e30)});
  core::SandParams no_g = base;
  no_g.glint_model = core::kGlintModelNone;
  cases.push_back({"no glints", sand(no_g, 0.0, 1e30)});
  // A transition pushed out to b = 100 is never reached within 20 units: the far branch compiles out.
  core::SandParams near_only = base;
  near_only.sigmoid_b = 100;
  cases.push_back({"close only (b = 100, dist <= 20)", sand(near_only, 0.0, 20.0)});
  cases.push_back({"far only (close never reached)", sand(base, 1e6, 1e30)});
  core::SandParams minimal = no_t;
  minimal.glint_model = core::kGlintModelNone;
  cases.push_back({"far only, T = 0, no glints", sand(minimal, 1e6, 1e30)});
  // What culling the chunks the camera cannot see saves (the rows above cull).
  cases.push_back({"floor, every chunk drawn", core::geometry_only_program(), true, false, false});
  cases.push_back({"full, every chunk drawn", sand(base, 0.0, 1e30), true, false, false});
  // The same three on the surface tessellated 4x4 (32 triangles): the floor without the geometry's cost.
  const size_t first_coarse = cases.size();
  cases.push_back({"32 tris: floor", core::geometry_only_program(), true, true});
  cases.push_back({"32 tris: full", sand(base, 0.0, 1e30), true, true});
  cases.push_back({"32 tris: far only, T = 0, no glints", sand(minimal, 1e6, 1e30), true, true});

  auto section = [&](const char* name) { return only.empty() || only == name; };
  for (auto [w, h] : sizes) {
    if (!section("surface")) break;
    const core::FrameInputs one = inputs(spec, data, w, h, {glm::vec2(0.0f)});
    std::printf("\nsurface pass, %dx%d (%.3f Mpix), sky on\n", w, h, double(w) * h * 1e-6);
    std::printf("  %-34s %9s %7s %9s %7s %11s %11s\n", "variant", "ms/frame", "spread", "Mpix/s", "ratio",
                "material ms", "floor share");
    std::vector<std::unique_ptr<core::SurfaceRenderer>> passes;
    for (const Case& c : cases) {
      core::SurfacePassOptions o;
      o.program = c.program;
      o.single_sample = c.single_sample;
      o.cull = c.cull;
      passes.push_back(std::make_unique<core::SurfaceRenderer>(ctx, c.coarse ? coarse_scene : scene, w, h, o));
      for (int i = 0; i < 2; ++i) passes.back()->render(one.uniforms, one.samples);  // warm-up (JIT, caches)
    }
    std::vector<std::vector<double>> ms(cases.size());
    for (int i = 0; i < frames; ++i)
      for (size_t c = 0; c < cases.size(); ++c)
        ms[c].push_back(passes[c]->render(one.uniforms, one.samples).timings[0].gpu_ms);
    std::printf("  (chunk culling: %llu of %llu triangles drawn on the main mesh, %llu of %llu on the 32)\n",
                (unsigned long long)passes[0]->pass().triangles_drawn(),
                (unsigned long long)passes[0]->pass().triangles_submitted_without_culling(),
                (unsigned long long)passes[first_coarse]->pass().triangles_drawn(),
                (unsigned long long)passes[first_coarse]->pass().triangles_submitted_without_culling());
    for (size_t c = 0; c < cases.size(); ++c) {
      // Ratios and the floor within each mesh: the main one, then the coarse one.
      const size_t base_row = c < first_coarse ? 0 : first_coarse;
      const double floor_ms = median(ms[base_row]), full_ms = median(ms[base_row + 1]);
      const double m = median(ms[c]);
      std::printf("  %-34s %9.2f %6.0f%% %9.2f %7.2f %11.2f %10.0f%%\n", cases[c].name.c_str(), m, spread(ms[c]),
                  double(w) * h * 1e-6 / (m * 1e-3), m / full_ms, m - floor_ms, 100.0 * floor_ms / m);
    }
  }

  // ---- 1b. terrain: what culling and the adaptive grid save on a large mesh seen from inside it
  // (the default experiment's frame 4): floor and the sand material the scene needs ("sand"), on the full grid with
  // every chunk drawn, with culling, and on the adapted grid with culling.
  if (section("terrain")) {
    std::vector<std::pair<int, int>> tsizes = sizes;
    if (tsizes.size() > 1) tsizes = {{320, 180}, {1280, 720}};
    for (auto [w, h] : tsizes) {
      // The default experiment itself (its dunes, flyover and material), at this size.
      ExperimentSpec tspec = ExperimentSpec::load(resolve_experiment_path("default"));
      tspec.width = w;
      tspec.height = h;
      const SceneData tdata = build_scene(tspec, cm);  // the adapted grid
      core::MeshSpec full_spec = tspec.mesh;
      full_spec.max_edge_px = 0.0f;
      full_spec.max_error_px = 0.0f;
      const core::Mesh full_mesh = core::build_mesh(full_spec);
      core::SceneGpu full_gpu(ctx, full_mesh, tdata.env_texture), adapted_gpu(ctx, tdata.mesh, tdata.env_texture);
      const core::SandParams tp = to_working_space(tspec.variants.front().material, tspec.working_space, cm);
      const core::MaterialProgram material = core::sand_program(tp, tdata.range, core::ProgramRole::Variant);
      core::FrameInputs in;
      in.uniforms = frame_uniforms(tspec, tdata, 4);
      in.samples = core::samples_for(tspec.path, 4, w, h, {glm::vec2(0.0f)});
      struct TerrainCase {
        std::string name;
        const core::SceneGpu* scene;
        bool cull;
        bool floor;
      };
      const std::vector<TerrainCase> tcases = {
          {"floor: full grid, every chunk drawn", &full_gpu, false, true},
          {"floor: full grid, culled", &full_gpu, true, true},
          {"floor: adapted grid, culled", &adapted_gpu, true, true},
          {"sand: full grid, every chunk drawn", &full_gpu, false, false},
          {"sand: full grid, culled", &full_gpu, true, false},
          {"sand: adapted grid, culled", &adapted_gpu, true, false}};
      std::vector<std::unique_ptr<core::SurfaceRenderer>> tpasses;
      for (const TerrainCase& c : tcases) {
        core::SurfacePassOptions o;
        o.program = c.floor ? core::geometry_only_program() : material;
        o.single_sample = true;
        o.cull = c.cull;
        tpasses.push_back(std::make_unique<core::SurfaceRenderer>(ctx, *c.scene, w, h, o));
        for (int i = 0; i < 2; ++i) tpasses.back()->render(in.uniforms, in.samples);
      }
      std::vector<std::vector<double>> tms(tcases.size());
      for (int i = 0; i < frames; ++i)
        for (size_t c = 0; c < tcases.size(); ++c)
          tms[c].push_back(tpasses[c]->render(in.uniforms, in.samples).timings[0].gpu_ms);
      std::printf("\nterrain %dx%d: the default experiment's dunes, flyover frame 4 (full grid %zu triangles, "
                  "adapted at max_edge_px %g, max_error_px %g: %zu)\n",
                  w, h, full_mesh.indices.size() / 3, double(tspec.mesh.max_edge_px), double(tspec.mesh.max_error_px),
                  tdata.mesh.indices.size() / 3);
      std::printf("  %-40s %9s %11s %7s\n", "case", "ms/frame", "triangles", "ratio");
      for (size_t c = 0; c < tcases.size(); ++c) {
        const size_t first = c < 3 ? 0 : 3;  // ratio to the full grid with every chunk drawn
        std::printf("  %-40s %9.2f %11llu %7.2f\n", tcases[c].name.c_str(), median(tms[c]),
                    (unsigned long long)tpasses[c]->pass().triangles_drawn(), median(tms[c]) / median(tms[first]));
      }
    }
  }

  // ---- 2. the reference: cost per sample, and a geometry-bound case. The
  // runner's way (supersampled passes, experiments/sources/variant_factory.h)
  // beside one geometry pass per sample (what it did before), same samples count.
  if (section("reference")) {
    const core::MaterialProgram ref = core::sand_program(base, data.range, core::ProgramRole::Reference);
    struct RefCase {
      int w, h, grid;
    };
    std::printf("\nreference (micro model, grid x grid stratified samples)\n");
    std::printf("  %-20s %-28s %11s %11s %11s %7s\n", "case", "method", "ms/frame", "ms/sample", "1-spp ms",
                "ratio");
    const std::vector<RefCase> ref_cases = smoke ? std::vector<RefCase>{{64, 36, 4}, {16, 9, 8}}
                                                 : std::vector<RefCase>{{640, 360, 16}, {16, 9, 64}};
    for (RefCase rc : ref_cases) {
      core::SurfacePassOptions o;
      o.program = ref;
      core::SurfaceRenderer one_spp(ctx, scene, rc.w, rc.h, o);
      const core::FrameInputs one = inputs(spec, data, rc.w, rc.h, {glm::vec2(0.0f)});
      one_spp.render(one.uniforms, one.samples);
      std::vector<double> t1;
      for (int i = 0; i < std::max(3, frames / 2); ++i) t1.push_back(one_spp.render(one.uniforms, one.samples).gpu_ms);
      const Supersampling sampling = supersampling(rc.grid, rc.w, rc.h, kReferencePatternSeed);
      RenderSetup fast = build_reference(ctx, scene, rc.w, rc.h, ref, rc.grid);
      const core::FrameInputs many = inputs(spec, data, rc.w, rc.h, sampling.offsets);
      const core::FrameInputs every = inputs(spec, data, rc.w, rc.h, core::stratified_offsets(rc.grid, 1u));
      const double n = double(rc.grid) * rc.grid;
      char label[64];
      std::snprintf(label, sizeof label, "%dx%d at %d spp", rc.w, rc.h, int(n));
      auto row = [&](const char* method, double ms) {
        std::printf("  %-20s %-28s %11.1f %11.4f %11.4f %7.2f\n", label, method, ms, ms / n, median(t1),
                    ms / n / median(t1));
      };
      std::vector<double> tf;
      for (int i = 0; i < 2; ++i) tf.push_back(fast.graph->execute(many).gpu_ms);
      char method[64];
      std::snprintf(method, sizeof method, "supersampled (f = %d, %zu passes)", sampling.factor, sampling.offsets.size());
      row(method, median(tf));
      // One geometry pass per sample (1 frame: at 4096 spp it takes half a minute).
      row("one pass per sample", one_spp.render(every.uniforms, every.samples).gpu_ms);
    }
  }

  // ---- 3. TAA resolve vs the surface pass of its frame
  if (section("taa")) {
    const int w = sizes.front().first, h = sizes.front().second;
    const core::MaterialProgram program = core::sand_program(base, data.range, core::ProgramRole::Variant);
    RenderSetup taa = build_variant(ctx, scene, w, h, spec.variants[1], program);
    core::FrameInputs in = inputs(spec, data, w, h, {core::jitter_offset(core::JitterSequence::Halton16, 0)});
    // Temporal upscaling at render scale 1/2 (taau): the surface pass at (w/2)x(h/2), the resolve at w x h,
    // in the same run as the native rows.
    const VariantSpec half = upscaler_half(spec.variants[1]);
    RenderSetup up = build_variant(ctx, scene, w, h, half, program);
    RenderSetup fsr = build_variant(ctx, scene, w, h, upscaler_half(spec.variants[1], "fsr2"), program);
    const int rw = half.render_width(w), rh = half.render_height(h);
    core::FrameInputs hin = inputs(spec, data, rw, rh, {core::jitter_offset(half.taa.jitter, 0, 0.5)});
    // The same surface with 32 triangles: where the pixels, not the triangles, decide the pass's cost (as on a GPU).
    RenderSetup ctaa = build_variant(ctx, coarse_scene, w, h, spec.variants[1], program);
    RenderSetup cup = build_variant(ctx, coarse_scene, w, h, half, program);
    auto times = time_passes({&taa, &up, &ctaa, &cup, &fsr}, {in, hin, in, hin, hin}, frames);
    auto& per = times[0];
    auto& hper = times[1];
    std::printf("\nTAA at %dx%d: surface pass (with motion vectors) %.2f ms, TAA resolve %.2f ms (%.3f of the surface "
                "pass)\n",
                w, h, median(per["surface"]), median(per["taa"]), median(per["taa"]) / median(per["surface"]));
    std::printf("taau at render scale 1/2 (%dx%d -> %dx%d): surface pass %.2f ms (%.3f of native), resolve %.2f ms "
                "(%.3f of native's)\n",
                rw, rh, w, h, median(hper["surface"]), median(hper["surface"]) / median(per["surface"]),
                median(hper["taa"]), median(hper["taa"]) / median(per["taa"]));
    std::printf("fsr2 at render scale 1/2: resolve %.2f ms (%.3f of native's)\n", median(times[4]["taa"]),
                median(times[4]["taa"]) / median(per["taa"]));
    std::printf("the same surface with %zu triangles: surface pass native %.2f ms, taau at 1/2 %.2f ms (%.3f of native)\n",
                coarse_mesh.indices.size() / 3, median(times[2]["surface"]), median(times[3]["surface"]),
                median(times[3]["surface"]) / median(times[2]["surface"]));

    // The same on the dunes of the default experiment (its flyover's frame 4, its adapted grid): native TAA,
    // and taau at 1/2 on the grid adapted for the output (mesh_lod "display", the default) and for its render
    // resolution ("render"), in this one run, frames interleaved.
    ExperimentSpec dspec = ExperimentSpec::load(resolve_experiment_path("default"));
    dspec.width = w;
    dspec.height = h;
    const VariantSpec* dtaa = nullptr;
    for (const VariantSpec& v : dspec.variants)
      if (v.name == "taa") dtaa = &v;
    if (!dtaa) throw std::runtime_error("the default experiment has no variant \"taa\"");
    const VariantSpec dhalf = upscaler_half(*dtaa);
    VariantSpec drender = dhalf;
    drender.mesh_lod = "render";
    VariantSpec dquarter = dhalf;  // what a lower resolution does not shrink: the triangles' own cost
    dquarter.render_scale = 0.25;
    const VariantSpec native = *dtaa;
    dspec.variants = {native, dhalf, drender, dquarter};
    const SceneData ddata = build_scene(dspec, cm);  // the adapted grid, and the one at render scale 1/2
    const SceneGpus dgpus(ctx, ddata);
    const core::MaterialProgram dprogram = core::sand_program(
        to_working_space(native.material, dspec.working_space, cm), ddata.range, core::ProgramRole::Variant);
    std::vector<RenderSetup> dsetups;
    std::vector<core::FrameInputs> dinputs;
    for (const VariantSpec& v : dspec.variants) {
      dsetups.push_back(build_variant(ctx, dgpus.of(v), w, h, v, dprogram));
      const int vw = v.render_width(w), vh = v.render_height(h);
      core::FrameInputs vin;
      vin.uniforms = frame_uniforms(dspec.path.frame(4, vw, vh), ddata.env, vw, vh, ddata.env_texture.mips_rgba.size());
      vin.samples = core::samples_for(dspec.path, 4, vw, vh, {core::jitter_offset(v.taa.jitter, 0, v.render_scale)});
      dinputs.push_back(vin);
    }
    // Their floors (no material: the cost of the triangles and the passes, which fewer pixels shrink only in
    // part): native and taau 1/2 on the render resolution's grid.
    for (size_t c : {size_t(0), size_t(2)}) {
      dsetups.push_back(build_variant(ctx, dgpus.of(dspec.variants[c]), w, h, dspec.variants[c],
                                      core::geometry_only_program()));
      dinputs.push_back(dinputs[c]);
    }
    std::vector<RenderSetup*> dptrs;
    for (RenderSetup& r : dsetups) dptrs.push_back(&r);
    auto dper = time_passes(dptrs, dinputs, frames);
    std::printf("on the default experiment's dunes at %dx%d (flyover frame 4), surface pass:\n", w, h);
    std::printf("  %-34s %11s %11s %9s\n", "variant", "triangles", "ms", "ratio");
    const char* labels[] = {"native TAA (falcor)",        "taau 1/2, mesh_lod display", "taau 1/2, mesh_lod render",
                            "taau 1/4, mesh_lod display", "native TAA, floor",          "taau 1/2 render, floor"};
    const size_t of_variant[] = {0, 1, 2, 3, 0, 2};
    for (size_t c = 0; c < dsetups.size(); ++c) {
      const bool lod = dspec.variants[of_variant[c]].mesh_lod == "render";
      std::printf("  %-34s %11zu %11.2f %9.3f\n", labels[c],
                  (lod ? ddata.render_lods.at(0.5) : ddata.mesh).indices.size() / 3, median(dper[c]["surface"]),
                  median(dper[c]["surface"]) / median(dper[0]["surface"]));
    }
    const double above_native = median(dper[0]["surface"]) - median(dper[4]["surface"]);
    const double above_half = median(dper[2]["surface"]) - median(dper[5]["surface"]);
    std::printf("  the material above its floor: native %.2f ms, taau 1/2 render %.2f ms (%.3f of native)\n",
                above_native, above_half, above_half / above_native);
  }

  // ---- 4. metrics of one variant frame
  if (section("metrics")) {
    const int w = smoke ? 64 : 640, h = smoke ? 36 : 360;
    core::SurfacePassOptions o;
    o.program = core::sand_program(base, data.range, core::ProgramRole::Variant);
    o.motion = true;
    core::SurfaceRenderer r(ctx, scene, w, h, o);
    const core::FrameInputs in = inputs(spec, data, w, h, {glm::vec2(0.0f)});
    core::FrameResult f = r.render(in.uniforms, in.samples);
    const Image& test = f.images.at("color");
    const Image& motion = f.images.at("motion");
    // The reference: the same frame with 2x2 samples, so that every pixel metric has differences to
    // measure (against the test frame itself FLIP and the colour metrics would skip most of the work).
    const core::FrameInputs ref_in =
        inputs(spec, data, w, h, {glm::vec2(-0.25f, -0.25f), glm::vec2(0.25f, -0.25f), glm::vec2(-0.25f, 0.25f),
                                  glm::vec2(0.25f, 0.25f)});
    const Image ref_linear = r.render(ref_in.uniforms, ref_in.samples).images.at("color");
    metrics::FrameMetrics fm(cm, spec.working_space, spec.metrics, spec.measured_metric_options());
    const auto ref = fm.prepare(ref_linear);
    std::printf("\nHDR-FLIP exposures of the reference: %d, from %.3f to %.3f stops\n", ref.flip ? ref.flip->exposures().count : 0,
                ref.flip ? ref.flip->exposures().start : 0.0, ref.flip ? ref.flip->exposures().stop : 0.0);
    metrics::FlickerTracker tracker;
    std::map<std::string, std::vector<double>> cost;
    std::vector<double> total;
    for (int i = 0; i < std::max(3, frames / 2); ++i) {
      metrics::NamedValues c;
      fm.measure(test, ref, motion, tracker, &c);
      double sum = 0;
      for (const auto& [n, ms] : c) {
        cost[n].push_back(ms);
        sum += ms;
      }
      if (i > 0) total.push_back(sum);  // the first has no previous frame for the flicker metrics
    }
    std::printf("\nmetrics of one %dx%d variant frame (wall ms, %ld of %u hardware threads; "
                "GLINTLAB_METRIC_THREADS caps them): total %.1f ms\n",
                w, h, metrics::metric_threads(), std::thread::hardware_concurrency(), median(total));
    for (const auto& [n, v] : cost) std::printf("  %-16s %8.2f ms\n", n.c_str(), median(v));
    // HDR-FLIP as it was before the reference's per-exposure state was shared by the variants.
    const Image test_xyz = cm.to_xyz_d65(test, spec.working_space);
    std::vector<double> alone;
    for (int i = 0; i < 3; ++i) {
      auto t0 = std::chrono::steady_clock::now();
      metrics::hdr_flip_map(test_xyz, *ref.xyz, spec.metric_options.flip_ppd);
      alone.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::printf("  %-16s %8.2f ms  (HDR-FLIP preparing the reference for every variant, as before)\n", "flip, unshared",
                median(alone));
  }
  // ---- 5. measure: files in, metrics out
  if (section("measure") && !measure_process.run()) return 1;
  // ---- 6. start-up of the CLI
  if (section("startup")) startup_section(smoke ? 1 : 15);
  if (ctx.validation_enabled() && ctx.validation_message_count() > 0) {
    std::fprintf(stderr, "error: the Vulkan validation layer reported %zu message(s); first: %s\n",
                 ctx.validation_message_count(), ctx.validation_messages().front().c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return bench(argc, argv);
  } catch (const std::exception& e) {  // a device that is not there, a Vulkan error: said, not aborted
    std::fflush(stdout);
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
