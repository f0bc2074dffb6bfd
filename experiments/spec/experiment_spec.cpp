#include "experiments/spec/experiment_spec.h"

#include "core/util/data_dir.h"
#include "core/util/json_check.h"
#include "core/util/strings.h"
#include "metrics/color/measurement_space.h"
#include "metrics/flip.h"
#include "metrics/metric_registry.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

namespace fs = std::filesystem;

namespace glintlab {

namespace {

core::CameraPath load_path(JsonReader& r, const std::string& key, const std::string& file, std::string* name,
                           std::string* path_file) {
  const nlohmann::json& v = r.raw(key);
  if (v.is_object()) {
    *name = "inline";
    JsonReader pr(v, file, r.key_path(key));
    return core::CameraPath::from_json(pr);
  }
  if (!v.is_string())
    r.fail(key, "expected a built-in path name, a path file or an inline path object");
  std::string s = v.get<std::string>();
  *name = s;
  auto builtins = core::CameraPath::builtin_names();
  if (std::find(builtins.begin(), builtins.end(), s) != builtins.end()) return core::CameraPath::builtin(s);
  // Relative to the experiment file, else to the data folder's experiments/data/.
  std::error_code ec;  // an impossible name (too long, a loop) is just not a file here
  fs::path p = fs::path(file).parent_path() / s;
  if (!fs::is_regular_file(p, ec)) p = fs::path(data_path("experiments/data")) / s;
  if (fs::is_regular_file(p, ec)) {
    *path_file = p.string();
    return core::CameraPath::load(p.string());
  }
  std::string allowed;
  for (const auto& b : builtins) allowed += (allowed.empty() ? "" : ", ") + b;
  r.fail(key, "\"" + s + "\" is neither a built-in path (" + allowed + ") nor a file relative to " + file +
                  " or " + data_path("experiments/data"));
}

template <typename E, size_t N>
E get_named(JsonReader& r, const std::string& key, const EnumTable<E, N>& table, E def) {
  return *enum_from_name(table, r.get_enum(key, enum_name(table, def), enum_names(table)));
}

// A path given in an experiment file is relative to the file's folder.
std::string relative_to(const std::string& file, const std::string& path);

// A variant's "taa" object: {"name": BUILT-IN} or {"file": PATH} with {"parameters": {...}}, or the
// flat form {PARAMETER or OPTION of falcor: ...}; "jitter" in every form. Each value is checked against
// the resolve's declaration: its range, its choices, and "requires=" (a value set where the bool it
// requires is false is an error).
core::TaaSettings parse_taa(JsonReader& r, const std::string& file, core::JitterSequence default_jitter) {
  const core::JitterSequence jitter = get_named(r, "jitter", core::kJitterNames, default_jitter);
  if (r.has("name") && r.has("file")) r.fail("file", "give either \"name\" (a built-in resolve) or \"file\", not both");
  core::TaaResolveDecl decl;
  if (r.has("file")) {
    const std::string path = relative_to(file, r.get_string("file"));
    try {
      decl = core::taa_resolve_from_file(path);
    } catch (const ConfigError& e) {
      r.fail("file", e.what());
    }
  } else {
    decl = *core::find_builtin_taa_resolve(r.get_enum("name", core::kTaaDefaultResolve, core::taa_resolve_names()));
  }
  core::TaaSettings t(decl);
  t.jitter = jitter;
  const bool flat = !r.has("name") && !r.has("file");
  std::optional<JsonReader> child = flat ? std::nullopt : r.optional_child("parameters");
  JsonReader* pr = flat ? &r : child ? &*child : nullptr;
  if (pr) {
    for (const auto& p : decl.parameters)
      t.set(p.name, p.is_bool ? (pr->get_bool(p.name, p.def != 0.0) ? 1.0 : 0.0) : pr->get_number(p.name, p.def, p.lo, p.hi));
    for (const auto& o : decl.options) t.set(o.name, pr->get_enum(o.name, o.choices[o.def], o.choices));
    auto check_requires = [&](const std::string& name, const std::string& req) {
      if (!req.empty() && pr->has(name) && !t.on(req)) pr->fail(name, "only applies with \"" + req + "\": true");
    };
    for (const auto& p : decl.parameters) check_requires(p.name, p.requires_bool);
    for (const auto& o : decl.options) check_requires(o.name, o.requires_bool);
    pr->finish();
  }
  r.finish();
  return t;
}

}  // namespace

int VariantSpec::render_width(int w) const { return std::max(1, int(std::lround(render_scale * w))); }
int VariantSpec::render_height(int h) const { return std::max(1, int(std::lround(render_scale * h))); }

namespace {

// A path given in an experiment file is relative to the file's folder.
std::string relative_to(const std::string& file, const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute() || file.empty()) return path;
  return (fs::path(file).parent_path() / path).string();
}

std::string variant_name(JsonReader& vr, std::set<std::string>& names) {
  const std::string name = vr.get_string("name");
  if (const std::string why = variant_name_problem(name); !why.empty()) vr.fail("name", why);
  if (!names.insert(name).second) vr.fail("name", "\"" + name + "\" is used by two variants");
  return name;
}

// {"frames": SEQ, "space": NAME}: a variant or reference read from files (nothing else is allowed:
// a renderer's options do not apply to another renderer's frames).
void read_frame_source(JsonReader& r, const std::string& file, std::string* seq, std::string* space) {
  *seq = relative_to(file, r.get_string("frames"));
  if (seq->empty()) r.fail("frames", "expected a sequence: a folder, a pattern with %04d or ####, optionally :LAYER");
  *space = r.get_string("space", "");
  r.finish();
}

core::SandParams parse_material(const nlohmann::json& j, const std::string& file, const std::string& path) {
  JsonReader r(j, file, path);
  return core::SandParams::from_json(r);
}

// "density_sweep": {VARIANT: {"parameter": NAME, "values": [v0 < v1 < ...]}, ...}. Every derived
// material is parsed here, so a value outside the parameter's range is refused before any work.
void read_density_sweep(JsonReader& r, ExperimentSpec& s) {
  const nlohmann::json& ds = r.raw("density_sweep");
  const std::string where0 = r.key_path("density_sweep");
  if (!ds.is_object() || ds.empty())
    r.fail("density_sweep", "expected an object {VARIANT: {\"parameter\": NAME, \"values\": [increasing]}, ...} "
                            "naming at least one variant");
  for (auto it = ds.begin(); it != ds.end(); ++it) {
    const std::string where = where0 + "." + it.key();
    auto v = std::find_if(s.variants.begin(), s.variants.end(), [&](const VariantSpec& x) { return x.name == it.key(); });
    if (v == s.variants.end()) throw ConfigError(s.file + ": " + where + ": no variant of that name");
    if (!v->frames.empty()) throw ConfigError(s.file + ": " + where + ": a variant read from files has no parameters");
    if (!it.value().is_object()) r.fail("density_sweep", it.key() + ": expected {\"parameter\": NAME, \"values\": [...]}");
    JsonReader m(it.value(), s.file, where);
    DensitySweepSpec::Method method{it.key(), m.get_string("parameter"), {}};
    if (!is_identifier(method.parameter))
      m.fail("parameter", "expected the name of a key of \"glints\" (e.g. \"log_density\")");
    if (m.has("glints")) {
      method.glints = m.raw("glints");
      if (!method.glints.is_object()) m.fail("glints", "expected an object of \"glints\" keys set at every value");
      if (method.glints.contains(method.parameter)) m.fail("glints", "sets the swept \"" + method.parameter + "\"");
    }
    const nlohmann::json& values = m.raw("values");
    if (!values.is_array() || values.size() < 2 || values.size() > 32)
      m.fail("values", "expected an array of 2 to 32 numbers in increasing order");
    for (const auto& x : values) {
      if (!x.is_number() || !std::isfinite(x.get<double>()) ||
          (!method.values.empty() && !(x.get<double>() > method.values.back())))
        m.fail("values", "expected an array of 2 to 32 numbers in increasing order, got " + dump_json(values));
      method.values.push_back(x.get<double>());
      parse_material(density_sweep_material(*v, method, method.values.back()), s.file, where + ".values");
    }
    m.finish();
    s.density_sweep.methods.push_back(std::move(method));
  }
}

}  // namespace

nlohmann::json density_sweep_material(const VariantSpec& v, const DensitySweepSpec::Method& sweep, double value) {
  nlohmann::json m = v.material_json;
  if (!m.contains("glints") || !m["glints"].is_object()) m["glints"] = nlohmann::json::object();
  for (auto it = sweep.glints.begin(); it != sweep.glints.end(); ++it) m["glints"][it.key()] = it.value();
  const auto vec = core::SandParams::glint_vector_keys();
  const bool both = std::find(vec.begin(), vec.end(), sweep.parameter) != vec.end();  // [u, v]: the value for both
  m["glints"][sweep.parameter] = both ? nlohmann::json::array({value, value}) : nlohmann::json(value);
  return m;
}

std::string density_sweep_problem(const ExperimentSpec& s, const VariantSpec& v, const DensitySweepSpec::Method& m,
                                  double value) {
  try {
    parse_material(density_sweep_material(v, m, value), s.file, "density_sweep." + v.name);
    return "";
  } catch (const ConfigError& e) {
    return e.what();
  }
}

nlohmann::json with_absolute_paths(const nlohmann::json& experiment, const std::string& file) {
  nlohmann::json e = experiment;
  if (!e.is_object()) return e;
  const fs::path dir = fs::absolute(fs::path(file)).parent_path();
  auto absolute = [&](nlohmann::json& v) {
    if (v.is_string() && !v.get<std::string>().empty() && fs::path(v.get<std::string>()).is_relative())
      v = (dir / v.get<std::string>()).lexically_normal().string();
  };
  if (e.contains("camera_path") && e["camera_path"].is_string()) {  // a file beside the experiment (load_path)
    const auto builtins = core::CameraPath::builtin_names();
    const std::string s = e["camera_path"];
    std::error_code ec;
    if (std::find(builtins.begin(), builtins.end(), s) == builtins.end() && fs::is_regular_file(dir / s, ec))
      absolute(e["camera_path"]);
  }
  if (e.contains("scene") && e["scene"].is_object() && e["scene"].contains("sky") && e["scene"]["sky"].is_object() &&
      e["scene"]["sky"].contains("hdri"))
    absolute(e["scene"]["sky"]["hdri"]);
  auto model_file = [&](nlohmann::json& material) {
    if (material.is_object() && material.contains("glint_model") && material["glint_model"].is_object() &&
        material["glint_model"].contains("file"))
      absolute(material["glint_model"]["file"]);
  };
  if (e.contains("material")) model_file(e["material"]);
  if (e.contains("variants") && e["variants"].is_array())
    for (auto& v : e["variants"])
      if (v.is_object())
        for (const char* key : {"material", "truth_material"})
          if (v.contains(key)) model_file(v[key]);
  return e;
}

ExperimentSpec ExperimentSpec::load(const std::string& file) { return from_json(read_json_file(file), file); }

ExperimentSpec ExperimentSpec::from_json(const nlohmann::json& j, const std::string& file) {
  check_json_depth(j, file);  // before any message could print a 10^5-deep value
  ExperimentSpec s;
  s.file = file;
  s.source = j;
  JsonReader r(j, file);
  s.name = r.get_string("name", fs::path(file).stem().string());
  s.description = r.get_string("description", "");
  if (!r.has("scene")) return read_frames_only(r, s, file);  // the frames' own size and colour spaces
  auto res = r.get_numbers("resolution", std::vector<double>{640, 360}, 1, 16384);
  if (res[0] != double(int(res[0])) || res[1] != double(int(res[1]))) r.fail("resolution", "expected two integers");
  s.width = int(res[0]);
  s.height = int(res[1]);
  s.working_space = r.get_enum("working_space", "lin_rec709", {"lin_rec709", "ACEScg"});

  JsonReader scene = r.child("scene");
  JsonReader mesh = scene.child("mesh");
  s.mesh = core::MeshSpec::from_json(mesh);
  if (auto sky = scene.optional_child("sky")) s.sky = core::SkySpec::from_json(*sky);
  scene.finish();

  s.path = load_path(r, "camera_path", file, &s.path_name, &s.path_file);
  s.frames = r.get_int("frames", s.path.frames(), 1, s.path.frames());

  s.material_json = r.has("material") ? r.raw("material") : nlohmann::json::object({{"preset", "thesis-default"}});
  if (!s.material_json.is_object()) r.fail("material", "expected an object {\"preset\": ..., overrides}");
  parse_material(s.material_json, file, r.key_path("material"));  // validate once at experiment level

  std::set<std::string> names;
  auto variants = r.array("variants", 1, 64);
  for (size_t i = 0; i < variants.size(); ++i) {
    JsonReader& vr = variants[i];
    VariantSpec v;
    v.name = variant_name(vr, names);
    if (vr.has("frames")) {  // a frame source: what the files are is theirs, not a renderer's option
      read_frame_source(vr, file, &v.frames, &v.frames_space);
      v.material = parse_material(s.material_json, file, r.key_path("material"));
      v.material_json = s.material_json;
      s.variants.push_back(std::move(v));
      continue;
    }
    v.aa = get_named(vr, "aa", kAaNames, AaMethod::None);
    v.ssaa_grid = vr.get_int("ssaa_grid", v.aa == AaMethod::Ssaa ? 2 : 1, 1, 16);
    if (v.aa != AaMethod::Ssaa && vr.has("ssaa_grid") && v.ssaa_grid != 1)
      vr.fail("ssaa_grid", "only applies to \"aa\": \"ssaa\"");
    v.render_scale = vr.get_number("render_scale", 1.0, 0.25, 1.0);
    v.glint_footprint = vr.get_enum("glint_footprint", "render", {"render", "display"});
    if (vr.has("glint_footprint") && v.render_scale == 1.0)
      vr.fail("glint_footprint", "only applies with \"render_scale\" below 1 (the render pixel is then wider than the "
                                 "display pixel)");
    v.mesh_lod = vr.get_enum("mesh_lod", "display", {"display", "render"});
    if (vr.has("mesh_lod") && v.render_scale == 1.0)
      vr.fail("mesh_lod", "only applies with \"render_scale\" below 1 (the render resolution is then below the "
                          "output's)");
    if (vr.has("mesh_lod") && !(s.mesh.max_edge_px > 0.0f))
      vr.fail("mesh_lod", "only applies to a mesh that adapts to the resolution (scene.mesh.max_edge_px > 0); this "
                          "one is the same grid at every resolution");
    // Below scale 1 a TAA's jitter cycles through 8 / s^2 phases (FSR 2's count) unless the variant says otherwise.
    const core::JitterSequence default_jitter =
        v.render_scale < 1.0 ? core::JitterSequence::HaltonFsr2 : core::JitterSequence::Halton16;
    if (v.aa == AaMethod::Taa) v.taa.jitter = default_jitter;
    if (vr.has("taa")) {
      if (v.aa != AaMethod::Taa) vr.fail("taa", "only applies to \"aa\": \"taa\"");
      v.taa_json = vr.raw("taa");
      if (!v.taa_json.is_object()) vr.fail("taa", "expected an object of TAA options");
      JsonReader tr(v.taa_json, file, vr.key_path("taa"));
      v.taa = parse_taa(tr, file, default_jitter);
    }
    v.debug = vr.get_enum("debug", "final", core::SandParams::debug_output_names());
    // The experiment's material with the variant's overrides of `key`, key by key at every depth (a JSON
    // merge patch, RFC 7386: an object merges into the object it overrides, anything else replaces it).
    auto merged = [&](const char* key) {
      nlohmann::json m = s.material_json;
      const nlohmann::json& over = vr.raw(key);
      if (!over.is_object()) vr.fail(key, "expected an object of material overrides");
      m.merge_patch(over);
      return m;
    };
    v.material_json = vr.has("material") ? merged("material") : s.material_json;
    v.material = parse_material(v.material_json, file, vr.key_path("material"));
    if (vr.has("truth_material")) {
      v.truth_material_json = merged("truth_material");
      v.truth_material = parse_material(v.truth_material_json, file, vr.key_path("truth_material"));
    }
    vr.finish();
    s.variants.push_back(std::move(v));
  }

  if (auto ref = r.optional_child("reference")) {
    s.reference.enabled = ref->get_bool("enabled", true);
    if (ref->has("frames")) {
      if (ref->has("grid")) ref->fail("grid", "a reference read from \"frames\" has no sample grid");
      read_frame_source(*ref, file, &s.reference.frames, &s.reference.frames_space);
    } else {
      s.reference.grid = ref->get_int("grid", 16, 1, 64);
      if (auto fl = ref->optional_child("floor")) {
        for (auto it = fl->json().begin(); it != fl->json().end(); ++it) {
          const bool prefix = !it.key().empty() && it.key().back() == '_';  // "pooled_rms_": a block size is missing
          if (prefix || !metrics::has_noise_floor(it.key()) || !metrics::value_range(it.key()))
          {
            std::string allowed;  // every metric whose row says it has a floor
            for (const metrics::MetricInfo& m : metrics::metric_table())
              if (m.floor) allowed += (allowed.empty() ? "" : ", ") + std::string(m.name) +
                                      (std::string(m.name).back() == '_' ? "<block>" : "");
            fl->fail(it.key(), "not a metric with a noise floor (allowed: " + allowed + ")");
          }
          s.reference.floor_target[it.key()] = fl->get_number(it.key(), 1e-3, 1.0);
        }
        if (s.reference.floor_target.empty())
          ref->fail("floor", "name at least one metric: {\"temporal_error_mc\": 0.1} asks for a floor below 10 % of "
                       "the smallest variant's value");
        fl->finish();
        s.reference.max_grid = ref->get_int("max_grid", 48, 2, 64);
        if (s.reference.grid < 2)
          ref->fail("grid", "a truth sized by \"floor\" starts at a grid of at least 2 (its two halves need "
                            "2 x 2 samples)");
        if (s.reference.max_grid < s.reference.grid)
          ref->fail("max_grid", "the limit " + std::to_string(s.reference.max_grid) + " is below \"grid\" " +
                                    std::to_string(s.reference.grid));
      }
      ref->finish();
    }
  }
  read_common(r, s);
  if (r.has("density_sweep")) read_density_sweep(r, s);
  r.finish();
  if (s.output.halves && (!s.reference.enabled || !s.reference.frames.empty() || s.reference.grid < 2))
    throw ConfigError(file + ": output.halves: the truth's halves are the two checkerboard halves of a rendered "
                      "truth's samples; this experiment's truth " +
                      (!s.reference.enabled        ? std::string("is off (reference.enabled false)")
                       : !s.reference.frames.empty() ? std::string("is read from files")
                                                     : "has 1 sample (reference.grid 1; at least 2 have halves)"));
  for (const auto& [m, fraction] : s.reference.floor_target) {  // a floor of a metric the run measures
    const auto per_pixel = metrics::metric_names();
    const bool measured =
        std::find(per_pixel.begin(), per_pixel.end(), m) == per_pixel.end()
            ? (m == "glint_hist_emd_oct" ? s.metric_options.glints
               : m.rfind("pooled_", 0) == 0 ? s.metric_options.pooled
                                             : true)
            : std::find(s.metrics.begin(), s.metrics.end(), m) != s.metrics.end();
    if (!measured)
      throw ConfigError(file + ": reference.floor." + m + ": the run does not measure " + m +
                        "; add it to \"metrics\" (or its group) or size the truth by a metric it measures");
  }
  return s;
}

void ExperimentSpec::read_common(JsonReader& r, ExperimentSpec& s) {
  if (r.has("metrics")) {
    const auto& m = r.raw("metrics");
    if (!m.is_array()) r.fail("metrics", "expected an array of metric names");
    std::vector<std::string> list;
    for (const auto& e : m) {
      if (!e.is_string()) r.fail("metrics", "expected an array of metric names, got " + e.dump());
      list.push_back(e.get<std::string>());
    }
    try {
      s.metrics = metrics::select_metrics(list, s.metric_options);
    } catch (const std::invalid_argument& e) {
      r.fail("metrics", e.what());
    }
  } else {
    s.metrics = metrics::metric_names();
  }
  if (auto mo = r.optional_child("metric_options")) {
    s.metric_options.display_view = mo->get_string("view", "");
    if (!s.metric_options.display_view.empty()) {
      try {
        metrics::parse_display_view(s.metric_options.display_view);
      } catch (const std::invalid_argument& e) {
        mo->fail("view", std::string(e.what()) + " (or \"\" for scene-referred)");
      }
    }
    s.metric_options.itp_luminance_nits = mo->get_number("itp_nits", 100.0, 1e-3, 1e5);
    s.metric_options.flip_hdr = mo->get_enum("flip", "hdr", {"hdr", "ldr"}) == "hdr";
    s.metric_options.flip_ppd = mo->get_number("flip_ppd", metrics::kFlipDefaultPpd, 1.0, 1000.0);
    mo->finish();
  }

  if (auto out = r.optional_child("output")) {
    s.output.exr = out->get_bool("exr", true);
    s.output.png = out->get_bool("png", true);
    s.output.every = out->get_int("every", 1, 1, 1000000);
    s.output.display = out->get_string("display", "sRGB");
    s.output.view = out->get_string("view", s.output.view);
    s.output.exposure = out->get_number("exposure", 0.0, -20.0, 20.0);
    s.output.contact_sheet = out->get_bool("contact_sheet", false);
    s.output.contact_sheet_columns = out->get_int("contact_sheet_columns", 8, 1, 64);
    if (auto zoom = out->optional_child("contact_sheet_zoom")) {
      if (!s.output.contact_sheet) out->fail("contact_sheet_zoom", "only applies with \"contact_sheet\": true");
      const std::vector<double> r = zoom->get_numbers("region", 4, 0.0, 16384.0);
      for (double x : r)
        if (x != std::floor(x)) zoom->fail("region", "expected whole pixels [x, y, w, h]");
      if (r[2] < 1 || r[3] < 1 || r[0] + r[2] > s.width || r[1] + r[3] > s.height)
        zoom->fail("region", "[x, y, w, h] must lie inside the " + std::to_string(s.width) + "x" +
                                 std::to_string(s.height) + " image with w, h >= 1");
      s.output.zoom_x = int(r[0]);
      s.output.zoom_y = int(r[1]);
      s.output.zoom_w = int(r[2]);
      s.output.zoom_h = int(r[3]);
      s.output.zoom_scale = zoom->get_int("scale", 4, 1, 16);
      zoom->finish();
    }
    s.output.motion = out->get_bool("motion", false);
    s.output.halves = out->get_bool("halves", false);
    out->finish();
  }
}

metrics::MetricOptions ExperimentSpec::measured_metric_options() const {
  metrics::MetricOptions o = metric_options;
  o.temporal_view = o.display_view.empty() ? output.display + "/" + output.view : o.display_view;
  return o;
}

ExperimentSpec ExperimentSpec::read_frames_only(JsonReader& r, ExperimentSpec& s, const std::string& file) {
  s.frames_only.enabled = true;
  std::set<std::string> names;
  auto variants = r.array("variants", 1, 64);
  for (auto& vr : variants) {
    VariantSpec v;
    v.name = variant_name(vr, names);
    if (!vr.has("frames"))
      vr.fail("frames", "an experiment without \"scene\" measures frame sources only: every variant needs "
                        "\"frames\": SEQ");
    read_frame_source(vr, file, &v.frames, &v.frames_space);
    s.variants.push_back(std::move(v));
  }
  s.reference.enabled = false;
  s.reference.grid = 0;
  if (auto ref = r.optional_child("reference")) {
    if (!ref->has("frames")) ref->fail("frames", "an experiment without \"scene\" reads its reference from \"frames\": SEQ");
    s.reference.enabled = true;
    if (ref->has("frames_b")) {  // the reference as two halves: the truth is their mean, their difference its floor
      s.reference.frames_b = relative_to(file, ref->get_string("frames_b"));
      if (s.reference.frames_b.empty()) ref->fail("frames_b", "expected a sequence, as \"frames\"");
    }
    read_frame_source(*ref, file, &s.reference.frames, &s.reference.frames_space);
  }
  if (auto m = r.optional_child("motion")) {
    if (m->has("frames") && m->has("from")) m->fail("from", "give \"frames\" or \"from\", not both");
    if (m->has("frames")) s.frames_only.motion = relative_to(file, m->get_string("frames"));
    if (m->has("from")) s.frames_only.motion_from = m->get_enum("from", "reference", {"reference", "test"});
    s.frames_only.motion_convention =
        m->get_enum("convention", "pixels", {"pixels", "blender", "unreal", "unity"});
    if (m->has("depth")) s.frames_only.depth = relative_to(file, m->get_string("depth"));
    m->finish();
  }
  if (r.has("frame_range")) {
    auto fr = r.get_numbers("frame_range", std::vector<double>{0, 0}, -1e9, 1e9);
    if (fr.size() != 2 || fr[0] != double(int(fr[0])) || fr[1] != double(int(fr[1])) || fr[0] > fr[1])
      r.fail("frame_range", "expected [first, last], two integer frame numbers with first <= last");
    s.frames_only.first = int(fr[0]);
    s.frames_only.last = int(fr[1]);
  }
  s.frames_only.fps = r.get_number("fps", 24.0, 1e-3, 1000.0);
  s.frames = 0;  // what the sequences hold
  read_common(r, s);
  r.finish();
  if (s.output.halves)
    throw ConfigError(file + ": output.halves: an experiment without \"scene\" renders no truth to write halves of "
                      "(give the truth's halves as reference.frames and frames_b)");
  return s;
}

std::string variant_name_problem(const std::string& name) {
  static const std::set<std::string> reserved = {"reference", "motion", "figures", "frames.csv", "summary.json",
                                                 "report.html", "records.jsonl", "contact_sheet.png",
                                                 "contact_sheet_zoom.png"};
  const bool chars_ok = !name.empty() && name.size() <= 100 &&
                        std::all_of(name.begin(), name.end(), [](char c) {
                          return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '+' ||
                                 c == '-';
                        });
  std::string shown;  // the name as a reader can see it: control characters escaped, at most 60 characters
  for (char c : name.substr(0, 60)) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned char>(c));
      shown += buf;
    } else {
      shown += c;
    }
  }
  if (name.size() > 60) shown += "...";
  const std::string allowed = " (it names a folder of the run and a row of frames.csv: 1 to 100 of A-Z a-z 0-9 . _ + -, "
                              "not starting with '.' or '-', not reference, reference-*, motion, figures or one of the "
                              "run's files)";
  if (!chars_ok || name[0] == '.' || name[0] == '-') return "\"" + shown + "\" is not allowed" + allowed;
  if (reserved.count(name) || name.rfind("reference-", 0) == 0)
    return "\"" + shown + "\" is one of the run folder's own names" + allowed;
  return "";
}

std::vector<std::string> builtin_experiment_names() {
  std::vector<std::string> out;
  std::error_code ec;
  const fs::path root(data_path("experiments/data"));
  for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->is_directory() && it->path().filename() == "paths") {  // camera paths, not experiments
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && it->path().extension() == ".json") {
      fs::path rel = it->path().lexically_relative(root);
      out.push_back((rel.parent_path() / rel.stem()).generic_string());  // e.g. "thesis/fig6-7-hdri-match"
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string resolve_experiment_path(const std::string& name_or_path) {
  std::error_code ec;  // an impossible name (too long, a loop) is just not a file
  if (fs::is_regular_file(name_or_path, ec)) return name_or_path;
  fs::path p = fs::path(data_path("experiments/data")) / (name_or_path + ".json");
  if (fs::is_regular_file(p, ec)) return p.string();
  std::string list;
  for (const auto& n : builtin_experiment_names()) list += (list.empty() ? "" : ", ") + n;
  throw ConfigError(name_or_path + ": no such experiment file, and not a built-in experiment (" + list + ")");
}

}  // namespace glintlab
