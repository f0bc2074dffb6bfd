// An experiment file (experiments/*.json) as a validated, typed spec. Every
// error names the file, the key path and what is allowed (ConfigError).
//
// {
//   "name": "default", "description": "...",
//   "resolution": [640, 360],              // each in [1, 16384]
//   "frames": 24,                          // optional, <= the path's frame count (default: all)
//   "working_space": "lin_rec709",         // or "ACEScg" (OCIO names of the shipped config)
//   "scene": { "mesh": {MeshSpec}, "sky": {SkySpec} },
//   "camera_path": "orbit-close" | "paths/x.json" | {inline CameraPath},
//   "material": {"preset": "thesis-default", <SandParams overrides>},
//   "variants": [ {"name": "no-aa", "aa": "none" | "ssaa" | "taa", "ssaa_grid": 2,
//                  "taa": {"jitter": "halton16", "name": "falcor" | "file": "my_resolve.glsl",
//                          "parameters": {<the resolve's declared parameters and options>}},  // taa only
//                  // or the flat form "taa": {"jitter": ..., <falcor's parameters and options>}
//                  "debug": "final" | <debug output>, "material": {<overrides>},
//                  "truth_material": {<overrides>}} ],   // its truth's material, if not "material"
//   "reference": {"enabled": true, "grid": 16},   // grid^2 stratified samples, box filter
//   "metrics": ["deltaE2000", "deltaEITP", "flip", "psnr", "relative"],  // and the groups "flicker",
//              "glints", "pooled": none named = every group, else flicker and the named ones
//   "metric_options": {"view": "" | "sRGB/Standard",  // "" = scene-referred per-pixel metrics
//                      "itp_nits": 100, "flip": "hdr" | "ldr", "flip_ppd": 67.0206},
//   "output": {"exr": true, "png": true, "every": 1, "display": "sRGB", "view": "ACES 1.0 SDR-video",
//              "exposure": 0 (stops, previews only),
//              "contact_sheet": false, "contact_sheet_columns": 8,
//              "contact_sheet_zoom": {"region": [x, y, w, h], "scale": k}},
//   "density_sweep": {"zirr": {"parameter": "log_density",   // a key of "glints" (optional;
//                              "values": [5, 5.5, 6, ...],   //  experiments/runner/density_sweep.h)
//                              "glints": {...}}}             // fixed at every value (optional)
// }
#pragma once

#include "core/scene/camera_path.h"
#include "core/scene/environment.h"
#include "core/scene/mesh.h"
#include "core/render/taa_resolve.h"
#include "core/util/json_check.h"
#include "core/util/named_enum.h"
#include "core/material/sand_material.h"
#include "metrics/metric_registry.h"

#include <nlohmann/json.hpp>

#include <climits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace glintlab {

// Anti-aliasing methods: one name table (the JSON values of "aa").
enum class AaMethod { None, Ssaa, Taa };
inline constexpr EnumTable<AaMethod, 3> kAaNames{{
    {AaMethod::None, "none"},  // one sample at each pixel centre
    {AaMethod::Ssaa, "ssaa"},  // ssaa_grid^2 stratified samples, one fixed pattern
    {AaMethod::Taa, "taa"},    // one jittered sample + the TAA resolve (core/render/taa_resolve.h)
}};

struct VariantSpec {
  std::string name;
  AaMethod aa = AaMethod::None;
  int ssaa_grid = 1;        // ssaa: grid x grid stratified samples per pixel
  core::TaaSettings taa;    // taa: the resolve, its parameters and options, the jitter ("taa" object)
  std::string debug = "final";
  core::SandParams material;  // experiment material + this variant's overrides
  nlohmann::json material_json;  // the merged object (for hashing and the summary)
  // "truth_material": {overrides}: the material its truth is rendered with where it is not `material`
  // (the variants of a density sweep: a model at another density, against the experiment's truth).
  std::optional<core::SandParams> truth_material;
  nlohmann::json truth_material_json;  // merged over the experiment's material, as "material"
  nlohmann::json taa_json;       // the "taa" object as given (for the summary)
  std::string frames;            // a frame source: the SEQ its frames are read from (experiments/sources/sequence.h)
  std::string frames_space;      // its OCIO space ("" = the files' tag, else scene_linear)

  // "render_scale" s in [0.25, 1]: the frame graph renders at round(s W) x round(s H) and resolves to the
  // output W x H: a TAA variant's resolve reconstructs it (temporal upscaling; its jitter then defaults
  // to halton_fsr2), any other variant is upscaled bilinearly (a spatial upscale).
  double render_scale = 1.0;
  // "glint_footprint": the pixel footprint the glint models filter over at s < 1: the render pixel
  // ("render", 1/s output pixels wide) or the display pixel ("display": the render footprint times s,
  // as FSR 2's mip-bias guidance does for textures).
  std::string glint_footprint = "render";
  // "mesh_lod": which resolution an adaptive mesh (scene.mesh "max_edge_px") is adapted for at s < 1: the
  // output's ("display", the default: the mesh the native variants and the truth draw) or the render
  // resolution's ("render": max_edge_px and max_error_px in render pixels, as an engine picks a level of
  // detail for the image it renders: fewer triangles, and vertex normals interpolated over wider cells).
  std::string mesh_lod = "display";
  int samples_per_pixel() const { return aa == AaMethod::Ssaa ? ssaa_grid * ssaa_grid : 1; }
  // The render resolution of an output of w x h: round(s w) x round(s h), at least 1.
  int render_width(int w) const;
  int render_height(int h) const;
};

struct ReferenceSpec {
  bool enabled = true;
  int grid = 16;  // grid x grid samples (16 x 16 by default)
  std::string frames;  // a frame source instead of a render: the SEQ (experiments/sources/sequence.h)
  std::string frames_space;
  std::string frames_b;  // frames-only: the reference's second half ("frames" the first; measure --reference-b)
  // "floor": {METRIC: FRACTION, ...}: a truth good enough instead of a sample count. The run starts at
  // `grid` and adds samples until each named metric's noise floor is at most FRACTION of the smallest
  // value any variant measured against that truth has, up to `max_grid` (experiments/runner/runner.cpp).
  std::map<std::string, double> floor_target;
  int max_grid = 48;
};

// A frames-only experiment (no "scene"): every variant and the reference are frame sources, measured
// as `glintlab measure` measures them; these are its further keys.
struct FramesOnlySpec {
  bool enabled = false;
  std::string motion;             // "motion": {"frames": SEQ}
  std::string motion_from;        //            {"from": "reference" | "test"}
  std::string motion_convention = "pixels";  // {"convention": NAME}
  std::string depth;              //            {"depth": SEQ}
  int first = INT_MIN, last = INT_MAX;  // "frame_range": [first, last]
  double fps = 24.0;              // "fps"
};

struct OutputSpec {
  bool exr = true;
  bool png = true;
  int every = 1;  // save images of every n-th frame (metrics are computed for all)
  std::string display = "sRGB";
  std::string view = "ACES 1.0 SDR-video";  // previews: a filmic tone curve (highlights roll off, glints stay visible)
  double exposure = 0.0;                   // stops applied to the scene-linear image before the view (previews only)
  bool contact_sheet = false;  // DIR/contact_sheet.png: rows = variants (+ reference), columns = saved frames
  int contact_sheet_columns = 8;  // at most this many saved frames per row
  // "contact_sheet_zoom": {"region": [x, y, w, h], "scale": k}: also DIR/contact_sheet_zoom.png, the same
  // sheet of that region of every frame (output pixels, clipped to the image), each pixel enlarged k
  // times (nearest: a glint stays one sharp square). zoom_scale 0 = none.
  int zoom_x = 0, zoom_y = 0, zoom_w = 0, zoom_h = 0, zoom_scale = 0;
  bool motion = false;  // DIR/motion/frame_NNNN.exr: the motion vectors flicker is measured along (`pixels`)
  // DIR/<reference>-half-a/ and -half-b/frame_NNNN.exr: the truth's two halves (where it has them), what
  // `measure --reference SEQ --reference-b SEQ` takes as a reference with its noise floor.
  bool halves = false;
};

// "density_sweep": each named variant rendered again at every value of one parameter of its "glints"
// (glintlab's common ones, e.g. log_density, or its model's own: the method's density parameter),
// measured against the run's truth, and at the value where its glint density matches the truth's
// (experiments/runner/density_sweep.h).
struct DensitySweepSpec {
  struct Method {
    std::string variant;
    std::string parameter;
    std::vector<double> values;  // strictly increasing, at least 2
    nlohmann::json glints = nlohmann::json::object();  // "glints": set at every value (not in the truth)
  };
  std::vector<Method> methods;  // by variant name (JSON object order)
  bool enabled() const { return !methods.empty(); }
};

struct ExperimentSpec {
  std::string file;
  std::string name;
  std::string description;
  int width = 640, height = 360;
  int frames = 1;
  std::string working_space = "lin_rec709";
  core::MeshSpec mesh;
  core::SkySpec sky;
  std::string path_name;  // built-in name, file, or "inline"
  std::string path_file;  // the camera path's file, when it is one (its content identifies the run)
  core::CameraPath path;
  nlohmann::json material_json;
  std::vector<VariantSpec> variants;
  ReferenceSpec reference;
  std::vector<std::string> metrics;
  metrics::MetricOptions metric_options;
  OutputSpec output;
  nlohmann::json source;  // the file's JSON as read (for hashing and the summary)
  FramesOnlySpec frames_only;
  DensitySweepSpec density_sweep;

  // metric_options as the run measures with them: temporal_score through the view the previews
  // use (output display/view), or through metric_options.view when one is set.
  metrics::MetricOptions measured_metric_options() const;

  static ExperimentSpec load(const std::string& file);
  static ExperimentSpec from_json(const nlohmann::json& j, const std::string& file);

 private:
  static void read_common(JsonReader& r, ExperimentSpec& s);  // metrics, metric_options, output
  static ExperimentSpec read_frames_only(JsonReader& r, ExperimentSpec& s, const std::string& file);
};

// The material of variant `v` of a density sweep at `value` of its parameter: the variant's merged
// material with the sweep's fixed "glints" keys and "glints"."parameter" set ([value, value] for the
// [u, v] keys).
nlohmann::json density_sweep_material(const VariantSpec& v, const DensitySweepSpec::Method& m, double value);
// "" where that material is valid, else what is wrong with it (a value outside the parameter's range).
std::string density_sweep_problem(const ExperimentSpec& s, const VariantSpec& v, const DensitySweepSpec::Method& m,
                                  double value);

// `experiment` (the JSON of `file`) with every file it names made absolute, as the spec resolves them:
// a camera-path file, the sky's HDRI, a user's glint model file in the experiment's and every variant's
// "material" and "truth_material". For a copy that is run from another folder (tune's trials).
nlohmann::json with_absolute_paths(const nlohmann::json& experiment, const std::string& file);

// A variant's name becomes a folder of the run directory and a CSV cell: "" when it may, else what is
// wrong and what is allowed (1 to 100 of A-Z a-z 0-9 . _ + -, not starting with '.' or '-', and not one
// of the run folder's own names: reference, reference-*, motion, figures, frames.csv, summary.json,
// report.html, records.jsonl, contact_sheet.png). The one check of `run` and `measure` alike.
std::string variant_name_problem(const std::string& name);

// Built-in experiments: every *.json under the data folder's experiments/ (not paths/), named by its
// path relative to it without extension ("default", "thesis/fig6-7-hdri-match").
std::vector<std::string> builtin_experiment_names();
// A name of a built-in experiment, or a path to a file.
std::string resolve_experiment_path(const std::string& name_or_path);

}  // namespace glintlab
