// Stress cases of the TAA resolve (core::TaaPass, shaders/passes/taa.frag) in
// a frame graph whose surface pass runs shaders/tests/taa_stress.frag: the
// colour and the motion vectors the resolve reads are set per frame, so the
// history can be filled with huge values, the motion can point off-screen or
// be NaN, the colour target can be RGBA16F, the image 1x1 or 4096x16.
//
// Checked in every frame: no output pixel NaN, infinite or negative; the
// output within the range of the inputs, out <= K max(current frame, last
// output) per channel (K = 2.5: the corners of a YCoCg box of colours in
// [0, M] reach 2.41 M in rgb; 1.25 for rgb boxes and Catmull-Rom's lobes);
// where a case says so, the history is rectified: out <= 2.5 x the 3x3
// neighbourhood's largest current value; where a case says so (grey inputs),
// no output is darker than the darkest input, out >= min(current frame, last
// output) (the history is a convex combination of last outputs and a
// rectification box never excludes the current colours' mean, so only
// filter ringing can break it). Three configurations (rgb, centre velocity,
// fixed feedback, no HDR mapping; bilinear history with clamp none or
// variance, Catmull-Rom history with clamp none) are compared with an fp64
// model of the resolve: out = (1 - alpha) h + alpha current where the history
// is valid (not the first frame, on screen, the surface the history holds (the
// disocclusion test of taa/falcor.glsl, modelled in fp64),
// finite), else current; h = the bilinear or Catmull-Rom (4x4 texels,
// negative results to 0) resample of the last output at p + 1/2 - v, clamped
// to mean +- gamma sigma of the 3x3 current colours for the variance
// configuration.
#include "core/render/surface_pass.h"
#include "core/render/taa_pass.h"
#include "core/util/image.h"
#include "experiments/stress/render_util.h"
#include "experiments/stress/stress_internal.h"

#include <cmath>
#include <cstring>
#include <limits>

namespace glintlab::stress {

namespace {

struct TaaFrame {
  glm::vec3 C{1.0f};      // colour scale
  float pattern = 1;      // 0 constant, 1 hash, 2 sparse bright, 3 flat with a small spread (taa_stress.frag)
  float bright_p = 0.1f;  // pattern 2: share of pixels at C (the others C / 64); 3: the relative spread
  bool set_motion = true;  // false: the true (zero) motion and distances of the static plane
  glm::vec2 motion{0.0f};
  float distance = 3.0f;  // set_motion: the surface's distance now and last frame (a change is a disocclusion)
};

struct Config {
  std::string label;
  core::TaaSettings s;
  bool fp64 = false;   // the configuration the fp64 model covers
  bool local = false;  // rectified: out <= 2.5 x the 3x3 current maximum
  bool floor = false;  // no ringing: out >= min(current frame, last output)
};

Config simple_config() {
  Config c;
  c.label = "no-clamp";
  c.s.set("clamp", "none");
  c.s.set("space", "rgb");
  c.s.set("history_filter", "bilinear");
  c.s.set("velocity", "center");
  c.s.set("feedback", "fixed");
  c.s.set("hdr", "none");
  c.s.set("disocclusion", true);
  c.fp64 = true;
  return c;
}
// The same with Falcor's Catmull-Rom history.
Config catmull_rom_config() {
  Config c = simple_config();
  c.label = "no-clamp-catmull-rom";
  c.s.set("history_filter", "catmull_rom");
  return c;
}
// The same with the variance clamp (mean +- gamma sigma over 3x3, in rgb).
Config variance_rgb_config() {
  Config c = simple_config();
  c.label = "variance-rgb";
  c.s.set("clamp", "variance");
  c.local = true;
  return c;
}
Config falcor_config() {
  Config c;
  c.label = "falcor";
  c.local = true;
  return c;
}
Config with(std::string label, bool local, const std::function<void(core::TaaSettings&)>& f) {
  Config c;
  c.label = std::move(label);
  c.local = local;
  f(c.s);
  return c;
}

// The glint-aware options (shaders/taa/falcor.glsl), each on Falcor's defaults: the glint layer of
// taa_stress.frag is its pattern-2 bright pixels. Rectified (out <= 2.5 x the 3x3 current maximum)
// where every history is clamped: the schedule and the layer with its own min/max box; the reactive
// mask, the locks and the unclamped layer keep unrectified history by design.
std::vector<Config> glint_configs() {
  std::vector<Config> c;
  c.push_back(with("accumulate", true, [](core::TaaSettings& s) { s.set("accumulate", true); }));
  c.push_back(with("glint-layer-minmax", true, [](core::TaaSettings& s) {
    s.set("glint_layer", true);
    s.set("glint_clamp", "minmax");
    s.set("dering", true);
  }));
  c.push_back(with("glint-layer-none-accumulate", false, [](core::TaaSettings& s) {
    s.set("glint_layer", true);
    s.set("accumulate", true);
  }));
  c.push_back(with("reactive", false, [](core::TaaSettings& s) { s.set("reactive", 0.5); }));
  c.push_back(with("glint-lock", false, [](core::TaaSettings& s) { s.set("glint_lock", true); }));
  return c;
}
std::vector<Config> plus_glint_configs(std::vector<Config> c) {
  for (Config& g : glint_configs()) c.push_back(std::move(g));
  return c;
}

struct TaaCaseSpec {
  std::string name;
  bool fast;
  std::vector<Config> configs;
  std::vector<TaaFrame> frames;
  int width = 32, height = 18;
  VkFormat color_format = VK_FORMAT_R32G32B32A32_SFLOAT;
  std::string what;
};

// The fp64 model of the unrectified resolve at pixel (x, y), channel c: `prev`
// the last output, `prev_motion` last frame's motion target (its z is the
// distance the history keeps), `tol` the disocclusion tolerance, `gamma` > 0:
// the variance clamp in rgb (0: none); `catmull_rom` the history filter
// (else bilinear).
double model_pixel(const Image& cur, const Image* prev, const Image& motion, const Image* prev_motion, float alpha,
                   double tol, double gamma, bool catmull_rom, int x, int y, int c) {
  const int W = cur.width, H = cur.height;
  double current = std::max(0.0f, cur.at(x, y, c));
  if (!prev) return current;
  // q in fp32 as the shader forms it
  float vx = motion.at(x, y, 0), vy = motion.at(x, y, 1);
  float qx = float(x) + 0.5f - vx, qy = float(y) + 0.5f - vy;
  if (!(std::isfinite(qx) && std::isfinite(qy) && qx >= 0 && qy >= 0 && qx <= float(W) && qy <= float(H)))
    return current;
  float px = qx - 0.5f, py = qy - 0.5f;
  float fx0 = std::floor(px), fy0 = std::floor(py);
  double fx = double(px - fx0), fy = double(py - fy0);
  int ix = int(fx0), iy = int(fy0);
  auto tap = [&](const Image& img, int i, int j, int ch) {
    i = std::min(std::max(i, 0), W - 1);
    j = std::min(std::max(j, 0), H - 1);
    return double(img.at(i, j, ch));
  };
  auto at = [&](int i, int j) { return tap(*prev, i, j, c); };
  // disocclusion (taa/falcor.glsl, same_surface; the stress frames have no jitter): the nearest
  // surface of the 3x3 now; last frame's nearest of each 3x3 (what the history keeps) at the bilinear
  // taps of weight > 0 around that surface's reprojected position; its previous distance within their
  // range widened by tol (a tap of sky leaves the range open above; no surface now needs a tap of sky)
  auto nearest = [&](const Image& m, int cx, int cy) {  // {x, y} of the nearest surface, or {-1, -1}
    int bx = -1, by = -1;
    double best = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int i = std::min(std::max(cx + dx, 0), W - 1), j = std::min(std::max(cy + dy, 0), H - 1);
        const double z = m.at(i, j, 2);
        if (z > 0 && (bx < 0 || z < best || (z == best && dx == 0 && dy == 0))) bx = i, by = j, best = z;
      }
    return std::pair{bx, by};
  };
  const auto [nx, ny] = nearest(motion, x, y);
  const float ux = float(x) + 0.5f - (nx < 0 ? 0.0f : motion.at(nx, ny, 0)),
              uy = float(y) + 0.5f - (nx < 0 ? 0.0f : motion.at(nx, ny, 1));
  bool valid = ux >= -1.0f && uy >= -1.0f && ux <= float(W) + 1 && uy <= float(H) + 1;
  if (valid) {
    const float cx = std::min(std::max(ux, 0.5f), float(W) - 0.5f) - 0.5f,
                cy = std::min(std::max(uy, 0.5f), float(H) - 0.5f) - 0.5f;
    const int tx = int(std::floor(cx)), ty = int(std::floor(cy));
    const bool fx_pos = cx - std::floor(cx) > 0.0f, fy_pos = cy - std::floor(cy) > 0.0f;
    double lo = std::numeric_limits<double>::infinity(), hi = 0;
    bool sky = false;
    for (int j = 0; j <= int(fy_pos); ++j)
      for (int i = 0; i <= int(fx_pos); ++i) {
        const auto [hx, hy] = nearest(*prev_motion, std::min(tx + i, W - 1), std::min(ty + j, H - 1));
        const double held = hx < 0 ? 0.0 : double(prev_motion->at(hx, hy, 2));
        if (held > 0) lo = std::min(lo, held), hi = std::max(hi, held);
        else sky = true;
      }
    if (nx < 0) {
      valid = sky;
    } else {
      const double w = motion.at(nx, ny, 3);
      valid = w > 0 && w >= lo - tol * w && (sky || w <= hi + tol * w);
    }
  }
  if (!valid) return current;
  auto mix = [](double a, double b, double t) { return a * (1 - t) + b * t; };
  double h = mix(mix(at(ix, iy), at(ix + 1, iy), fx), mix(at(ix, iy + 1), at(ix + 1, iy + 1), fx), fy);
  if (catmull_rom) {  // the cubic convolution kernel with a = -1/2 at the four texels per axis
    auto weights = [](double t, double w[4]) {
      w[0] = t * (-0.5 + t * (1.0 - 0.5 * t));
      w[1] = 1.0 + t * t * (-2.5 + 1.5 * t);
      w[2] = t * (0.5 + t * (2.0 - 1.5 * t));
      w[3] = t * t * (-0.5 + 0.5 * t);
    };
    double wx[4], wy[4];
    weights(fx, wx);
    weights(fy, wy);
    h = 0;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) h += wx[i] * wy[j] * at(ix - 1 + i, iy - 1 + j);
  }
  if (!std::isfinite(h)) return current;
  h = std::max(h, 0.0);
  if (gamma > 0) {  // variance clamp in rgb: mean +- gamma sigma of the 3x3 current colours
    double m1 = 0, m2 = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) m1 += std::max(0.0, tap(cur, x + dx, y + dy, c));
    const double mean = m1 / 9;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) m2 += std::pow(std::max(0.0, tap(cur, x + dx, y + dy, c)) - mean, 2);
    const double sigma = std::sqrt(m2 / 9);
    h = std::min(std::max(h, mean - gamma * sigma), mean + gamma * sigma);
  }
  return std::max(0.0, mix(h, current, alpha));
}

StressCaseResult run_taa_case(Env& env, const TaaCaseSpec& spec) {
  const int W = spec.width, H = spec.height;
  auto mesh = std::make_shared<const core::Mesh>(plane_mesh(40, 2));
  core::SceneGpu scene(env.ctx, *mesh, constant_env(0.0f));
  core::CameraState cam;
  cam.position = {0.0f, 3.0f, 0.0f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.up = {0.0f, 0.0f, -1.0f};
  cam.fov_y_deg = 60;
  cam.near = 0.1f;
  cam.far = 10;
  ValueScan scan;
  ErrorStat err;
  double range_ratio = 0, local_ratio = 0, floor_ratio = std::numeric_limits<double>::infinity();
  size_t range_violations = 0, local_violations = 0, floor_violations = 0, fp64_compared_frames = 0;
  std::string notes;
  for (const Config& cfg : spec.configs) {
    core::FrameGraph g(env.ctx, W, H);
    core::SurfacePassOptions o;
    o.program.fragment = "tests/taa_stress.frag";
    o.sky = false;
    o.motion = true;
    o.color_format = spec.color_format;
    o.glint = cfg.s.uses().glint;
    g.add(std::make_unique<core::SurfacePass>(env.ctx, scene, o));
    g.add(std::make_unique<core::TaaPass>(env.ctx, cfg.s));
    g.build({"taa.color", "color", "motion"});
    Image prev, prev_motion;
    bool have_prev = false;
    for (size_t k = 0; k < spec.frames.size(); ++k) {
      const TaaFrame& f = spec.frames[k];
      core::FrameInputs in;
      in.frame = int(k);
      Lighting light;
      light.sun_L = f.C;
      in.uniforms = frame_uniforms(cam, W, H, light);
      in.uniforms.sun_dir = glm::vec4(f.pattern, f.bright_p, float(k + 1), 0.0f);
      in.uniforms.env_sh[0] = glm::vec4(f.motion, f.set_motion ? 1.0f : 0.0f, f.distance);
      in.samples = samples(cam, W, H);
      core::FrameResult r = g.execute(in);
      const Image& out = r.images.at("taa.color");
      const Image& cur = r.images.at("color");
      const Image& mot = r.images.at("motion");
      PixelScan ps = scan_image(out);
      scan.nonfinite += ps.nonfinite;
      scan.negative += ps.negative;
      scan.items += ps.pixels;
      if (ps.nonfinite || ps.negative)
        notes += "; " + cfg.label + " frame " + std::to_string(k) + ": " + std::to_string(ps.nonfinite) +
                 " non-finite, " + std::to_string(ps.negative) + " negative";
      // range of the inputs: this frame's colour and the history (last output)
      double M = scan_image(cur).max_value;
      if (have_prev) M = std::max(M, scan_image(prev).max_value);
      double m_in = std::numeric_limits<double>::infinity();  // the darkest input value
      if (cfg.floor)
        for (const Image* img : {&cur, have_prev ? &prev : &cur})
            for (int y = 0; y < H; ++y)
              for (int x = 0; x < W; ++x)
                for (int c = 0; c < 3; ++c) m_in = std::min(m_in, double(img->at(x, y, c)));
      const double K = 2.5;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          for (int c = 0; c < 3; ++c) {
            double v = out.at(x, y, c);
            if (!std::isfinite(v)) continue;
            if (M > 0) range_ratio = std::max(range_ratio, v / M);
            range_violations += !(v <= K * M * (1 + 1e-6));
            if (cfg.floor && m_in > 0) {
              floor_ratio = std::min(floor_ratio, v / m_in);
              floor_violations += !(v >= m_in * (1 - 1e-5));
            }
            if (cfg.local && have_prev) {
              double m3 = 0;
              for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                  int xx = std::min(std::max(x + dx, 0), W - 1), yy = std::min(std::max(y + dy, 0), H - 1);
                  for (int cc = 0; cc < 3; ++cc) m3 = std::max(m3, double(cur.at(xx, yy, cc)));
                }
              if (m3 > 0) local_ratio = std::max(local_ratio, v / m3);
              local_violations += !(v <= K * m3 * (1 + 1e-6));
            }
            if (cfg.fp64) {
              double want = model_pixel(cur, have_prev ? &prev : nullptr, mot, have_prev ? &prev_motion : nullptr,
                                        float(cfg.s.value("alpha")), cfg.s.value("disocclusion_tolerance"),
                                        cfg.s.option("clamp") == "variance" ? cfg.s.value("gamma") : 0.0,
                                        cfg.s.option("history_filter") == "catmull_rom", x, y, c);
              err.add(v, want, 1e-30, cfg.label + " frame " + std::to_string(k) + " (" + std::to_string(x) + ", " +
                                          std::to_string(y) + ")");
            }
          }
      fp64_compared_frames += cfg.fp64;
      prev = out;
      prev_motion = mot;
      have_prev = true;
    }
  }
  bool ok = range_violations == 0 && local_violations == 0 && floor_violations == 0;
  std::string configs;
  for (const Config& c : spec.configs) configs += (configs.empty() ? "" : ", ") + c.label;
  std::string detail = spec.what + "; configurations " + configs + "; " + std::to_string(spec.frames.size()) +
                       " frames each; out / max(input) max " + fmt(range_ratio) + " (bound 2.5, " +
                       std::to_string(range_violations) + " above)";
  if (local_ratio > 0 || local_violations)
    detail += "; rectified configurations: out / max(3x3 current) max " + fmt(local_ratio) + " (bound 2.5, " +
              std::to_string(local_violations) + " above)";
  if (std::isfinite(floor_ratio) || floor_violations)
    detail += "; no ringing: out / min(input) min " + fmt(floor_ratio) + " (bound 1 - 1e-5, " +
              std::to_string(floor_violations) + " below)";
  if (err.compared) detail += "; fp64 model of the resolve (no-clamp, variance-rgb), floor 1e-30: worst " + err.worst;
  detail += notes;
  StressCaseResult res = make_result(spec.name, "taa", scan, err.compared ? &err : nullptr,
                                     err.compared ? std::optional<double>(1e-5) : std::nullopt, ok, detail);
  res.extra["range_ratio"] = range_ratio;
  res.extra["range_bound"] = 2.5;
  if (local_ratio > 0) res.extra["local_ratio"] = local_ratio;
  if (std::isfinite(floor_ratio)) res.extra["floor_ratio"] = floor_ratio;
  return res;
}

std::vector<TaaFrame> huge_then_normal(float huge, int normal_frames) {
  std::vector<TaaFrame> f;
  f.push_back({glm::vec3(huge), 1});
  for (int k = 0; k < normal_frames; ++k) f.push_back({glm::vec3(1.0f), 1});
  return f;
}

}  // namespace

void add_taa_cases(std::vector<Case>& cases) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  Config minmax = with("minmax-rgb-catmull", true, [](core::TaaSettings& s) {
    s.set("clamp", "minmax");
    s.set("space", "rgb");
  });
  Config clip = with("clip-ycocg", true, [](core::TaaSettings& s) { s.set("clamp", "clip"); });
  Config tonemap = with("variance-tonemap", true, [](core::TaaSettings& s) { s.set("hdr", "tonemap"); });
  Config inv_luma = with("variance-inverse-luma-luma-feedback", true, [](core::TaaSettings& s) {
    s.set("hdr", "inverse_luma");
    s.set("feedback", "luma");
  });
  Config flicker = with("anti-flicker", false, [](core::TaaSettings& s) { s.set("anti_flicker", true); });
  Config closest = with("closest-depth-none-clamp", false, [](core::TaaSettings& s) {
    s.set("velocity", "closest_depth");
    s.set("clamp", "none");
  });
  std::vector<TaaCaseSpec> specs;
  specs.push_back({"taa.huge-history.falcor", true, {falcor_config()}, huge_then_normal(1e30f, 4), 32, 18,
                   VK_FORMAT_R32G32B32A32_SFLOAT,
                   "frame 0 at 1e30 (a history full of huge values), then 4 frames at 1; Falcor's defaults (variance "
                   "clamp in YCoCg, Catmull-Rom, Karis feedback)"});
  specs.push_back({"taa.huge-history.no-clamp", true, {simple_config()}, huge_then_normal(1e30f, 4), 32, 18,
                   VK_FORMAT_R32G32B32A32_SFLOAT,
                   "frame 0 at 1e30, then 4 frames at 1, no rectification: the history decays as 0.9^k 1e30 (within "
                   "the range of its inputs)"});
  specs.push_back({"taa.huge-history.every-clamp-and-hdr", false, plus_glint_configs({minmax, clip, tonemap, inv_luma, closest}),
                   huge_then_normal(1e30f, 3), 32, 18, VK_FORMAT_R32G32B32A32_SFLOAT,
                   "frame 0 at 1e30, then 3 at 1: min/max (rgb), clip (YCoCg), variance with the FSR2 tonemap and with "
                   "Karis' inverse luma and luma feedback, closest-depth velocity without clamp"});
  specs.push_back({"taa.huge-history.anti-flicker", false, {flicker},
                   {{glm::vec3(1e30f), 1}, {glm::vec3(1.0f), 1}, {glm::vec3(1e30f), 1}, {glm::vec3(1.0f), 1},
                    {glm::vec3(1e30f), 1}, {glm::vec3(1.0f), 1}},
                   32, 18, VK_FORMAT_R32G32B32A32_SFLOAT,
                   "frames alternating 1e30 and 1 (the luma oscillation the anti-flicker guard keeps unrectified "
                   "history for)"});
  specs.push_back({"taa.fp32-max-history", true, {falcor_config(), simple_config(), variance_rgb_config()},
                   {{glm::vec3(3e38f), 0}, {glm::vec3(1.0f), 1}, {glm::vec3(3e38f), 1}, {glm::vec3(1.0f), 1}}, 32, 18,
                   VK_FORMAT_R32G32B32A32_SFLOAT,
                   "frames at 3e38 (fp32's largest values: 9-tap sums and squares overflow) and 1 in turn"});
  specs.push_back({"taa.huge-current", true, plus_glint_configs({falcor_config(), simple_config(), variance_rgb_config(), tonemap}),
                   {{glm::vec3(1.0f), 1}, {glm::vec3(1.0f), 1}, {glm::vec3(1e20f), 2, 0.1f}, {glm::vec3(1.0f), 1},
                    {glm::vec3(1e20f), 2, 0.5f}},
                   32, 18, VK_FORMAT_R32G32B32A32_SFLOAT,
                   "a valid history of 1, then sparse bright pixels of 1e20 (their squares overflow fp32 in the "
                   "neighbourhood variance)"});
  {
    // flat regions: the one-pass variance m2 / 9 - mean^2 cancels (fp32: sigma ~ 2.4e-4 mean of noise)
    std::vector<TaaFrame> f;
    for (int k = 0; k < 6; ++k) f.push_back({glm::vec3(1.0f + 1e-3f * float(k)), 3, k % 2 ? 1e-5f : 0.0f});
    for (int k = 0; k < 4; ++k) f.push_back({glm::vec3(1e4f * (1.0f + 1e-3f * float(k))), 3, 1e-4f});
    specs.push_back({"taa.variance-flat-regions", true, {variance_rgb_config(), falcor_config()}, f, 32, 18,
                     VK_FORMAT_R32G32B32A32_SFLOAT,
                     "flat colours (relative spread 0, 1e-5, 1e-4) brightening by 1e-3 per frame: the variance box is "
                     "narrower than fp32's cancellation in m2/9 - mean^2"});
  }
  {
    std::vector<TaaFrame> f;
    const glm::vec2 mv[] = {{0, 0}, {1e6f, -1e6f}, {-1e30f, 5}, {32.5f, 0}, {-32, 0}, {0.5f, 18.5f}, {3, -2}};
    for (const glm::vec2& m : mv) f.push_back({glm::vec3(1.0f), 1, 0.1f, true, m});
    specs.push_back({"taa.motion-offscreen", true, plus_glint_configs({simple_config(), catmull_rom_config(), falcor_config()}), f, 32, 18,
                     VK_FORMAT_R32G32B32A32_SFLOAT,
                     "every pixel's motion vector (1e6, -1e6), (-1e30, 5), (32.5, 0), (-32, 0), (0.5, 18.5), (3, -2): "
                     "off-screen, at the edges, partly on screen"});
  }
  {
    std::vector<TaaFrame> f;
    const glm::vec2 mv[] = {{0, 0}, {nan, 0}, {inf, 0}, {-inf, nan}, {0, 0}, {nan, nan}, {0.25f, -0.75f}};
    for (const glm::vec2& m : mv) f.push_back({glm::vec3(1.0f), 1, 0.1f, true, m});
    specs.push_back({"taa.motion-nonfinite", true, plus_glint_configs({simple_config(), falcor_config(), closest}), f, 32, 18,
                     VK_FORMAT_R32G32B32A32_SFLOAT, "motion vectors NaN, +inf, -inf in the motion target"});
  }
  {
    std::vector<TaaFrame> f;
    const glm::vec2 mv[] = {{0, 0}, {0.5f, 0.5f}, {-0.49999f, 0}, {0.3f, -0.7f}, {31.999f, 17.999f}, {-0.001f, 0.001f}};
    for (const glm::vec2& m : mv) f.push_back({glm::vec3(1.0f), 1, 0.1f, true, m});
    specs.push_back({"taa.motion-subpixel-and-edges", true, plus_glint_configs({simple_config(), catmull_rom_config()}), f, 32, 18,
                     VK_FORMAT_R32G32B32A32_SFLOAT,
                     "fractional motion (bilinear and Catmull-Rom history) and motion landing within 1e-3 of the "
                     "image edges"});
  }
  {
    // Every pixel disoccluded at once: the distance the history keeps (last frame's) differs from the
    // one the current frame reports for its previous position (3 -> 6 and back: beyond the
    // tolerance), over sparse glints with fractional motion; the history restarts there.
    std::vector<TaaFrame> f;
    const float dist[] = {3, 3, 6, 6, 3, 3};
    for (float d : dist) f.push_back({glm::vec3(64.0f), 2, 0.04f, true, {0.37f, -0.61f}, d});
    Config falcor_tested = falcor_config();
    falcor_tested.label = "falcor-disocclusion";
    falcor_tested.s.set("disocclusion", true);
    specs.push_back({"taa.disocclusion", true, plus_glint_configs({simple_config(), falcor_config(), falcor_tested}),
                     f, 32, 18,
                     VK_FORMAT_R32G32B32A32_SFLOAT,
                     "sparse glints (4 % at 64) moving (0.37, -0.61) a frame, every pixel disoccluded twice (the "
                     "distance kept with the history 3, the current frame's previous distance 6, and back)"});
  }
  specs.push_back({"taa.rgba16f-color", true, {falcor_config(), simple_config()},
                   {{glm::vec3(6e4f), 1}, {glm::vec3(1e6f), 2, 0.1f}, {glm::vec3(1.0f), 1}, {glm::vec3(1e6f), 0}}, 32,
                   18, VK_FORMAT_R16G16B16A16_SFLOAT,
                   "an RGBA16F colour target (values 6e4 and 1e6: beyond half's 65504) resolved by TAA"});
  {
    std::vector<TaaFrame> f = huge_then_normal(1e30f, 2);
    f.push_back({glm::vec3(1.0f), 1, 0.1f, true, {0.4f, 0.0f}});
    f.push_back({glm::vec3(1.0f), 1, 0.1f, true, {1.0f, 1.0f}});
    specs.push_back({"taa.resolution-1x1", true, {falcor_config(), simple_config()}, f, 1, 1,
                     VK_FORMAT_R32G32B32A32_SFLOAT,
                     "a 1x1 image (every tap clamps to the one texel), huge history, motion 0.4 and 1 pixel"});
    specs.push_back({"taa.resolution-4096x16", false, {falcor_config(), simple_config()}, f, 4096, 16,
                     VK_FORMAT_R32G32B32A32_SFLOAT, "a 4096x16 image, huge history, motion 0.4 and 1 pixel"});
  }
  {
    // Sparse glints 64x brighter than the sand around them, a new pattern every
    // frame, fractional motion: the Catmull-Rom history's negative lobes ring
    // beside each glint of the last output (to 0, where it is floored), and a
    // glinting neighbourhood's variance box is too wide to lift it. Deringing
    // keeps the history within its 2x2 texels.
    std::vector<TaaFrame> f;
    for (int k = 0; k < 6; ++k) f.push_back({glm::vec3(64.0f), 2, 0.04f, true, {0.37f, -0.61f}});
    Config dflt = with("falcor-dering", true, [](core::TaaSettings& s) { s.set("dering", true); });
    dflt.floor = true;
    Config ycocg_clip = with("clip-ycocg-catmull-dering", true, [](core::TaaSettings& s) {
      s.set("clamp", "clip");
      s.set("dering", true);
    });
    ycocg_clip.floor = true;
    Config bilinear = with("bilinear", true,
                           [](core::TaaSettings& s) { s.set("history_filter", "bilinear"); });
    bilinear.floor = true;
    specs.push_back({"taa.sparse-glints-no-ringing", true, plus_glint_configs({dflt, ycocg_clip, bilinear}), f, 32, 18,
                     VK_FORMAT_R32G32B32A32_SFLOAT,
                     "grey sand at 1 with 4 % glints at 64, a new pattern each frame, motion (0.37, -0.61): no output "
                     "darker than the darkest input"});
  }
  for (auto& s : specs) cases.push_back({s.name, "taa", s.fast, [s](Env& env) { return run_taa_case(env, s); }});
}

}  // namespace glintlab::stress
