#include "experiments/taa_test/taa_test.h"

#include "core/material/program.h"
#include "core/render/frame_graph.h"
#include "core/render/sample_schedule.h"
#include "core/render/surface_pass.h"
#include "core/render/taa_pass.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "core/util/strings.h"
#include "core/vk/shader_compiler.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/runner.h"
#include "experiments/sources/rendered_sources.h"
#include "experiments/spec/experiment_spec.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"

#include <cmath>
#include <iomanip>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace glintlab {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// ---- the scenes: wavy sand under a low sun, small enough for a CI job on two CPU cores

json sky() {
  return {{"turbidity", 3}, {"sky_intensity", 0.5}, {"sun_elevation_deg", 25}, {"sun_azimuth_deg", 30},
          {"sun_intensity", 6}};
}
// The micro model at every distance (no close-to-far transition within the scenes), so that a variant
// renders the function its truth integrates: every difference is sampling.
json sand() {
  return {{"preset", "thesis-hdri-match"}, {"noise_scale", 400}, {"glint_sigma", 0.002}, {"I_glints", {20, 20, 20}},
          {"sigmoid_a", 2}, {"sigmoid_b", 1000}};
}
json wavy() { return {{"type", "wavy"}, {"size", 20}, {"tessellation", 128}, {"amplitude", 0.5}, {"wavelength", 3}}; }

json scene(int w, int h, const json& mesh, const json& path) {
  return {{"name", "taa-test"},
          {"resolution", {w, h}},
          {"scene", {{"mesh", mesh}, {"sky", sky()}}},
          {"camera_path", path},
          {"material", sand()},
          {"output", {{"exr", false}, {"png", false}}}};
}

// Static, low over the sand: ridges one behind the other up to the horizon (edges against the sky).
json static_sand() {
  return {{"type", "static"}, {"fps", 30}, {"frames", 64}, {"position", {-4.5, 0.9, -0.5}}, {"target", {3, 0, 1}},
          {"fov", 40}};
}
// A close orbit over glinting sand, 2 degrees a frame.
json close_orbit(int frames) {
  return {{"type", "orbit"}, {"fps", 30}, {"frames", frames}, {"center", {0, 0, 0}}, {"radius", 3.6252},
          {"height", 1.6905}, {"start_deg", 180}, {"end_deg", 180 + 2.0 * (frames - 1)}, {"fov", 40}};
}
// A steady pan: the camera flies over the sand at 1.5 units/s (about 3 px a frame at 96x54).
json pan_path() {
  return {{"type", "flyover"}, {"fps", 30}, {"frames", 16}, {"start", {-2, -1}}, {"direction", {1, 0.3}},
          {"speed", 1.5}, {"height", 1.5}, {"pitch_deg", 35}, {"fov", 40}};
}
// Two shots of the sand, the second from the opposite side: a camera cut at frame 6. `other_first`: the
// first shot from elsewhere (another view of the sand and the sky), the second the same.
constexpr int kCutFrame = 6;
json cut_path(bool other_first) {
  const json a0 = other_first ? json{0.0, 3.0, -3.0} : json{-3.6, 1.7, 0.0};
  const json a1 = other_first ? json{0.4, 3.0, -2.9} : json{-3.5, 1.7, 0.4};
  return {{"type", "keyframes"},
          {"fps", 30},
          {"frames", 10},
          {"interpolation", "linear"},
          {"keyframes",
           {{{"time", 0.0}, {"position", a0}, {"target", {0, 0, 0}}, {"fov", 40}},
            {{"time", 0.1}, {"position", a1}, {"target", {0, 0, 0}}, {"fov", 40}},
            {{"time", 0.2}, {"position", {3.6, 1.2, 0.0}}, {"target", {0, 0, 0}}, {"fov", 30}, {"cut", true}},
            {{"time", 0.4}, {"position", {3.5, 1.2, -0.4}}, {"target", {0, 0, 0}}, {"fov", 30}}}}};
}
// A sand sphere crossing the sky before a static camera, about 1.7 px a frame.
constexpr int kGhostFrames = 24, kGhostAfter = 4;
json ghost_scene() {
  json mesh = {{"type", "sphere"}, {"size", 1.2}, {"tessellation", 32},
               {"motion", {{"type", "translate"}, {"velocity", {3.0, 0.0, 0.0}}}}};
  json path = {{"type", "static"}, {"fps", 30}, {"frames", kGhostFrames}, {"position", {1.2, -1.6, -6.0}},
               {"target", {1.2, 0.0, 0.0}}, {"fov", 30}};
  return scene(96, 54, mesh, path);
}

// The resolve as a variant's "taa" object (without what a false bool switches off: "requires=").
json taa_object(const core::TaaSettings& s, const std::string& jitter) {
  const core::TaaResolveDecl& d = *s.resolve;
  json params = json::object();
  auto off = [&](const std::string& req) { return !req.empty() && !s.on(req); };
  for (size_t i = 0; i < d.parameters.size(); ++i) {
    if (off(d.parameters[i].requires_bool)) continue;
    if (d.parameters[i].is_bool)
      params[d.parameters[i].name] = s.values[i] != 0.0;
    else
      params[d.parameters[i].name] = s.values[i];
  }
  for (size_t i = 0; i < d.options.size(); ++i)
    if (!off(d.options[i].requires_bool)) params[d.options[i].name] = d.options[i].choices[s.choices[i]];
  json t = {{"jitter", jitter}, {"parameters", params}};
  if (d.builtin)
    t["name"] = d.name;
  else
    t["file"] = d.file;
  return t;
}

// ---- rendering a sequence through the resolve, reading back its output and its input

struct Sequence {
  std::vector<Image> out, current;  // taa.color and the surface pass's colour (a = coverage), per frame
};

// The render texel under each output pixel's centre (what an upscaling resolve's "current" is compared
// with below scale 1; at scale 1 the image itself).
Image under_each_pixel(const Image& render, int w, int h) {
  if (render.width == w && render.height == h) return render;
  Image out(w, h, render.channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int rx = std::min(render.width - 1, int((x + 0.5) * render.width / w));
      const int ry = std::min(render.height - 1, int((y + 0.5) * render.height / h));
      for (int c = 0; c < render.channels; ++c) out.at(x, y, c) = render.at(rx, ry, c);
    }
  return out;
}

// Every frame of `e` through the resolve.
Sequence render_sequence(core::VkContext& ctx, json e, const core::TaaSettings& s, double render_scale) {
  e["variants"] = json::array({json{{"name", "resolve"}, {"aa", "taa"}, {"render_scale", render_scale}}});
  const ExperimentSpec spec = ExperimentSpec::from_json(e, "taa-test");
  const VariantSpec& v = spec.variants[0];
  const int rw = v.render_width(spec.width), rh = v.render_height(spec.height);
  const SceneData data = build_scene(spec, metrics::ColorManager());
  core::SceneGpu scene_gpu(ctx, data.mesh, data.env_texture);
  core::FrameGraph graph(ctx, spec.width, spec.height);
  auto taa = std::make_unique<core::TaaPass>(ctx, s);
  core::SurfacePassOptions o;
  o.program = core::sand_program(v.material, data.range, core::ProgramRole::Variant);
  o.single_sample = true;
  o.motion = taa->uses().motion;
  o.glint = taa->uses().glint;
  if (render_scale < 1.0) {  // as build_variant renders a variant below the output resolution
    o.width = rw;
    o.height = rh;
    o.sky_jittered = true;
  }
  graph.add(std::make_unique<core::SurfacePass>(ctx, scene_gpu, o));
  graph.add(std::move(taa));
  graph.build({"taa.color", "color"});
  RenderedFrames frames(spec, data);
  Sequence seq;
  for (int k = 0; k < spec.frames; ++k) {
    core::FrameInputs in = frames.inputs(k, rw, rh);
    const glm::vec2 j = core::jitter_offset(s.jitter, k, render_scale);
    in.samples = core::samples_for(spec.path, k, rw, rh, {j});
    in.jitter_px = j;
    core::FrameResult r = graph.execute(in);
    seq.out.push_back(std::move(r.images.at("taa.color")));
    seq.current.push_back(under_each_pixel(r.images.at("color"), spec.width, spec.height));
  }
  return seq;
}

double luma(const Image& im, int x, int y) {
  return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2);
}

// ---- runs through the experiment runner: the truths, the metrics and their floors are the run's

struct Run {
  json summary;
  std::map<std::string, std::vector<std::map<std::string, double>>> frames;  // variant -> frame -> metric
};

Run run(const json& experiment, const fs::path& dir, const std::string& cache, const std::string& device,
        bool validation) {
  fs::create_directories(dir);
  std::ofstream(dir / "e.json") << experiment.dump(2);
  RunOptions opt;
  opt.experiment = (dir / "e.json").string();
  opt.out_dir = (dir / "out").string();
  opt.cache_dir = cache;
  opt.device = device;
  opt.validation = validation;
  opt.report = false;
  opt.images = false;
  std::ostringstream log;
  const int code = run_experiment(opt, log);
  // 1: NaN, Inf or negative pixels (the figures then say so) or a validation message; anything else is
  // the suite's failure, not the resolve's figure.
  if ((code != kExitOk && code != kExitDefect) || log.str().find("Vulkan validation layer reported") != std::string::npos)
    throw std::runtime_error("taa-test: a run of the suite failed (exit " + std::to_string(code) + "):\n" + log.str());
  Run r;
  std::ifstream in(dir / "out" / "summary.json");
  r.summary = json::parse(in);
  std::ifstream rec(dir / "out" / "records.jsonl");
  for (std::string line; std::getline(rec, line);) {
    const json j = json::parse(line, nullptr, false);
    if (j.is_discarded() || j.value("type", "") != "frame" || !j.contains("name")) continue;
    auto& list = r.frames[j["name"].get<std::string>()];
    const int k = j["frame"].get<int>();
    if (int(list.size()) <= k) list.resize(size_t(k) + 1);
    for (const auto& m : j["metrics"])
      list[size_t(k)][m[0].get<std::string>()] = m[1].is_number() ? m[1].get<double>() : std::nan("");
  }
  return r;
}

double summary_mean(const Run& r, const std::string& variant, const std::string& metric) {
  for (const auto& v : r.summary["variants"])
    if (v["name"] == variant && v["metrics"].contains(metric) && v["metrics"][metric]["mean"].is_number())
      return v["metrics"][metric]["mean"].get<double>();
  return std::nan("");
}

std::string fmt(double v, int prec = 3) {
  std::ostringstream o;
  o << std::setprecision(prec) << v;
  return o.str();
}

ConformanceCheck bounded(const std::string& name, double figure, double bound, const std::string& unit,
                         const std::string& detail) {
  ConformanceCheck c;
  c.name = name;
  c.figure = figure;
  c.bound = bound;
  c.pass = std::isfinite(figure) && figure <= bound;
  c.unit = unit;
  c.detail = detail;
  return c;
}

// ---- the checks on directly rendered sequences

size_t defects(const std::vector<const Sequence*>& seqs, size_t* values) {
  size_t bad = 0;
  *values = 0;
  for (const Sequence* s : seqs)
    for (const Image& im : s->out)
      for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x)
          for (int c = 0; c < 3; ++c) {
            const float v = im.at(x, y, c);
            bad += !(std::isfinite(v) && v >= 0.0f);
            ++*values;
          }
  return bad;
}

size_t differing(const Sequence& a, const Sequence& b) {
  size_t n = 0;
  for (size_t k = 0; k < a.out.size(); ++k)
    for (size_t i = 0; i < a.out[k].data.size(); ++i) {
      const float x = a.out[k].data[i], y = b.out[k].data[i];
      n += !(x == y || (std::isnan(x) && std::isnan(y)));
    }
  return n;
}

// What is left of the sphere kGhostAfter frames after it left a pixel: over the pixels the sphere
// covered in frame k - K and no frame since, sum |L(resolve) - L(current sample)| over
// sum |L(sphere then) - L(sky now)|.
double ghost_share(const Sequence& s) {
  double left = 0.0, contrast = 0.0;
  const int w = s.current[0].width, h = s.current[0].height;
  for (int k = kGhostAfter; k < int(s.out.size()); ++k)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!(s.current[size_t(k - kGhostAfter)].at(x, y, 3) > 0.5f)) continue;
        bool sky = true;
        for (int j = k - kGhostAfter + 1; j <= k; ++j) sky = sky && s.current[size_t(j)].at(x, y, 3) < 0.5f;
        if (!sky) continue;
        left += std::fabs(luma(s.out[size_t(k)], x, y) - luma(s.current[size_t(k)], x, y));
        contrast += std::fabs(luma(s.current[size_t(k - kGhostAfter)], x, y) - luma(s.current[size_t(k)], x, y));
      }
  return contrast > 0.0 ? left / contrast : std::nan("");
}

// The first frame after the cut against the same frame after another first shot, relative to the frame's
// maximum: after a cut nothing of the history may remain, so what came before cannot matter.
double cut_difference(const Sequence& s, const Sequence& other) {
  const Image& out = s.out[kCutFrame];
  const Image& cur = other.out[kCutFrame];
  double worst = 0.0, peak = 0.0;
  for (int y = 0; y < cur.height; ++y)
    for (int x = 0; x < cur.width; ++x)
      for (int c = 0; c < 3; ++c) {
        peak = std::max(peak, double(cur.at(x, y, c)));
        const double d = std::fabs(double(out.at(x, y, c)) - double(cur.at(x, y, c)));
        worst = std::isnan(d) ? INFINITY : std::max(worst, d);
      }
  return peak > 0.0 ? worst / peak : std::nan("");
}

}  // namespace

core::TaaSettings taa_test_settings(const std::string& r, const std::vector<std::string>& overrides) {
  core::TaaSettings s;
  if (const core::TaaResolveDecl* d = core::find_builtin_taa_resolve(r)) {
    s = core::TaaSettings(*d);
  } else if (r.find('/') == std::string::npos && r.find(".glsl") == std::string::npos) {
    throw ConfigError("taa-test: \"" + r + "\" is neither a built-in TAA resolve (" + join(core::taa_resolve_names()) +
                      ") nor a .glsl file");
  } else {
    s = core::TaaSettings(core::taa_resolve_from_file(r));
  }
  for (const auto& kv : overrides) {
    const size_t eq = kv.find('=');
    const std::string k = kv.substr(0, eq), v = eq == std::string::npos ? "" : kv.substr(eq + 1);
    try {
      const core::DeclaredParameter* p = s.resolve->parameter(k);
      if (p && p->is_bool) {
        if (v != "true" && v != "false") throw std::invalid_argument("a bool parameter takes true or false");
        s.set(k, v == "true");
      } else if (p) {
        double x = 0;
        if (!core::parse_finite(v, x)) throw std::invalid_argument("expected a number");
        s.set(k, x);
      } else {
        s.set(k, v);  // an option, or the error naming what the resolve has
      }
    } catch (const std::invalid_argument& e) {
      throw ConfigError("taa-test --parameters " + kv + ": " + e.what());
    }
  }
  return s;
}

ConformanceReport run_taa_test(core::VkContext& ctx, const core::TaaSettings& s, const std::string& work_dir,
                               const std::string& device, double render_scale) {
  const core::TaaResolveDecl& d = *s.resolve;
  ConformanceReport r;
  r.suite = "taa-test";
  r.subject_key = "resolve";
  r.subject = d.name;
  r.file = d.builtin ? core::default_shader_compiler().shader_dir() + "/" + d.file : d.file;
  r.device = ctx.info().name;
  r.parameters = taa_object(s, "halton16")["parameters"];
  if (render_scale < 1.0) r.parameters["render_scale"] = render_scale;
  // Below scale 1 the jitter is FSR 2's count of Halton phases, as a render-scaled variant's default.
  const std::string jitter = render_scale < 1.0 ? "halton_fsr2" : "halton16";
  auto variant = [&](const std::string& name, const std::string& jit) {
    return json{{"name", name}, {"aa", "taa"}, {"render_scale", render_scale}, {"taa", taa_object(s, jit)}};
  };
  const fs::path dir(work_dir);
  // The truths are content-keyed: they are shared between runs of the suite where a disk cache is.
  const std::string spirv = core::default_shader_compiler().cache_dir();
  const std::string cache = spirv == "-" ? (dir / "cache").string() : (fs::path(spirv).parent_path() / "taa-test").string();
  const bool validation = ctx.validation_enabled();

  // finite, deterministic, ghosting, cut: the resolve's frames and their own samples
  core::TaaSettings sj = s;
  sj.jitter = render_scale < 1.0 ? core::JitterSequence::HaltonFsr2 : core::JitterSequence::Halton16;
  const Sequence ghost = render_sequence(ctx, ghost_scene(), sj, render_scale);
  const Sequence ghost2 = render_sequence(ctx, ghost_scene(), sj, render_scale);
  const Sequence cut = render_sequence(ctx, scene(64, 36, wavy(), cut_path(false)), sj, render_scale);
  const Sequence cut_other = render_sequence(ctx, scene(64, 36, wavy(), cut_path(true)), sj, render_scale);
  size_t values = 0;
  const size_t bad = defects({&ghost, &cut}, &values);
  ConformanceCheck finite = bounded("finite", double(bad), 0.0, "NaN, Inf or negative values",
                                    std::to_string(values) + " values of the ghosting and cut sequences");
  ConformanceCheck deterministic = bounded("deterministic", double(differing(ghost, ghost2)), 0.0,
                                           "values that differ between two renders",
                                           "the ghosting sequence, " + std::to_string(kGhostFrames) + " frames");
  ConformanceCheck ghosting =
      bounded("ghosting", ghost_share(ghost), 0.05, "of the sphere's contrast left",
              "a sphere crossing the sky at 1.7 px a frame before a static camera, 96x54, " +
                  std::to_string(kGhostFrames) + " frames; " + std::to_string(kGhostAfter) + " frames after it left a pixel");
  ConformanceCheck cut_check = bounded("cut", cut_difference(cut, cut_other), 1e-4, "of the frame's maximum",
                                       "max difference of the first frame after a camera cut (frame " +
                                           std::to_string(kCutFrame) + " of 10, 64x36) between two sequences whose "
                                           "first shots differ");

  // converges: 64 frames of a static view against 8x8 supersampling, one truth of 32x32 samples
  json conv = scene(64, 36, wavy(), static_sand());
  conv["variants"] = json::array({variant("resolve", "r2")});
  conv["reference"] = {{"grid", 32}};
  conv["metrics"] = {"deltaE2000"};
  const Run conv_run = run(conv, dir / "converges", cache, device, validation);
  json ssaa = conv;
  ssaa["camera_path"]["frames"] = 1;
  ssaa["variants"] = json::array({json{{"name", "ssaa"}, {"aa", "ssaa"}, {"ssaa_grid", 8}}});
  const Run ssaa_run = run(ssaa, dir / "converges-ssaa", cache, device, validation);
  const auto& conv_frames = conv_run.frames.at("resolve");
  const double de_last = conv_frames.empty() ? std::nan("") : conv_frames.back().at("deltaE2000");
  const double de_ssaa = ssaa_run.frames.at("ssaa").at(0).at("deltaE2000");
  ConformanceCheck converges =
      bounded("converges", de_last / de_ssaa, 1.25, "x the CIEDE2000 of 8x8 supersampling",
              "static view of sand ridges to the horizon, 64x36, frame 64 of R2 jitter: CIEDE2000 " + fmt(de_last) + " against " +
                  fmt(de_ssaa) + ", truth 32x32 samples");

  // pan: pooled error at 2 px against one sample per pixel (and 4x4 supersampling), frames 6 on
  json pan = scene(96, 54, wavy(), pan_path());
  pan["variants"] = json::array({variant("resolve", jitter),
                                 json{{"name", "ssaa"}, {"aa", "ssaa"}, {"ssaa_grid", 4}},
                                 json{{"name", "one-sample"}, {"render_scale", render_scale}}});
  pan["reference"] = {{"grid", 16}};
  pan["metrics"] = {"pooled"};
  const Run pan_run = run(pan, dir / "pan", cache, device, validation);
  double pr = 0.0, ps = 0.0, p1 = 0.0;
  const auto& pf = pan_run.frames.at("resolve");
  const auto& sf = pan_run.frames.at("ssaa");
  const auto& of = pan_run.frames.at("one-sample");
  for (size_t k = 6; k < pf.size() && k < sf.size() && k < of.size(); ++k) {
    pr += pf[k].at("pooled_rms_2");
    ps += sf[k].at("pooled_rms_2");
    p1 += of[k].at("pooled_rms_2");
  }
  ConformanceCheck pan_check =
      bounded("pan", pr / p1, 1.25, "x the pooled error of one sample per pixel",
              "a steady pan over sand (about 3 px a frame), 96x54, 16 frames: the RMS of 2x2-pixel luminance "
              "means against a 16x16-sample truth, frames 6-15, where one sample's aliasing mostly averages out "
              "and blur and lag remain: resolve " + fmt(pr / 10) + ", one sample per pixel " + fmt(p1 / 10) +
                  ", 4x4 supersampling " + fmt(ps / 10));

  // flicker: a close orbit over glinting sand, against one sample per pixel, above the truth's floor
  json fl = scene(64, 36, wavy(), close_orbit(16));
  fl["variants"] = json::array({variant("resolve", jitter),
                                json{{"name", "one-sample"}, {"render_scale", render_scale}}});
  fl["reference"] = {{"grid", 8}};
  fl["metrics"] = {"flicker"};
  const Run fl_run = run(fl, dir / "flicker", cache, device, validation);
  const double fe = summary_mean(fl_run, "resolve", "flicker_excess"),
               fe1 = summary_mean(fl_run, "one-sample", "flicker_excess");
  double floor = 0.0;
  for (const auto& ref : fl_run.summary["references"])
    if (ref.contains("floor") && ref["floor"].contains("flicker_excess") && ref["floor"]["flicker_excess"].is_number())
      floor = ref["floor"]["flicker_excess"].get<double>();
  ConformanceCheck flicker =
      bounded("flicker", (fe - floor) / (fe1 - floor), 0.5, "of one sample's flicker excess above the floor",
              "a close orbit over glinting sand (2 degrees a frame), 64x36, 16 frames: flicker excess " + fmt(fe) +
                  " against " + fmt(fe1) + " for one sample per pixel, floor " + fmt(floor) + " (8x8-sample truth)");

  r.checks = {finite, deterministic, converges, ghosting, cut_check, pan_check, flicker};
  for (auto& c : r.checks) apply_declaration(c, d.checks, d.fails);
  return r;
}

void add_taa_test_command(CLI::App& app, int& exit_code) {
  auto scale = std::make_shared<double>(1.0);
  add_conformance_command(
      app, exit_code, "taa-test",
      "the conformance suite of a temporal resolve (built-in name or .glsl file): finite, deterministic, "
      "converges, ghosting, cut, pan, flicker on small scenes (exit 1 if a declared check fails)",
      "resolve", "a built-in TAA resolve (see `list`) or a resolve file",
      [scale](const ConformanceCommandOptions& o) {
        const core::TaaSettings s = taa_test_settings(o.subject, o.parameters);
        core::TaaPass::compile(s);  // a compile error before any work (exit 3)
        const std::string device = o.device;
        const double render_scale = *scale;
        return ConformanceSuite([s, device, render_scale](core::VkContext& ctx) {
          std::string tmpl = (fs::temp_directory_path() / "glintlab-taa-test-XXXXXX").string();
          if (!mkdtemp(tmpl.data()))
            throw IoError("taa-test: cannot create a temporary folder in " + fs::temp_directory_path().string());
          struct Remove {
            std::string dir;
            ~Remove() {
              std::error_code ec;
              fs::remove_all(dir, ec);
            }
          } remove{tmpl};
          return run_taa_test(ctx, s, tmpl, device, render_scale);
        });
      },
      [scale](CLI::App& c) {
        c.add_option("--render-scale", *scale,
                     "render every scene at this scale of its output resolution and resolve it up (temporal "
                     "upscaling; FSR 2's modes are 0.667, 0.588, 0.5, 0.333)")
            ->check(CLI::Range(0.25, 1.0));
      });
}

}  // namespace glintlab
