// Stress cases of the renderer: the sand material (passes/sand.frag) through
// core::SurfaceRenderer, or through build_variant's frame graph (none, ssaa,
// taa) and build_reference, at small resolutions, with hostile cameras,
// lights, parameters, target formats and sizes. Every pixel of every frame is
// scanned: none may be NaN, infinite or negative (rgb and alpha). There is no
// fp64 image to compare with (max_rel_error null); the energy case bounds the
// filtered glints against their beckmann limit over the image.
#include "core/material/program.h"
#include "core/render/surface_pass.h"
#include "core/util/image.h"
#include "experiments/runner/variant_factory.h"
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

core::SandParams sand(core::GlintModel model) {
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

struct RenderCaseSpec {
  std::string name;
  bool fast;
  std::function<std::vector<Shot>()> shots;
  std::string what;
};

StressCaseResult run_render_case(Env& env, const RenderCaseSpec& spec) {
  ValueScan scan;
  std::string per_shot;
  double max_value = 0;
  for (const Shot& s : spec.shots()) {
    ShotResult r = render_shot(env, s);
    scan.nonfinite += r.scan.nonfinite;
    scan.negative += r.scan.negative;
    scan.items += r.scan.pixels;
    max_value = std::max(max_value, r.scan.max_value);
    if (r.scan.nonfinite || r.scan.negative)
      per_shot += "; " + s.label + ": " + std::to_string(r.scan.nonfinite) + " non-finite, " +
                  std::to_string(r.scan.negative) + " negative";
  }
  StressCaseResult res = make_result(spec.name, "render", scan, nullptr, std::nullopt, true,
                                     spec.what + "; " + std::to_string(scan.items) + " pixels, largest value " +
                                         fmt(max_value) + per_shot);
  res.extra["max_value"] = max_value;
  return res;
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

const std::vector<core::GlintModel> kModels = {core::GlintModel::Kajs, core::GlintModel::Grains, core::GlintModel::Zirr,
                                               core::GlintModel::Beckmann};

std::string model_name(core::GlintModel m) { return std::string(enum_name(core::kGlintModelNames, m)); }

// ---- energy over the image: zirr (debug output "glints") vs beckmann
StressCaseResult energy_render_case(Env& env) {
  auto mesh = plane(20, 8);
  std::string per;
  double worst = 0, lowest = 1e300;
  ValueScan scan;
  for (double ld : {6.0, 9.0, 12.0}) {
    double sums[2] = {0, 0};
    for (int m = 0; m < 2; ++m) {
      Shot s;
      s.label = "energy";
      s.params = sand(m == 0 ? core::GlintModel::Zirr : core::GlintModel::Beckmann);
      s.params.glints.log_density = ld;
      s.params.glints.relative_roughness = {0.5, 0.5};  // pmf at the peak 1/4: many reflecting microdetails
      s.features.debug_output = "glints";
      s.mesh = mesh;
      s.cam = look({0, 3, 3}, {0, 0, 0}, 30);
      s.light.sun_dir = {0, 1, -1};  // the highlight in the image
      s.width = 64, s.height = 36;
      s.sky = false;
      ShotResult r = render_shot(env, s);
      scan.nonfinite += r.scan.nonfinite, scan.negative += r.scan.negative, scan.items += r.scan.pixels;
      sums[m] = r.scan.sum;
    }
    double ratio = sums[1] > 0 ? sums[0] / sums[1] : kInf;
    worst = std::max(worst, ratio);
    lowest = std::min(lowest, ratio);
    per += (per.empty() ? "" : ", ") + std::string("1e") + std::to_string(int(ld)) + ": " + fmt(ratio);
  }
  const double factor = 1.25;
  StressCaseResult res = make_result("render.energy-zirr-vs-beckmann", "render", scan, nullptr, std::nullopt,
                                     worst <= factor,
                                     "sum over a 64x36 image of a plane (highlight in view) of zirr's glint radiance / "
                                     "beckmann's, densities 1e6, 1e9, 1e12 per uv unit (every pixel covers 10 .. 1e7 "
                                     "microdetails): " + per + "; bound <= " + fmt(factor));
  res.extra["energy_ratio"] = worst;
  res.extra["energy_ratio_min"] = lowest;
  res.extra["energy_bound"] = factor;
  return res;
}

}  // namespace

void add_render_cases(std::vector<Case>& cases) {
  std::vector<RenderCaseSpec> specs;
  // grazing views at 80 .. 89.99 deg, one case per model
  for (core::GlintModel m : kModels)
    specs.push_back({"render.grazing-view." + model_name(m), m == core::GlintModel::Zirr,
                     [m] {
                       std::vector<Shot> shots;
                       auto mesh = plane(4e4f, 4);
                       for (double deg : {80.0, 89.0, 89.9, 89.99}) {
                         Shot s;
                         s.label = fmt(deg) + " deg";
                         s.params = sand(m);
                         s.mesh = mesh;
                         s.cam = grazing_camera(deg, 1.0f);
                         shots.push_back(s);
                       }
                       return shots;
                     },
                     model_name(m) + ", a plane seen at 80, 89, 89.9, 89.99 deg from its normal at the image centre "
                                     "(footprints stretched to the horizon)"});
  specs.push_back({"render.camera-behind-surface", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (core::GlintModel m : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       Shot s;
                       s.label = model_name(m) + " from below";
                       s.params = sand(m);
                       s.mesh = mesh;
                       s.cam = look({0.5f, -2, 1}, {0, 0, 0});  // under the plane: its back side faces the camera
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "kajs and zirr, the camera under a plane (two-sided: the back face is shaded, sun above it)"});
  specs.push_back({"render.camera-inside-sphere", true,
                   [] {
                     std::vector<Shot> shots;
                     core::MeshSpec spec;
                     spec.type = "sphere";
                     spec.size = 4;
                     spec.tessellation = 24;
                     auto mesh = std::make_shared<const core::Mesh>(core::build_mesh(spec));
                     for (core::GlintModel m : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       Shot s;
                       s.label = model_name(m) + " at the centre";
                       s.params = sand(m);
                       s.mesh = mesh;
                       s.cam = look({0, 0, 0}, {1, 0.2f, 0.3f}, 90, 0.01f, 50);
                       shots.push_back(s);
                       s.label = model_name(m) + " on the shell";
                       s.cam = look({0, 1.999f, 0}, {1, 1.9f, 0.2f}, 90, 1e-4f, 50);
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "kajs and zirr inside a sphere of radius 2: at its centre and 1e-3 from its shell (distances "
                   "down to the near plane 1e-4)"});
  specs.push_back({"render.camera-in-plane", false,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (float y : {0.0f, 1e-7f, -1e-7f}) {
                       Shot s;
                       s.label = "eye at y = " + fmt(y);
                       s.params = sand(core::GlintModel::Zirr);
                       s.mesh = mesh;
                       s.cam = look({-5, y, 0.3f}, {5, y, 0}, 40, 1e-4f, 100);
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "zirr, the eye in the plane of the surface and 1e-7 above and below it (edge-on triangles)"});
  specs.push_back({"render.backlit", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (core::GlintModel m : kModels) {
                       Shot s;
                       s.label = model_name(m);
                       s.params = sand(m);
                       s.params.T = 1.0;
                       s.mesh = mesh;
                       s.cam = look({0, 2, 2}, {0, 0, 0});
                       s.light.sun_dir = glm::vec3(0, -2, -2);  // = -w_o at the image centre
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "every model, the sun exactly opposite the view direction at the image centre, T = 1"});
  specs.push_back({"render.object-coords-1e6", true,
                   [] {
                     std::vector<Shot> shots;
                     core::Mesh m = plane_mesh(10, 4);
                     for (auto& v : m.vertices) v.position += glm::vec3(1e6f, 0.0f, -1e6f);
                     m.bounds_min += glm::vec3(1e6f, 0.0f, -1e6f);
                     m.bounds_max += glm::vec3(1e6f, 0.0f, -1e6f);
                     auto mesh = std::make_shared<const core::Mesh>(std::move(m));
                     for (core::GlintModel gm : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       for (double ns : {1.0, 1e6}) {
                         Shot s;
                         s.label = model_name(gm) + " noise_scale " + fmt(ns);
                         s.params = sand(gm);
                         s.params.noise_scale = ns;
                         s.mesh = mesh;
                         s.model = glm::translate(glm::mat4(1.0f), glm::vec3(-1e6f, 0.0f, 1e6f));
                         s.cam = look({0, 3, 3}, {0, 0, 0});
                         shots.push_back(s);
                       }
                     }
                     return shots;
                   },
                   "kajs and zirr, object coordinates around (1e6, 0, -1e6) moved to the origin by the model matrix, "
                   "noise_scale 1 and 1e6 (cell coordinates 1e12)"});
  specs.push_back({"render.far-1e6-sigmoid-a1e3", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(8e6f, 4);
                     for (core::GlintModel gm : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       Shot s;
                       s.label = model_name(gm);
                       s.params = sand(gm);
                       s.params.sigmoid_a = 1e3;
                       s.params.sigmoid_b = 1e6;  // the transition crosses the image
                       s.mesh = mesh;
                       s.cam = look({0, 7e5f, 0}, {3e5f, 0, 1e5f}, 40, 1e3f, 1e7f);
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "kajs and zirr, a plane 0.8 .. 1.5e6 away, sigmoid a = 1e3, b = 1e6 (the close-to-far transition "
                   "crosses the image)"});
  specs.push_back({"render.footprint-1e-9-to-1e3-cells", true,
                   [] {
                     std::vector<Shot> shots;
                     for (core::GlintModel gm : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       Shot s;
                       s.params = sand(gm);
                       s.params.noise_scale = 1;
                       s.params.glints.log_density = -3;
                       s.label = model_name(gm) + " tiny";
                       s.mesh = plane(1, 2);  // the camera 1e-6 above: pixels 1e-9 units wide
                       s.cam = look({0, 1e-6f, 0}, {0, -1, 0}, 1, 1e-7f, 1);
                       shots.push_back(s);
                       s.label = model_name(gm) + " huge";
                       s.params.noise_scale = 30;
                       s.params.glints.log_density = 4;
                       s.mesh = plane(1e4f, 4);  // 1e3 above at 60 deg: pixels ~36 units, 1e3 grain cells
                       s.cam = look({0, 1e3f, 0}, {0, 0, 0}, 60, 1.0f, 1e4f);
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "kajs and zirr looking straight down from 1e-6 (pixel footprints 1e-9 grain cells, 1e-12 "
                   "microdetail cells) and from 1e3 (1e3 grain cells, 1e5 microdetail cells)"});
  specs.push_back({"render.sun-1e6", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (core::GlintModel gm : kModels) {
                       Shot s;
                       s.label = model_name(gm);
                       s.params = sand(gm);
                       s.params.I_glints = {1e6, 1e6, 1e6};
                       s.params.glints.intensity = 1e6;
                       s.mesh = mesh;
                       s.cam = look({0, 3, 3}, {0, 0, 0});
                       s.light.sun_L = glm::vec3(1e6f);
                       s.light.sun_dir = {0, 1, -1};
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "every model, sun radiance 1e6, I_glints and glint intensity 1e6 (values up to ~1e14 in fp32)"});
  specs.push_back({"render.palette-black-and-white", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (double v : {0.0, 1.0}) {
                       for (core::GlintModel gm : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                         Shot s;
                         s.label = model_name(gm) + (v == 0 ? " black" : " white");
                         s.params = sand(gm);
                         for (auto& c : s.params.palette) c = {v, v, v};
                         s.mesh = mesh;
                         s.cam = look({0, 3, 3}, {0, 0, 0});
                         if (v == 0) s.light.sky = glm::vec3(0.0f);
                         shots.push_back(s);
                       }
                     }
                     return shots;
                   },
                   "kajs and zirr with every grain colour 0 (and no sky) and 1"});
  specs.push_back({"render.material-extremes", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     int k = 0;
                     for (double R : {0.0, 1.0})
                       for (double P : {0.0, 1.0})
                         for (double sg : {1e-6, 1.0}) {
                           Shot s;
                           core::GlintModel gm = kModels[k++ % 4];
                           s.label = model_name(gm) + " R " + fmt(R) + " P " + fmt(P) + " sigma " + fmt(sg);
                           s.params = sand(gm);
                           s.params.R_s = R, s.params.R_t = R, s.params.T = 1.0, s.params.P = P;
                           s.params.glint_sigma = sg;
                           s.params.oren_nayar_sigma = R * 1.5707963;
                           s.params.glints.alpha_g = {R == 0 ? 1e-3 : 1.0, R == 0 ? 1e-3 : 1.0};
                           s.params.glints.relative_roughness = {P == 0 ? 1e-3 : 1.0, 1e-3};
                           s.mesh = mesh;
                           s.cam = look({0, 3, 3}, {0, 0, 0});
                           s.light.sun_dir = {0, 1, -1};
                           shots.push_back(s);
                         }
                     return shots;
                   },
                   "R_s = R_t in {0, 1}, P in {0, 1}, glint sigma in {1e-6, 1}, T = 1, Oren-Nayar sigma 0 / pi/2, "
                   "glint alpha_g 1e-3 / 1, relative roughness 1e-3 / 1, the models in turn"});
  specs.push_back({"render.rgba16f-target", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (core::GlintModel gm : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       for (float sun : {6.0f, 1e4f, 1e6f}) {
                         Shot s;
                         s.label = model_name(gm) + " sun " + fmt(sun);
                         s.params = sand(gm);
                         s.mesh = mesh;
                         s.cam = look({0, 3, 3}, {0, 0, 0});
                         s.light.sun_L = glm::vec3(sun);
                         s.light.sun_dir = {0, 1, -1};
                         s.format = VK_FORMAT_R16G16B16A16_SFLOAT;
                         shots.push_back(s);
                       }
                     }
                     return shots;
                   },
                   "kajs and zirr into an RGBA16F colour target, sun 6 and 1e4 (glints up to ~1e5 > half's 65504)"});
  specs.push_back({"render.resolution-1x1", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (core::GlintModel gm : kModels) {
                       Shot s;
                       s.label = model_name(gm);
                       s.params = sand(gm);
                       s.mesh = mesh;
                       s.cam = look({0, 3, 3}, {0, 0, 0});
                       s.width = s.height = 1;
                       shots.push_back(s);
                     }
                     Shot t = shots.back();
                     t.label = "taa 1x1";
                     t.variant = true, t.aa = AaMethod::Taa, t.frames = 4;
                     shots.push_back(t);
                     return shots;
                   },
                   "every model at 1x1 (one pixel: its footprint is the whole view), and TAA at 1x1 over 4 frames"});
  specs.push_back({"render.resolution-4096x16", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (core::GlintModel gm : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       Shot s;
                       s.label = model_name(gm);
                       s.params = sand(gm);
                       s.mesh = mesh;
                       s.cam = look({0, 3, 3}, {0, 0, 0}, 2);
                       s.width = 4096, s.height = 16;
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "kajs and zirr at 4096x16 (aspect 256: pixels 1/16 of the fov tall, extremely wide view)"});
  specs.push_back({"render.zirr-density-1e-3-to-1e12", true,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(20, 4);
                     for (double ld : {-3.0, 0.0, 3.0, 6.0, 9.0, 12.0}) {
                       Shot s;
                       s.label = "log_density " + fmt(ld);
                       s.params = sand(core::GlintModel::Zirr);
                       s.params.glints.log_density = ld;
                       s.mesh = mesh;
                       s.cam = look({0, 3, 3}, {0, 0, 0});
                       s.light.sun_dir = {0, 1, -1};
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "zirr at 1e-3, 1, 1e3, 1e6, 1e9, 1e12 microdetails per uv unit (glints.log_density -3 .. 12)"});
  specs.push_back({"render.variants-ssaa-taa-reference", false,
                   [] {
                     std::vector<Shot> shots;
                     auto mesh = plane(4e4f, 4);
                     for (core::GlintModel gm : {core::GlintModel::Kajs, core::GlintModel::Zirr}) {
                       Shot s;
                       s.params = sand(gm);
                       s.mesh = mesh;
                       s.cam = grazing_camera(89.9, 1.0f);
                       s.variant = true;
                       s.label = model_name(gm) + " ssaa 4x4";
                       s.aa = AaMethod::Ssaa, s.ssaa_grid = 4;
                       shots.push_back(s);
                       s.label = model_name(gm) + " taa";
                       s.aa = AaMethod::Taa, s.ssaa_grid = 1, s.frames = 6;
                       shots.push_back(s);
                       s.label = model_name(gm) + " reference 4x4";
                       s.variant = false, s.reference = true, s.ssaa_grid = 4, s.frames = 1;
                       shots.push_back(s);
                     }
                     return shots;
                   },
                   "build_variant (ssaa 4x4, taa over 6 frames) and build_reference (4x4, supersampled pass) for "
                   "kajs and zirr (grains as its truth) at 89.9 deg"});
  for (auto& s : specs)
    cases.push_back({s.name, "render", s.fast, [s](Env& env) { return run_render_case(env, s); }});
  cases.push_back({"render.energy-zirr-vs-beckmann", "render", false, energy_render_case});
}

}  // namespace glintlab::stress
