// Parameters of the Kajs 2022 sand material (thesis chapter 4, Appendix A):
// named parameters with the Appendix A defaults, presets, validated JSON
// overrides, std140 packing for shaders/sand/sand_params.glsl, and the
// compile-time pruning defines of shaders/sand/sand.glsl.
#pragma once

#include "core/material/glint_model.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace glintlab {
class JsonReader;
}

namespace glintlab::core {

// std140 mirror of `struct SandParams` in shaders/sand/sand_params.glsl.
struct SandParamsGPU {
  float palette[8][4];  // rgb = C[i], a = 1
  float I_glints[4];    // rgb, a = 0
  float SSS, R_s, T, R_t;
  float sigma_g, P, noise_scale, ior;
  float scattering, absorption, sigma_on, sig_a;
  float sig_b, glint_intensity, glint_light_cone, glint_pad0;
  uint32_t appendix_compat, fresnel_half_vector, glint_model, energy_consistent;
  float glint_alpha[4];  // xy = alpha_g (u, v), zw = relative roughness (u, v)
  float glint_log_density, specular_aa_sigma2, specular_aa_kappa, glint_pad3;
  float glint_parameters[kMaxGlintParameters];  // the glint_D model's parameters, declaration order
};
static_assert(sizeof(SandParamsGPU) == 288, "SandParamsGPU must match the std140 GLSL struct");
static_assert(offsetof(SandParamsGPU, glint_parameters) == 256, "std140 offset");
static_assert(offsetof(SandParamsGPU, I_glints) == 128, "std140 offset");
static_assert(offsetof(SandParamsGPU, SSS) == 144, "std140 offset");
static_assert(offsetof(SandParamsGPU, sigma_g) == 160, "std140 offset");
static_assert(offsetof(SandParamsGPU, scattering) == 176, "std140 offset");
static_assert(offsetof(SandParamsGPU, sig_b) == 192, "std140 offset");
static_assert(offsetof(SandParamsGPU, appendix_compat) == 208, "std140 offset");
static_assert(offsetof(SandParamsGPU, glint_model) == 216, "std140 offset");
static_assert(offsetof(SandParamsGPU, glint_intensity) == 196, "std140 offset");
static_assert(offsetof(SandParamsGPU, energy_consistent) == 220, "std140 offset");
static_assert(offsetof(SandParamsGPU, glint_alpha) == 224, "std140 offset");
static_assert(offsetof(SandParamsGPU, glint_log_density) == 240, "std140 offset");

// Bits of SandParams::appendix_compat (= SAND_COMPAT_* in sand_params.glsl):
// Appendix A behaviour where it differs from chapter 4 (shaders/sand/DIFFERENCES.md).
enum SandCompat : uint32_t {
  kSandCompatRandNormalized = 1u,    // "rand_normalized"
  kSandCompatIntensityXi1 = 2u,      // "intensity_xi1"
  kSandCompatGateXi1 = 4u,           // "gate_xi1"
  kSandCompatGlintSky = 8u,          // "glint_sky"
  kSandCompatFresnelAbs = 16u,       // "fresnel_abs"
  kSandCompatOrenNayarWorld = 32u,   // "oren_nayar_world"
  kSandCompatAll = 63u,
};

// What a run needs from the material; shader_defines() compiles out the rest.
struct SandFeatures {
  double min_distance = 0.0;  // smallest camera distance of any shaded point in the run
  double max_distance = std::numeric_limits<double>::infinity();  // largest
  std::string debug_output = "final";  // one of SandParams::debug_output_names()
};

// The parameters every glint_D model shares (Zirr & Kaplanyan 2016 sec.
// 4.5), JSON object "glints"; names after the paper's sec. 4.5. A model's
// own parameters (its declaration, core/material/glint_model.h) are given in
// "glints" too, by their names.
struct SandGlintParams {
  // log10 of microdetails per unit uv area, [-3, 14] (1e-3 .. 1e14). Default 7: the scene
  // meshes span uv [0, 1] once over 10 units (core/scene/mesh.h), so 1e7 per
  // uv area is 1e5 per square unit (3.2 mm apart in a 10 m scene). The
  // default experiment's pixels (640x360, 40 deg, 3.6-4 units away) cover
  // ~6.6e-7 uv area face-on, 2.4x that at its 25 deg slant: 6-16
  // microdetails, of which up to (alpha_l / alpha_g)^2 = 1 % reflect (eq. 7 at
  // the highlight's peak): about one pixel in seven near the highlight holds
  // a reflecting microdetail, ~7x the smooth highlight's peak (m0 / 16 vs
  // D_g), several times the diffuse sand -- sparse, visible sparkles. 8 gives
  // denser, dimmer ones; at 6 a microdetail spans several pixels.
  double log_density = 7.0;
  std::array<double, 2> alpha_g{0.3, 0.3};             // global Beckmann roughness (u, v), [1e-3, 1]
  std::array<double, 2> relative_roughness{0.1, 0.1};  // alpha_l / alpha_g of a microdetail (u, v), [1e-3, 1]
  double intensity = 1.0;       // overall gain (sec. 4.5), [0, 1e6]; 1 = the physical BRDF
  // Light-cone angular radius (rad), [0, 0.5]; unset ("sun" in JSON): the
  // sun's angular radius of the frame (frame_sun_dir.w).
  std::optional<double> light_cone;
  // The model's own parameters that differ from their declared defaults
  // (bools as 0/1); SandParams::glint_parameter() reads one with its default.
  std::map<std::string, double> model;
};

// Geometric specular anti-aliasing, JSON "specular_aa": the roughness of the lobes the material
// shades widened by how the surface turns within the pixel (shaders/sand/specular_aa.glsl has each
// method's equations). It widens the glint_D models' alpha_g (their smooth limit, the far field, and
// the spread of the microdetail normals alpha_m); alpha_l, one microdetail's lobe, is kept (none of
// the papers widens it). Where the macro normal does not turn within the pixel nothing is changed.
// The truth never has it (reference()): it is what the supersampled footprint integral has exactly.
struct SandSpecularAA {
  std::string method = "none";  // one of names()
  double sigma2 = 0.0;          // sigma^2: the variance of the pixel filter (screen units)
  double kappa = 0.0;           // kappa: the largest alpha^2 the kernel adds

  // "none", "kaplanyan2016", "tokuyoshi2019", "tokuyoshi2021"
  static const std::vector<std::string>& names();
  // The published parameters of a method ("none": 0, 0).
  static SandSpecularAA published(const std::string& method);
  bool on() const { return method != "none"; }
  int define() const;  // SAND_SPECULAR_AA's value: the method's index in names()
};

struct SandParams {
  using RGB = std::array<double, 3>;
  // Grain palette C[8] (eq. 4.4); Appendix A default: all white.
  std::array<RGB, 8> palette{{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1},
                              {1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}};
  // Colour space the palette and I_glints are given in (OCIO name in the
  // project config); the renderer converts to its working space before pack().
  std::string palette_space = "lin_rec709";
  double SSS = 0.8;           // subsurface scattering multiplier, [0, 1]
  double R_s = 0.12;          // specular roughness, [0, 1]
  double T = 0.8;             // transmission, [0, 1]
  double R_t = 0.2;           // transmission roughness, [0, 1]
  double glint_sigma = 1e-5;  // Gaussian sigma of eq. 4.17, [1e-6, 1]
  double P = 0.1;             // porosity factor, [0, 1]
  double noise_scale = 2000;  // grain cells per object unit, [1, 1e6]
  RGB I_glints{1, 1, 1};      // glint gain I_glints (eq. 4.20), [0, 1e6] per channel
  double scattering = 0.2;    // eq. 4.12, [0, 1]
  double absorption = 0.8;    // eq. 4.13, [0, 1]
  double oren_nayar_sigma = 0.1;  // eq. 4.34, radians, [0, pi/2]
  double sigmoid_a = 2.0;     // eq. 4.37 stretch, (0, 1e4]
  double sigmoid_b = 1.3;     // eq. 4.37 shift, distance units, [0, 1e7]
  double ior = 1.458;         // grain IOR (silica), [1, 3]
  std::string glint_model = kGlintModelKajs;  // one of glint_model_names(), or a user file's name
  // The declaration of a user's model file ("glint_model": {"file": ...}) or of a built-in model
  // with another truth ({"name": ..., "truth": ...}); null for the others.
  std::shared_ptr<const GlintModelDecl> glint_file;
  std::string fresnel_half_vector = "macro_normal";  // "macro_normal" | "light_view"
  uint32_t appendix_compat = 0;  // SandCompat bits; 0 = chapter 4 everywhere
  // false: the thesis' units (sky diffuse rho/pi L_sky^Omega = rho E/pi^2; the
  // sun's Fresnel, transmission and kajs glint terms without 1/pi); true:
  // radiometrically consistent (shaders/sand/DIFFERENCES.md "Units").
  bool energy_consistent = false;
  SandGlintParams glints;  // "glints": the glint_D models
  // "specular_aa": a method's name (its published parameters) or {"method": ..., "sigma2": ...,
  // "kappa": ...}; needs a glint_D model (kajs and none have no roughness to widen).
  SandSpecularAA specular_aa;

  // The glint_D model's declaration; nullptr for "kajs" and "none".
  const GlintModelDecl* glint_decl() const;
  // A parameter of the glint_D model: its value, else its default. ConfigError
  // when the model does not declare it.
  double glint_parameter(const std::string& name) const;

  // "thesis-default" (Appendix A defaults), "thesis-hdri-match" (thesis
  // sec. 6.2, Fig. 6.5/6.8), "thesis-appendix-a" (defaults + every
  // Appendix A behaviour bit). Unknown name -> ConfigError listing the names.
  static SandParams preset(const std::string& name);
  static std::vector<std::string> preset_names();
  // {"preset": "...", <any parameter as override>}; every value range-checked,
  // unknown keys rejected (ConfigError naming file, key and allowed range).
  // palette: array of 8 [r,g,b]; I_glints: [r,g,b]; appendix_compat: "none",
  // "all" or an array of bit names (compat_names()); glints: an object with
  // log_density, alpha_g [u, v], relative_roughness [u, v], size_variation,
  // intensity, light_cone (number or "sun"), color_saturation.
  static SandParams from_json(JsonReader& r);
  // Throws ConfigError("sand: <name>: ...") on any out-of-range value.
  void validate() const;
  SandParamsGPU pack() const;

  static std::vector<std::string> compat_names();  // bit i = 1 << i
  // The keys of "glints" whose value is [u, v] (alpha_g, relative_roughness).
  static std::vector<std::string> glint_vector_keys();
  static std::vector<std::string> debug_output_names();
  // Value of SAND_DEBUG for a debug output name; ConfigError if unknown.
  static int debug_output_define(const std::string& name);

  // The parameters whose supersampled image is the ground truth of this
  // material: the model its declaration names as truth (zirr filters the
  // grains microstructure, so its truth is grains: the same microdetails,
  // point-evaluated), with the parameters of the same names that the truth
  // declares; "self": the model itself. The close-to-far transition's sigmoid (not part of the truth)
  // is reset, so variants that differ only in it share one reference.
  SandParams reference() const;
};

// Sigmoid of eq. 4.37 in a stable form (the value the shader's sig() has).
double sand_sigmoid(double x, double a, double b);

// Threshold below which a transition weight counts as "never reached".
constexpr double kSandPruneWeight = 1e-4;

// Defines ("NAME=VALUE") for shaders/sand/sand.glsl: SAND_TRANSMISSION=0
// when T = 0; SAND_GLINTS=0 when glint_model is "none", or "kajs" with
// I_glints = 0 or the close field pruned, or another model with
// glints.intensity = 0; SAND_GLINT_MODEL=<glint_model_gpu_id> (only that
// model is compiled; a glint_D model's file and parameters by
// glint_model_defines); SAND_SPECULAR_AA=<SandSpecularAA::define()> with SAND_SPECULAR_AA_SIGMA2 and
// SAND_SPECULAR_AA_KAPPA where a method is on and glints are compiled; SAND_FAR=0 when sig(max_distance) < 1e-4; SAND_CLOSE=0
// when 1 - sig(min_distance) < 1e-4; SAND_DEBUG=<value>. A debug output
// keeps both fields (no close/far pruning).
std::vector<std::string> shader_defines(const SandParams& params, const SandFeatures& needs);

// The defines that build a glint_D model into shaders/sand/glint_models.glsl:
// GLINT_MODEL_INCLUDE, the include alias GLINT_MODEL_FILE (its file),
// GLINT_MODEL_HASH (its content hash, so the reference cache key changes with
// any byte of it), its parameters as GlintQuery fields read from
// SandParams.glint_parameters, and GLINT_LIMIT_GGX for a model whose smooth
// limit is GGX.
std::vector<std::string> glint_model_defines(const GlintModelDecl& model);

}  // namespace glintlab::core
