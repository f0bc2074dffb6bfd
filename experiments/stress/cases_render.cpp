// Stress cases of the renderer: the sand material (passes/sand.frag) through
// core::SurfaceRenderer, or through build_variant's frame graph (none, ssaa,
// taa) and build_reference, at small resolutions, with hostile cameras,
// lights, parameters, target formats and sizes. Every pixel of every frame is
// scanned: none may be NaN, infinite or negative (rgb and alpha). There is no
// fp64 image to compare with (max_rel_error null); the energy case bounds the
// filtered glints against their beckmann limit over the image.
//
// A case is a row (RenderRow): models, a mesh and a list of settings, each a
// label and a change to the default shot; shots_of makes a shot per setting
// and model, run_render_case renders and scans them.
#include "core/material/program.h"
#include "core/render/surface_pass.h"
#include "core/util/image.h"
#include "experiments/sources/variant_factory.h"
#include "experiments/stress/render_util.h"
#include "experiments/stress/stress_internal.h"

#include <glm/gtc/matrix_transform.hpp>

namespace glintlab::stress {

namespace {

struct Shot {
  std::string label;
  core::SandParams params;
  core::SandFeatures features;  // {0, inf}: every field compiled in
  std::shared_ptr<const core::Mesh> mesh;
  glm::mat4 model{1.0f};
  core::CameraState cam;
  int width = 32, height = 18;
  Lighting light;
  VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT;
  bool sky = true;
  // through build_variant (aa and frames) instead of a bare SurfaceRenderer
  bool variant = false;
  AaMethod aa = AaMethod::None;
  int ssaa_grid = 1, frames = 1;
  bool reference = false;  // build_reference with grid `ssaa_grid`
};

struct ShotResult {
  PixelScan scan;
  std::vector<Image> frames;
};

core::SandParams sand(const std::string& model) {
  core::SandParams p = core::SandParams::preset("thesis-default");
  p.glint_model = model;
  p.noise_scale = 400;
  p.glint_sigma = 0.01;
  p.I_glints = {20, 20, 20};
  return p;
}

std::shared_ptr<const core::Mesh> plane(float size, int tess = 4) {
  return std::make_shared<const core::Mesh>(plane_mesh(size, tess));
}

ShotResult render_shot(Env& env, const Shot& s) {
  core::SceneGpu scene(env.ctx, *s.mesh, constant_env(s.light.sky.x));
  core::FrameUniforms u = frame_uniforms(s.cam, s.width, s.height, s.light, s.model);
  ShotResult out;
  auto add = [&](const Image& img) {
    PixelScan p = scan_image(img);
    out.scan.nonfinite += p.nonfinite;
    out.scan.negative += p.negative;
    out.scan.pixels += p.pixels;
    out.scan.max_value = std::max(out.scan.max_value, p.max_value);
    out.scan.sum += p.sum;
    out.frames.push_back(img);
  };
  if (s.reference) {
    core::MaterialProgram prog = core::sand_program(s.params, s.features, core::ProgramRole::Reference);
    RenderSetup r = build_reference(env.ctx, scene, s.width, s.height, prog, s.ssaa_grid);
    core::FrameInputs in;
    in.uniforms = u;
    in.samples = samples(s.cam, s.width, s.height,
                         supersampling(s.ssaa_grid, s.width, s.height, kReferencePatternSeed).offsets);
    add(r.graph->execute(in).images.at(r.output));
    return out;
  }
  core::MaterialProgram prog = core::sand_program(s.params, s.features, core::ProgramRole::Variant);
  if (s.variant) {
    VariantSpec v;
    v.name = s.label;
    v.aa = s.aa;
    v.ssaa_grid = s.ssaa_grid;
    v.material = s.params;
    RenderSetup r = build_variant(env.ctx, scene, s.width, s.height, v, prog);
    for (int k = 0; k < s.frames; ++k) {
      core::FrameInputs in;
      in.frame = k;
      in.uniforms = u;
      std::vector<glm::vec2> offsets = variant_offsets(v, k);
      in.samples = samples(s.cam, s.width, s.height, offsets);
      in.jitter_px = offsets.size() == 1 ? offsets[0] : glm::vec2(0.0f);
      add(r.graph->execute(in).images.at(r.output));
    }
    return out;
  }
  core::SurfacePassOptions o;
  o.program = prog;
  o.sky = s.sky;
  o.color_format = s.format;
  core::SurfaceRenderer renderer(env.ctx, scene, s.width, s.height, o);
  add(renderer.render(u, samples(s.cam, s.width, s.height)).images.at("color"));
  return out;
}

// The camera looking along a plane at `deg` degrees from its normal at the image centre.
core::CameraState grazing_camera(double deg, float height) {
  core::CameraState c;
  double t = std::tan(deg * 3.14159265358979 / 180);
  c.position = {0.0f, height, 0.0f};
  c.target = {float(height * t), 0.0f, 0.0f};
  c.fov_y_deg = 20;
  c.near = height * 0.01f;
  c.far = float(height * t * 4 + 10);
  return c;
}

core::CameraState look(glm::vec3 from, glm::vec3 at, float fov = 40, float near = 0.05f, float far = 500) {
  core::CameraState c;
  c.position = from;
  c.target = at;
  c.fov_y_deg = fov;
  c.near = near;
  c.far = far;
  if (std::abs(glm::normalize(at - from).y) > 0.999f) c.up = {0, 0, -1};
  return c;
}

// Every model but "none": kajs and each glint_D model of the registry.
std::vector<std::string> all_models() {
  std::vector<std::string> out;
  for (const auto& n : core::glint_model_names())
    if (n != core::kGlintModelNone) out.push_back(n);
  return out;
}
// The footprint-filtering model (the one whose walk and binomial draws are stressed) and its smooth limit.
const std::string kZirr = "zirr";
std::string zirr_limit() { return core::find_builtin_glint_model(kZirr)->limit; }
const std::vector<std::string> kKajsZirr = {core::kGlintModelKajs, kZirr};

std::string model_name(const std::string& m) { return m; }

// One setting of a render case: what it changes on the shot the row makes.
struct Setting {
  std::string label;                      // after the model's name in the shot's label
  std::function<void(Shot&)> apply;       // empty: the row's shot as it is
  std::optional<std::string> model;  // rendered with this model only (else with each of the row's)
};

// A render case: every setting rendered with each model (in that order: settings, then models). A shot
// starts as sand(model) on the row's mesh, seen by look({0, 3, 3}, {0, 0, 0}); `base`, then the setting
// change it.
struct RenderRow {
  std::string name;
  bool fast;  // part of the --fast subset
  std::vector<std::string> models;  // each setting is rendered with each (unless it names its own)
  std::vector<Setting> settings;
  std::string what;  // what the case stresses (detail)
  std::function<std::shared_ptr<const core::Mesh>()> mesh;  // made once per case (empty: plane(20, 4))
  std::function<void(Shot&)> base;                           // applied to every shot first (empty: none)
};

// One setting per value: label `prefix` + fmt(value) + `suffix`, apply(shot, value).
std::vector<Setting> sweep(const std::string& prefix, const std::vector<double>& values,
                           const std::function<void(Shot&, double)>& apply, const std::string& suffix = "") {
  std::vector<Setting> settings;
  for (double v : values) settings.push_back({prefix + fmt(v) + suffix, [apply, v](Shot& s) { apply(s, v); }});
  return settings;
}

std::vector<Shot> shots_of(const RenderRow& row) {
  auto mesh = row.mesh ? row.mesh() : plane(20, 4);
  std::vector<Shot> shots;
  for (const Setting& set : row.settings)
    for (const std::string& m : set.model ? std::vector<std::string>{*set.model} : row.models) {
      Shot s;
      s.label = model_name(m) + (set.label.empty() ? "" : " " + set.label);
      s.params = sand(m);
      s.mesh = mesh;
      s.cam = look({0, 3, 3}, {0, 0, 0});
      if (row.base) row.base(s);
      if (set.apply) set.apply(s);
      shots.push_back(s);
    }
  return shots;
}

void add_pixels(ValueScan& scan, const PixelScan& p) {
  scan.nonfinite += p.nonfinite;
  scan.negative += p.negative;
  scan.items += p.pixels;
}

StressCaseResult run_render_case(Env& env, const RenderRow& row) {
  ValueScan scan;
  std::string per_shot;
  double max_value = 0;
  for (const Shot& s : shots_of(row)) {
    ShotResult r = render_shot(env, s);
    add_pixels(scan, r.scan);
    max_value = std::max(max_value, r.scan.max_value);
    if (r.scan.nonfinite || r.scan.negative)
      per_shot += "; " + s.label + ": " + std::to_string(r.scan.nonfinite) + " non-finite, " +
                  std::to_string(r.scan.negative) + " negative";
  }
  StressCaseResult res = make_result(row.name, "render", scan, nullptr, std::nullopt, true,
                                     row.what + "; " + std::to_string(scan.items) + " pixels, largest value " +
                                         fmt(max_value) + per_shot);
  res.extra["max_value"] = max_value;
  return res;
}

// R_s = R_t, P and the glint sigma at both ends, the models in turn.
std::vector<Setting> material_extremes() {
  std::vector<Setting> settings;
  int k = 0;
  for (double R : {0.0, 1.0})
    for (double P : {0.0, 1.0})
      for (double sg : {1e-6, 1.0})
        settings.push_back({"R " + fmt(R) + " P " + fmt(P) + " sigma " + fmt(sg),
                            [R, P, sg](Shot& s) {
                              s.params.R_s = R, s.params.R_t = R, s.params.T = 1.0, s.params.P = P;
                              s.params.glint_sigma = sg;
                              s.params.oren_nayar_sigma = R * 1.5707963;
                              s.params.glints.alpha_g = {R == 0 ? 1e-3 : 1.0, R == 0 ? 1e-3 : 1.0};
                              s.params.glints.relative_roughness = {P == 0 ? 1e-3 : 1.0, 1e-3};
                              s.light.sun_dir = {0, 1, -1};
                            },
                            all_models()[k++ % all_models().size()]});
  return settings;
}

std::vector<RenderRow> render_rows() {
  std::vector<RenderRow> rows;
  // grazing views at 80 .. 89.99 deg, one case per model
  for (const std::string& m : all_models())
    rows.push_back({"render.grazing-view." + model_name(m), m == kZirr, {m},
                    sweep("", {80.0, 89.0, 89.9, 89.99},
                          [](Shot& s, double deg) { s.cam = grazing_camera(deg, 1.0f); }, " deg"),
                    model_name(m) + ", a plane seen at 80, 89, 89.9, 89.99 deg from its normal at the image centre "
                                    "(footprints stretched to the horizon)",
                    [] { return plane(4e4f, 4); }});
  rows.push_back({"render.camera-behind-surface", true, kKajsZirr,
                  // under the plane: its back side faces the camera
                  {{"from below", [](Shot& s) { s.cam = look({0.5f, -2, 1}, {0, 0, 0}); }}},
                  "kajs and zirr, the camera under a plane (two-sided: the back face is shaded, sun above it)"});
  rows.push_back({"render.camera-inside-sphere", true, kKajsZirr,
                  {{"at the centre", [](Shot& s) { s.cam = look({0, 0, 0}, {1, 0.2f, 0.3f}, 90, 0.01f, 50); }},
                   {"on the shell", [](Shot& s) { s.cam = look({0, 1.999f, 0}, {1, 1.9f, 0.2f}, 90, 1e-4f, 50); }}},
                  "kajs and zirr inside a sphere of radius 2: at its centre and 1e-3 from its shell (distances down to "
                  "the near plane 1e-4)",
                  [] {
                    core::MeshSpec spec;
                    spec.type = "sphere";
                    spec.size = 4;
                    spec.tessellation = 24;
                    return std::make_shared<const core::Mesh>(core::build_mesh(spec));
                  }});
  rows.push_back({"render.camera-in-plane", false, {kZirr},
                  sweep("eye at y = ", {0.0f, 1e-7f, -1e-7f},
                        [](Shot& s, double y) {
                          s.cam = look({-5, float(y), 0.3f}, {5, float(y), 0}, 40, 1e-4f, 100);
                        }),
                  "zirr, the eye in the plane of the surface and 1e-7 above and below it (edge-on triangles)"});
  rows.push_back({"render.backlit", true, all_models(),
                  {{"",
                    [](Shot& s) {
                      s.params.T = 1.0;
                      s.cam = look({0, 2, 2}, {0, 0, 0});
                      s.light.sun_dir = glm::vec3(0, -2, -2);  // = -w_o at the image centre
                    }}},
                  "every model, the sun exactly opposite the view direction at the image centre, T = 1"});
  rows.push_back({"render.object-coords-1e6", true, kKajsZirr,
                  sweep("noise_scale ", {1.0, 1e6},
                        [](Shot& s, double ns) {
                          s.params.noise_scale = ns;
                          s.model = glm::translate(glm::mat4(1.0f), glm::vec3(-1e6f, 0.0f, 1e6f));
                        }),
                  "kajs and zirr, object coordinates around (1e6, 0, -1e6) moved to the origin by the model matrix, "
                  "noise_scale 1 and 1e6 (cell coordinates 1e12)",
                  [] {
                    core::Mesh m = plane_mesh(10, 4);
                    for (auto& v : m.vertices) v.position += glm::vec3(1e6f, 0.0f, -1e6f);
                    m.bounds_min += glm::vec3(1e6f, 0.0f, -1e6f);
                    m.bounds_max += glm::vec3(1e6f, 0.0f, -1e6f);
                    return std::make_shared<const core::Mesh>(std::move(m));
                  }});
  rows.push_back({"render.far-1e6-sigmoid-a1e3", true, kKajsZirr,
                  {{"",
                    [](Shot& s) {
                      s.params.sigmoid_a = 1e3;
                      s.params.sigmoid_b = 1e6;  // the transition crosses the image
                      s.cam = look({0, 7e5f, 0}, {3e5f, 0, 1e5f}, 40, 1e3f, 1e7f);
                    }}},
                  "kajs and zirr, a plane 0.8 .. 1.5e6 away, sigmoid a = 1e3, b = 1e6 (the close-to-far transition "
                  "crosses the image)",
                  [] { return plane(8e6f, 4); }});
  rows.push_back({"render.footprint-1e-9-to-1e3-cells", true, kKajsZirr,
                  {{"tiny",
                    [](Shot& s) {
                      s.params.noise_scale = 1;
                      s.params.glints.log_density = -3;
                      s.mesh = plane(1, 2);  // the camera 1e-6 above: pixels 1e-9 units wide
                      s.cam = look({0, 1e-6f, 0}, {0, -1, 0}, 1, 1e-7f, 1);
                    }},
                   {"huge",
                    [](Shot& s) {
                      s.params.noise_scale = 30;
                      s.params.glints.log_density = 4;
                      s.mesh = plane(1e4f, 4);  // 1e3 above at 60 deg: pixels ~36 units, 1e3 grain cells
                      s.cam = look({0, 1e3f, 0}, {0, 0, 0}, 60, 1.0f, 1e4f);
                    }}},
                  "kajs and zirr looking straight down from 1e-6 (pixel footprints 1e-9 grain cells, 1e-12 "
                  "microdetail cells) and from 1e3 (1e3 grain cells, 1e5 microdetail cells)"});
  rows.push_back({"render.sun-1e6", true, all_models(),
                  {{"",
                    [](Shot& s) {
                      s.params.I_glints = {1e6, 1e6, 1e6};
                      s.params.glints.intensity = 1e6;
                      s.light.sun_L = glm::vec3(1e6f);
                      s.light.sun_dir = {0, 1, -1};
                    }}},
                  "every model, sun radiance 1e6, I_glints and glint intensity 1e6 (values up to ~1e14 in fp32)"});
  rows.push_back({"render.palette-black-and-white", true, kKajsZirr,
                  {{"black",
                    [](Shot& s) {
                      for (auto& c : s.params.palette) c = {0.0, 0.0, 0.0};
                      s.light.sky = glm::vec3(0.0f);
                    }},
                   {"white", [](Shot& s) { for (auto& c : s.params.palette) c = {1.0, 1.0, 1.0}; }}},
                  "kajs and zirr with every grain colour 0 (and no sky) and 1"});
  rows.push_back({"render.material-extremes", true, {}, material_extremes(),
                  "R_s = R_t in {0, 1}, P in {0, 1}, glint sigma in {1e-6, 1}, T = 1, Oren-Nayar sigma 0 / pi/2, "
                  "glint alpha_g 1e-3 / 1, relative roughness 1e-3 / 1, the models in turn"});
  rows.push_back({"render.rgba16f-target", true, kKajsZirr,
                  sweep("sun ", {6.0f, 1e4f, 1e6f},
                        [](Shot& s, double sun) {
                          s.light.sun_L = glm::vec3(float(sun));
                          s.light.sun_dir = {0, 1, -1};
                          s.format = VK_FORMAT_R16G16B16A16_SFLOAT;
                        }),
                  "kajs and zirr into an RGBA16F colour target, sun 6 and 1e4 (glints up to ~1e5 > half's 65504)"});
  rows.push_back({"render.resolution-1x1", true, all_models(),
                  {{"", {}},
                   {"taa 1x1", [](Shot& s) { s.variant = true, s.aa = AaMethod::Taa, s.frames = 4; },
                    zirr_limit()}},
                  "every model at 1x1 (one pixel: its footprint is the whole view), and TAA at 1x1 over 4 frames", {},
                  [](Shot& s) { s.width = s.height = 1; }});
  rows.push_back({"render.resolution-4096x16", true, kKajsZirr,
                  {{"",
                    [](Shot& s) {
                      s.cam = look({0, 3, 3}, {0, 0, 0}, 2);
                      s.width = 4096, s.height = 16;
                    }}},
                  "kajs and zirr at 4096x16 (aspect 256: pixels 1/16 of the fov tall, extremely wide view)"});
  rows.push_back({"render.zirr-density-1e-3-to-1e12", true, {kZirr},
                  sweep("log_density ", {-3.0, 0.0, 3.0, 6.0, 9.0, 12.0},
                        [](Shot& s, double ld) {
                          s.params.glints.log_density = ld;
                          s.light.sun_dir = {0, 1, -1};
                        }),
                  "zirr at 1e-3, 1, 1e3, 1e6, 1e9, 1e12 microdetails per uv unit (glints.log_density -3 .. 12)"});
  rows.push_back({"render.variants-ssaa-taa-reference", false, kKajsZirr,
                  {{"ssaa 4x4", [](Shot& s) { s.variant = true, s.aa = AaMethod::Ssaa, s.ssaa_grid = 4; }},
                   {"taa", [](Shot& s) { s.variant = true, s.aa = AaMethod::Taa, s.frames = 6; }},
                   {"reference 4x4", [](Shot& s) { s.reference = true, s.ssaa_grid = 4; }}},
                  "build_variant (ssaa 4x4, taa over 6 frames) and build_reference (4x4, supersampled pass) for "
                  "kajs and zirr (grains as its truth) at 89.9 deg",
                  [] { return plane(4e4f, 4); }, [](Shot& s) { s.cam = grazing_camera(89.9, 1.0f); }});
  return rows;
}

// ---- energy over the image: zirr (debug output "glints") vs beckmann, a pair of shots per density
RenderRow energy_row() {
  return {"render.energy-zirr-vs-beckmann", false, {kZirr, zirr_limit()},
          sweep("log_density ", {6.0, 9.0, 12.0}, [](Shot& s, double ld) { s.params.glints.log_density = ld; }),
          "sum over a 64x36 image of a plane (highlight in view) of zirr's glint radiance / beckmann's, densities "
          "1e6, 1e9, 1e12 per uv unit (every pixel covers 10 .. 1e7 microdetails)",
          [] { return plane(20, 8); },
          [](Shot& s) {
            s.params.glints.relative_roughness = {0.5, 0.5};  // pmf at the peak 1/4: many reflecting microdetails
            s.features.debug_output = "glints";
            s.cam = look({0, 3, 3}, {0, 0, 0}, 30);
            s.light.sun_dir = {0, 1, -1};  // the highlight in the image
            s.width = 64, s.height = 36;
            s.sky = false;
          }};
}

StressCaseResult energy_render_case(Env& env) {
  const RenderRow row = energy_row();
  const std::vector<Shot> shots = shots_of(row);
  std::string per;
  double worst = 0, lowest = 1e300;
  ValueScan scan;
  for (size_t i = 0; i + 1 < shots.size(); i += 2) {  // zirr, then beckmann
    double sums[2] = {0, 0};
    for (int m = 0; m < 2; ++m) {
      ShotResult r = render_shot(env, shots[i + m]);
      add_pixels(scan, r.scan);
      sums[m] = r.scan.sum;
    }
    double ratio = sums[1] > 0 ? sums[0] / sums[1] : kInf;
    worst = std::max(worst, ratio);
    lowest = std::min(lowest, ratio);
    per += (per.empty() ? "" : ", ") + std::string("1e") + std::to_string(int(shots[i].params.glints.log_density)) +
           ": " + fmt(ratio);
  }
  const double factor = 1.25;
  StressCaseResult res = make_result(row.name, "render", scan, nullptr, std::nullopt, worst <= factor,
                                     row.what + ": " + per + "; bound <= " + fmt(factor));
  res.extra["energy_ratio"] = worst;
  res.extra["energy_ratio_min"] = lowest;
  res.extra["energy_bound"] = factor;
  return res;
}

}  // namespace

void add_render_cases(std::vector<Case>& cases) {
  for (auto& row : render_rows())
    cases.push_back({row.name, "render", row.fast, [row](Env& env) { return run_render_case(env, row); }});
  const RenderRow energy = energy_row();
  cases.push_back({energy.name, "render", energy.fast, energy_render_case});
}

}  // namespace glintlab::stress
