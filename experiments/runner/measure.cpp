#include "experiments/runner/measure.h"
#include "core/util/strings.h"

#include "core/util/allocator.h"
#include "core/util/content_hash.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/sources/motion_convention.h"
#include "experiments/sources/sequence.h"
#include "experiments/runner/frame_loop.h"
#include "experiments/runner/journal.h"
#include "experiments/runner/output_writers.h"
#include "experiments/runner/plan.h"
#include "experiments/runner/version.h"
#include "experiments/runner/work_schedule.h"
#include "experiments/sources/file_sources.h"
#include "experiments/spec/scene_setup.h"
#include "metrics/color/color_manager.h"
#include "metrics/color/measurement_space.h"
#include "metrics/frame_metrics.h"
#include "metrics/motion_check.h"
#include "metrics/pixel_scan.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace glintlab {

namespace {

// The truth's two halves (--reference, --reference-b; "frames", "frames_b") must be two independent
// estimates of one image: the same channels (a grey half beside an RGB one would be averaged into the
// truth) and the same colour space, and not the same files or the same bytes (the floor, half their
// difference, would read exactly 0). ConfigError naming both.
void check_halves(const FrameFiles& a, const FrameFiles& b) {
  const std::string both = "--reference '" + a.seq + "' and --reference-b '" + b.seq + "'";
  if (a.channels != b.channels)
    throw ConfigError(both + ": the halves have other channels (" + join(a.channels, ",") + " against " +
                      join(b.channels, ",") + "): two halves of one truth are images of one kind");
  if (a.space != b.space)
    throw ConfigError(both + ": the halves are in other colour spaces (" + a.space + " against " + b.space +
                      "): two halves of one truth are images of one kind");
  if (a.array || b.array) return;
  size_t same = 0;
  for (size_t k = 0; k < a.paths.size() && k < b.paths.size(); ++k) {
    std::error_code ec;
    const bool one_file = fs::equivalent(a.paths[k], b.paths[k], ec);
    if (one_file || (fs::file_size(a.paths[k], ec) == fs::file_size(b.paths[k], ec) && !ec &&
                     file_content_hash(a.paths[k]) == file_content_hash(b.paths[k])))
      ++same;
  }
  if (same > 0)
    throw ConfigError(both + ": " + std::to_string(same) + " of " + std::to_string(a.paths.size()) +
                      " frames are the same file or the same bytes in both halves; the truth's noise floor is half "
                      "the difference of two independent halves (of equal samples), which these would make 0");
}


// A test's name becomes a folder of previews: the one rule of variant names (experiment_spec.h).
void check_name(const std::string& name, const std::string& what) {
  if (const std::string why = variant_name_problem(name); !why.empty()) throw ConfigError(what + ": " + why);
}

// A name from a sequence's path: the folder's name, or the file pattern's text before its frame field.
std::string default_name(const SequenceSpec& seq) {
  fs::path p(seq.pattern);
  std::error_code ec;
  std::string base = fs::is_directory(p, ec) ? p.lexically_normal().filename().string() : p.filename().string();
  if (base.empty() || base == ".") base = fs::absolute(p).lexically_normal().filename().string();
  const size_t cut = base.find_first_of("%#");
  if (cut != std::string::npos && cut > 0) base = base.substr(0, cut);
  base = std::regex_replace(base, std::regex(R"([^A-Za-z0-9._+-])"), "_");
  while (!base.empty() && (base.back() == '.' || base.back() == '_' || base.back() == '-')) base.pop_back();
  base = base.substr(0, 100);
  if (!variant_name_problem(base).empty()) base = "test";
  return base;
}

// Lists `text`'s frames and picks those with the given numbers (every one must exist).
ChannelFiles resolve(const std::string& what, const std::string& text, const std::vector<int>& numbers) {
  ChannelFiles s;
  s.what = what;
  s.seq = parse_sequence(text, what);
  s.paths = frame_paths(s.seq, numbers, what);
  return s;
}

// The same for frames in memory: `count` frames, frame k the run's frame k.
ChannelFiles resolve(const std::string& what, std::shared_ptr<const FrameArray> array, size_t count) {
  check_array_frames(*array, count, what);
  ChannelFiles s;
  s.what = what;
  s.seq.text = array->name;
  for (size_t k = 0; k < count; ++k) s.paths.push_back(array_frame_name(*array, k));
  s.array = std::move(array);
  return s;
}

// What a source's journal and summary entries call it: its SEQ, or its array's name.
std::string source_text(const std::string& seq, const std::shared_ptr<const FrameArray>& array) {
  return array ? array->name : seq;
}

// The frames to measure: the base sequence's numbers within --frames, with no gap.
std::vector<int> select_numbers(const std::string& what, const std::string& text, int first, int last) {
  const SequenceSpec seq = parse_sequence(text, what);
  std::vector<int> all;
  for (const auto& f : list_frames(seq, what)) all.push_back(f.number);
  std::vector<int> out;
  for (int n : all)
    if (n >= first && n <= last) out.push_back(n);
  if (out.empty())
    throw ConfigError("--frames: " + what + " '" + text + "' has frames " + std::to_string(all.front()) + " to " +
                      std::to_string(all.back()) + ", none in " + std::to_string(first) + ":" + std::to_string(last));
  for (size_t i = 1; i < out.size(); ++i)
    if (out[i] != out[i - 1] + 1)
      throw ConfigError(what + ": '" + text + "' has a gap: frame " + std::to_string(out[i - 1] + 1) +
                        (out[i] - out[i - 1] > 2 ? " to " + std::to_string(out[i] - 1) : std::string()) +
                        " missing (flicker needs consecutive frames; measure the parts apart with --frames)");
  return out;
}

// Every frame of a source: one size, the channels present, within the pixel limit.
void check_headers(const ChannelFiles& s, int* width, int* height) {
  for (const auto& path : s.paths)
    check_frame_header(s.array ? array_header(*s.array) : read_frame_header(path), s.channels, s.what, path, width,
                       height);
}

// The layer of a file that holds a convention's vectors, for --motion-from: the colour layer's
// sibling ("ViewLayer.Combined" -> "ViewLayer.Vector"), else any layer with a vector layer name.
std::string vector_layer(MotionConvention c, const FrameHeader& h, const std::string& colour_layer) {
  const std::string parent = colour_layer.find('.') == std::string::npos
                                 ? std::string()
                                 : colour_layer.substr(0, colour_layer.rfind('.'));
  for (const auto& name : motion_layer_names(c)) {
    const std::string candidate = parent.empty() ? name : parent + "." + name;
    for (const auto& ch : h.channels)
      if (ch.rfind(candidate + ".", 0) == 0) return candidate;
  }
  for (const auto& ch : h.channels)
    for (const auto& name : motion_layer_names(c)) {
      const size_t at = ch.find(name + ".");
      if (at != std::string::npos && (at == 0 || ch[at - 1] == '.') && ch.find('.', at + name.size() + 1) == std::string::npos)
        return ch.substr(0, at + name.size());
    }
  return "";
}

struct Plan {
  std::optional<FrameFiles> reference, reference_b;
  std::vector<FrameFiles> tests;
  std::vector<std::string> test_names;
  std::optional<ChannelFiles> motion, depth;
  MotionConvention convention = MotionConvention::Pixels;
  MotionChannels motion_channels;
  std::vector<int> numbers;
  int width = 0, height = 0;
};

// Means of the motion check over the frames, from the journal (variant 0's rows).
struct MotionMeans final : RecordSink {
  metrics::MotionExplained sum;
  int n = 0, pairs = 0, empty_pairs = 0;
  size_t nonfinite = 0;
  void frame(const FrameRecord& r) override {
    if (r.variant != 0) return;
    std::map<std::string, double> m(r.metrics.begin(), r.metrics.end());
    auto get = [&](const char* k) { return m.count(k) ? m[k] : std::nan(""); };
    if (!r.sequence_start) {
      ++pairs;
      empty_pairs += get("flicker_valid_px") == 0;
    }
    if (get("motion_nonfinite_px") > 0) nonfinite += size_t(get("motion_nonfinite_px"));
    if (!std::isfinite(get("motion_explained"))) return;
    sum.given += get("motion_explained");
    sum.negated += get("motion_explained_negated");
    sum.flip_y += get("motion_explained_flip_y");
    sum.flip_x += get("motion_explained_flip_x");
    ++n;
  }
  metrics::MotionExplained mean() const {
    metrics::MotionExplained m;
    const double nan = std::nan("");
    m.given = n ? sum.given / n : nan;
    m.negated = n ? sum.negated / n : nan;
    m.flip_y = n ? sum.flip_y / n : nan;
    m.flip_x = n ? sum.flip_x / n : nan;
    return m;
  }
};


nlohmann::json num_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }


// What a measurement is, from its options and the files' headers, before any pixel is read.
struct Setup {
  Plan p;
  ExperimentSpec spec;
  nlohmann::json source;  // the run's description in the journal header
  std::string disocclusion, motion_kind, motion_source;
};

// The options alone, before any file is opened; their motion convention. ConfigError naming the option.
MotionConvention checked_options(const MeasureOptions& o) {
  if (o.tests.empty()) throw ConfigError("measure: give at least one --test [NAME=]SEQ");
  const bool arrays = o.reference_array || o.motion_array || o.depth_array ||
                      std::any_of(o.tests.begin(), o.tests.end(), [](const MeasureSource& t) { return bool(t.array); });
  if (arrays && (o.first != INT_MIN || o.last != INT_MAX))
    throw ConfigError("--frames: not allowed with frames in memory (an array's frame k is the run's frame k: "
                      "give the frames to measure)");
  if (arrays && !o.motion_from.empty())
    throw ConfigError("--motion-from: not allowed with frames in memory; give the vectors as their own array");
  if (o.tests.size() > 64) throw ConfigError("measure: at most 64 --test sequences");
  if (!(o.fps >= kMinFps && o.fps <= kMaxFps)) {
    std::ostringstream msg;
    msg << "--fps: " << o.fps << " is not allowed; allowed: frames per second in [" << kMinFps << ", " << kMaxFps
        << "]";
    throw ConfigError(msg.str());
  }
  if (o.first > o.last)
    throw ConfigError("--frames: FIRST " + std::to_string(o.first) + " is after LAST " + std::to_string(o.last));
  if ((!o.motion.empty() || o.motion_array) && !o.motion_from.empty())
    throw ConfigError("measure: give --motion SEQ or --motion-from, not both");
  if (!o.motion_from.empty() && o.motion_from != "reference" && o.motion_from != "test")
    throw ConfigError("--motion-from: '" + o.motion_from + "' is not allowed (reference or test)");
  if (!o.reference_b.empty() && o.reference.empty() && !o.reference_array)
    throw ConfigError("--reference-b: the reference's second half needs its first: give --reference SEQ too");
  if (o.motion_from == "reference" && o.reference.empty())
    throw ConfigError("--motion-from reference: there is no --reference");
  if ((!o.depth.empty() || o.depth_array) && o.motion.empty() && !o.motion_array && o.motion_from.empty())
    throw ConfigError("--depth: depth is for disocclusion along given vectors; give --motion or --motion-from too "
                      "(estimated flow uses forward-backward consistency)");
  auto c = enum_from_name(kMotionConventionNames, o.motion_convention);
  if (!c)
    throw ConfigError("--motion-convention: '" + o.motion_convention + "' is not known (allowed: " +
                      enum_name_list(kMotionConventionNames) + ")");
  return *c;
}

// The frame numbers (from the reference, or the first test), then every colour sequence opened: the
// reference, its second half and the tests, each with the frames of the base one.
void open_colour_sequences(const MeasureOptions& o, const metrics::ColorManager& cm, std::ostream& log, Plan& p) {
  // ---- the frames: numbers from the reference (or the first test), then every sequence resolved
  const bool range = o.first != INT_MIN || o.last != INT_MAX;
  const bool has_reference = !o.reference.empty() || o.reference_array;
  const std::string base = has_reference ? o.reference : o.tests[0].seq;
  const std::shared_ptr<const FrameArray>& base_array = has_reference ? o.reference_array : o.tests[0].array;
  if (base_array) {  // frames in memory are numbered from 0
    for (int k = 0; k < base_array->frames; ++k) p.numbers.push_back(k);
  } else {
    p.numbers = select_numbers(has_reference ? "--reference" : "--test", base, o.first, o.last);
  }
  if (p.numbers.empty() || p.numbers.size() > size_t(kMaxSequenceFrames))
    throw ConfigError("measure: " + std::to_string(p.numbers.size()) + " frames; allowed: 1 to " +
                      std::to_string(kMaxSequenceFrames));
  auto colour_source = [&](const std::string& what, const std::string& text, const std::string& space,
                           const std::shared_ptr<const FrameArray>& array) {
    const std::string in_space = space.empty() ? o.space : space;
    if (array) return open_colour_array(array, p.numbers.size(), in_space, cm, "measure: " + what, &p.width, &p.height, log);
    FrameFiles f = open_colour_sequence(text, p.numbers, in_space, cm, "measure: " + what, &p.width, &p.height, log);
    if (!range) {  // without --frames, every sequence has exactly the frames of the base one
      const auto all = list_frames(parse_sequence(text, what), what);
      if (all.size() != p.numbers.size())
        throw ConfigError(what + ": '" + text + "' has " +
                          frame_count_text(all.size(), all.front().number, all.back().number) + ", but " +
                          (has_reference ? "the reference" : "the first test") + " has " +
                          frame_count_text(p.numbers.size(), p.numbers.front(), p.numbers.back()) +
                          "; give --frames FIRST:LAST to measure a common range");
    }
    return f;
  };
  if (has_reference) p.reference = colour_source("--reference", o.reference, o.reference_space, o.reference_array);
  if (!o.reference_b.empty()) {
    p.reference_b = colour_source("--reference-b", o.reference_b, o.reference_space, nullptr);
    if (p.reference) check_halves(*p.reference, *p.reference_b);
  }
  std::set<std::string> names;
  for (const auto& t : o.tests) {
    const std::string name = !t.name.empty() ? t.name : t.array ? "test" : default_name(parse_sequence(t.seq, "--test"));
    check_name(name, "--test");
    if (!names.insert(name).second)
      throw ConfigError("--test: two tests are named '" + name + "'; name them: --test NAME=SEQ");
    p.tests.push_back(colour_source("--test " + name, t.seq, t.space, t.array));
    p.test_names.push_back(name);
  }
}

// The motion: the vector files (--motion, or --motion-from the colour files' vector layer) or optical
// flow; depth; and what disocclusion is decided by.
void resolve_motion(const MeasureOptions& o, Setup& s) {
  Plan& p = s.p;
  std::string &motion_kind = s.motion_kind, &motion_source = s.motion_source, &disocclusion = s.disocclusion;
  const std::string colour_of_motion = o.motion_from == "reference" ? o.reference
                                       : o.motion_from == "test"    ? o.tests[0].seq
                                                                    : std::string();
  if (!o.motion.empty() || o.motion_array || !colour_of_motion.empty()) {
    const std::string what = !colour_of_motion.empty() ? "--motion-from " + o.motion_from : "--motion";
    ChannelFiles m = o.motion_array ? resolve(what, o.motion_array, p.numbers.size())
                                    : resolve(what, colour_of_motion.empty() ? o.motion : colour_of_motion, p.numbers);
    const FrameHeader h = m.array ? array_header(*m.array) : read_frame_header(m.paths[0]);
    std::string layer = m.seq.layer;
    if (!colour_of_motion.empty()) {
      // Only a layer named for vectors: a colour layer's R and G are never read as motion.
      layer = vector_layer(p.convention, h, m.seq.layer);
      if (layer.empty()) {
        std::string names;
        for (const auto& n : motion_layer_names(p.convention)) names += (names.empty() ? "" : ", ") + n;
        throw ConfigError(m.what + ": '" + m.paths[0] + "' has no layer of " +
                          std::string(enum_name(kMotionConventionNames, p.convention)) + " vectors (a layer named " +
                          names + "; colour channels are never read as vectors); the file has: " +
                          channel_list(h) + ". Give the vectors' files with --motion SEQ, or no vectors "
                          "(optical flow)");
      }
    }
    p.motion_channels = motion_channels(p.convention, h, layer, m.paths[0]);
    m.channels = p.motion_channels.backward;
    m.channels.insert(m.channels.end(), p.motion_channels.forward.begin(), p.motion_channels.forward.end());
    m.channels.insert(m.channels.end(), p.motion_channels.distances.begin(), p.motion_channels.distances.end());
    p.motion = std::move(m);
    motion_kind = "exact";
    motion_source = p.motion->what + " " + (colour_of_motion.empty() ? source_text(o.motion, o.motion_array) : p.motion->seq.text) +
                    (layer.empty() ? std::string() : " (layer " + layer + ")");
  } else {
    motion_kind = "estimated";
    motion_source = std::string("optical flow (OpenCV DIS) of ") + (p.reference ? "the reference" : "the first test");
  }
  if (!o.depth.empty() || o.depth_array) {
    ChannelFiles d = o.depth_array ? resolve("--depth", o.depth_array, p.numbers.size()) : resolve("--depth", o.depth, p.numbers);
    const FrameHeader h = d.array ? array_header(*d.array) : read_frame_header(d.paths[0]);
    auto z = find_channels(h, d.seq.layer, {{"Z", "z", "Y", "R", "depth", "Depth", "Depth.Z"}});
    if (z[0].empty())
      throw ConfigError("--depth: '" + d.paths[0] + "' has no depth channel (Z, Y or R" +
                        (d.seq.layer.empty() ? std::string() : " of layer " + d.seq.layer) +
                        "); the file has: " + channel_list(h));
    d.channels = z;
    p.depth = std::move(d);
  }
  const bool distances = p.motion && !p.motion_channels.distances.empty();
  const bool fb = (p.motion && !p.motion_channels.forward.empty()) || motion_kind == "estimated";
  disocclusion = distances                    ? "glintlab's distance channels"
                 : p.depth && fb               ? "depth, and forward-backward consistency"
                 : p.depth                     ? "depth"
                 : fb                          ? "forward-backward consistency"
                                               : "off-screen only (no depth, no vectors to the next frame)";

  if (motion_kind == "estimated" && std::min(p.width, p.height) < 16)
    throw ConfigError("measure: no motion vectors given, and optical flow (OpenCV DIS) needs frames of at least "
                      "16 pixels on the short side (these are " + std::to_string(p.width) + "x" +
                      std::to_string(p.height) + "); give the renderer's vectors with --motion or --motion-from");
  if (motion_kind == "estimated" && std::max(p.width, p.height) < 46)
    throw ConfigError("measure: no motion vectors given, and optical flow (OpenCV DIS) needs frames of at least "
                      "46 pixels on the long side (these are " + std::to_string(p.width) + "x" +
                      std::to_string(p.height) + "); give the renderer's vectors with --motion or --motion-from");
  // ---- every header, before any pixel (the colour sequences' are checked as they are opened)
  if (p.motion) check_headers(*p.motion, &p.width, &p.height);
  if (p.depth) check_headers(*p.depth, &p.width, &p.height);

}

// The run as an experiment of file sources (one variant a test), and its description for the journal.
void describe_run(const MeasureOptions& o, const std::vector<std::string>& metric_list,
                  const std::vector<std::string>& per_pixel, const metrics::MetricOptions& selected, Setup& s) {
  Plan& p = s.p;
  nlohmann::json& source = s.source;
  ExperimentSpec& spec = s.spec;
  // ---- what the run is: options and the content of every file (the journal header)
  nlohmann::json tests = nlohmann::json::array();
  for (size_t i = 0; i < o.tests.size(); ++i)
    tests.push_back({{"name", p.test_names[i]}, {"frames", p.tests[i].seq}, {"space", p.tests[i].space}});
  source = {{"reference", source_text(o.reference, o.reference_array)},
            {"reference_space", p.reference ? p.reference->space : ""},
            {"reference_b", o.reference_b},
            {"tests", tests},
            {"motion", source_text(o.motion, o.motion_array)},
            {"motion_from", o.motion_from},
            {"motion_convention", o.motion_convention},
            {"depth", source_text(o.depth, o.depth_array)},
            {"metrics", metric_list},
            {"frames", {p.numbers.front(), p.numbers.back()}},
            {"fps", o.fps},
            {"name", o.name}};
  if (!o.display.empty()) source["view"] = o.display + "/" + o.view;  // what temporal_score saw

  spec.name = o.name;
  spec.file = o.file;
  spec.width = p.width;
  spec.height = p.height;
  spec.frames = int(p.numbers.size());
  spec.working_space = metrics::kXyzD65Space;  // inputs are converted from their own spaces once
  spec.metrics = per_pixel;
  spec.metric_options.glints = selected.glints;
  spec.metric_options.pooled = selected.pooled;
  spec.reference.enabled = bool(p.reference);
  spec.reference.grid = 0;
  spec.reference.frames = source_text(o.reference, o.reference_array);
  spec.reference.frames_b = o.reference_b;
  spec.output.exr = false;
  spec.output.png = o.report;  // previews are for the report: a CI job with --no-report writes none
  spec.output.every = std::max(1, int((p.numbers.size() + 7) / 8));  // at most 8 previews a sequence
  spec.output.contact_sheet = false;
  if (!o.display.empty()) spec.output.display = o.display;
  if (!o.view.empty()) spec.output.view = o.view;
  spec.output.exposure = o.exposure;
  for (size_t i = 0; i < p.tests.size(); ++i) {
    VariantSpec v;
    v.name = p.test_names[i];
    v.frames = p.tests[i].seq;
    spec.variants.push_back(v);
  }
  spec.source = source;
}

// Everything the options and the headers say; ConfigError or std::invalid_argument on bad input.
Setup resolve_measurement(const MeasureOptions& o, const metrics::ColorManager& cm, std::ostream& log) {
  Setup s;
  s.p.convention = checked_options(o);
  std::vector<std::string> metric_list = o.metrics.empty() ? std::vector<std::string>{"deltaE2000", "flip"} : o.metrics;
  metrics::MetricOptions selected;
  std::vector<std::string> per_pixel;
  try {
    per_pixel = metrics::select_metrics(metric_list, selected);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("--metrics: ") + e.what());
  }
  if (!o.space.empty()) (void)cm.canonical_name(o.space);
  check_name(o.name, "--name");
  if (!o.display.empty() || !o.view.empty()) {  // --view: the previews' and temporal_score's display
    const std::string problem = display_view_problem(cm, o.display, o.view);
    if (!problem.empty()) throw ConfigError("--view: " + problem);
  }

  open_colour_sequences(o, cm, log, s.p);
  resolve_motion(o, s);
  describe_run(o, metric_list, per_pixel, selected, s);
  return s;
}

// The journal's header: what the run is, and the content hash of every file it reads (its identity:
// --resume continues only the same run).
nlohmann::json journal_header(const Setup& s, const metrics::ColorManager& cm) {
  const Plan& p = s.p;
  nlohmann::json hashes = nlohmann::json::object();
  auto add_hashes = [&](const auto& files) {
    if (files.array) {
      hashes[files.array->name] = array_content_hash(*files.array);
      return;
    }
    for (const auto& path : files.paths)
      if (!hashes.contains(path)) hashes[path] = file_content_hash(path);
  };
  if (p.reference) add_hashes(*p.reference);
  if (p.reference_b) add_hashes(*p.reference_b);
  for (const auto& t : p.tests) add_hashes(t);
  if (p.motion) add_hashes(*p.motion);
  if (p.depth) add_hashes(*p.depth);
  return {{"type", "run"},
          {"glintlab_version", version()},
          {"command", "measure"},
          {"file", ""},
          {"source", s.source},
          {"content_hash", core::hash_hex(dump_json(s.source))},
          {"inputs", hashes},
          {"ocio_config", file_content_hash(cm.config_path())},
          {"overrides", nlohmann::json::object()},
          {"shard", {0, 1}}};
}

// The run's plan: one variant a test, read from its files, each measured against the one reference (if
// any).
RunPlan measure_plan(const Setup& s) {
  RunPlan plan;
  plan.spec = &s.spec;
  plan.frames = s.spec.frames;
  plan.measure = true;
  for (size_t i = 0; i < s.spec.variants.size(); ++i) {
    RunPlan::Variant pv;
    pv.spec = &s.spec.variants[i];
    pv.reference = s.p.reference ? 0 : -1;
    pv.files = s.p.tests[i];
    plan.variants.push_back(pv);
  }
  if (s.p.reference) {
    RunPlan::Reference r;
    r.name = "reference";
    r.files = s.p.reference;
    for (size_t i = 0; i < plan.variants.size(); ++i) r.variants.push_back(int(i));
    plan.references.push_back(r);
  }
  return plan;
}

// The frame loop's sources: every test's files, the reference's (one sequence or two halves), the
// vectors' files or optical flow; frame k at k / fps seconds, called by its number in the files.
LoopSources measure_sources(const Setup& s, const MeasureOptions& o, const metrics::ColorManager& cm,
                            const metrics::FrameMetrics& frame_metrics) {
  const Plan& p = s.p;
  LoopSources src;
  for (const auto& t : p.tests) src.variants.push_back(file_sequence(t, cm, metrics::kXyzD65Space));
  if (p.reference)
    src.references.push_back(file_reference(*p.reference, p.reference_b, cm, metrics::kXyzD65Space, &frame_metrics,
                                            p.tests.size() > 1));
  src.motion = p.motion ? file_motion(*p.motion, p.depth, p.convention, p.motion_channels)
                        : estimated_motion(p.width, p.height);
  src.clock = [numbers = p.numbers, fps = o.fps](int k) { return FrameClock{k / fps, false, numbers[size_t(k)]}; };
  src.check_motion = true;
  return src;
}

// The outputs, from the journal: frames.csv, summary.json with the motion check over the run and its
// warnings, the report; the console's lines. kExitDefect where a frame had NaN, Inf or negative pixels.
int write_measure_outputs(const Setup& s, const MeasureOptions& o, const RunPlan& plan, Journal& journal_in,
                          ImageWriter& images, const metrics::ColorManager& cm, const fs::path& out_dir,
                          std::ostream& log) {
  const Plan& p = s.p;
  const nlohmann::json& source = s.source;
  const std::string &motion_kind = s.motion_kind, &motion_source = s.motion_source, &disocclusion = s.disocclusion;
  Journal* journal = &journal_in;
  // ---- outputs, from the journal; the motion check over the run
  MotionMeans mm;
  journal->replay(mm);
  const metrics::MotionExplained mean = mm.mean();
  const std::string warning = metrics::motion_warning(mean);
  nlohmann::json warnings = nlohmann::json::array();
  if (!warning.empty()) warnings.push_back(warning);
  if (mm.empty_pairs > 0)
    warnings.push_back(std::to_string(mm.empty_pairs) + " of " + std::to_string(mm.pairs) +
                       " frame pairs have no pixel along the motion (every pixel background, disoccluded or "
                       "off-screen): are the vectors and distances what the convention says?");
  if (mm.nonfinite > 0)
    warnings.push_back(std::to_string(mm.nonfinite) + " motion vector values are NaN or Inf (those pixels are left out)");
  nlohmann::json extra = {
      {"command", "measure"},
      {"motion", motion_kind},
      {"motion_source", motion_source},
      {"motion_convention", motion_kind == "exact" ? nlohmann::json(o.motion_convention) : nlohmann::json(nullptr)},
      {"disocclusion", disocclusion},
      {"motion_explained",
       {{"mean", num_or_null(mean.given)},
        {"negated", num_or_null(mean.negated)},
        {"flip_y", num_or_null(mean.flip_y)},
        {"flip_x", num_or_null(mean.flip_x)},
        {"frames", mm.n},
        {"meaning", "mean |dR| along the vectors / at a fixed pixel (PQ luminance of the reference, or of the first "
                    "test without one): 0 = the vectors explain all of its change, 1 = no more than no motion"}}},
      {"warnings", warnings},
      {"frame_numbers", {p.numbers.front(), p.numbers.back()}},
      {"fps", o.fps},
      {"sources", source}};
  for (const auto& w : warnings) log << "warning: " << w.get<std::string>() << "\n";
  int report_status = kExitOk;
  const nlohmann::json summary = write_run_outputs(out_dir, plan, {journal},
                                                   RunInfo{"", cm.config_path(), 0, extra}, images, o.report,
                                                   &report_status, log);
  for (const auto& v : summary["variants"]) {
    const auto& m = v["metrics"];
    auto mean_of = [&](const char* n) -> std::string {
      if (!m.contains(n) || m[n]["mean"].is_null()) return "-";
      std::ostringstream s;
      s << std::setprecision(4) << m[n]["mean"].get<double>();
      return s.str();
    };
    log << "  " << std::left << std::setw(20) << v["name"].get<std::string>() << std::right
        << " deltaE2000 " << std::setw(9) << mean_of("deltaE2000") << "  flicker_ratio " << std::setw(9)
        << mean_of("flicker_ratio") << "  temporal_score " << std::setw(10) << mean_of("temporal_score")
        << "  flicker_contrast " << std::setw(9) << mean_of("flicker_contrast") << "\n";
  }
  for (const auto& r : summary["references"]) {
    if (!r.contains("floor")) {
      log << "  no floor (the reference is one estimate: --reference-b SEQ gives its second half)\n";
      continue;
    }
    log << "  floor (the truth's noise)";
    for (const char* n : {"deltaE2000", "temporal_score", "flicker_excess", "temporal_lag"})
      if (r["floor"].contains(n) && r["floor"][n].is_number())
        log << "  " << n << " " << std::setprecision(4) << r["floor"][n].get<double>();
    log << "\n";
  }
  DefectCount defects;
  journal->replay(defects);
  if (defects.frames + defects.reference_frames > 0) {
    log << "error: " << defects.frames << " test frame(s) had NaN, Inf or negative pixels and "
        << defects.reference_frames << " were measured against a reference frame with some (see frames.csv); "
        << "their metrics are NaN\n";
    return kExitDefect;
  }
  return report_status;
}

}  // namespace

int measure_sequences(const MeasureOptions& o, std::ostream& log) {
  share_one_heap_between_threads();  // frames are decoded on one thread and freed on another
  const metrics::ColorManager cm = load_color_manager(o.ocio_config);
  Setup s;
  if (const int code = run_guarded([&] { s = resolve_measurement(o, cm, log); return int(kExitOk); }, log);
      code != kExitOk)
    return code;
  const Plan& p = s.p;
  const ExperimentSpec& spec = s.spec;
  const metrics::FrameMetrics frame_metrics(cm, spec.working_space, spec.metrics, spec.measured_metric_options());
  // The loop's working set in 2 MiB pages: at most about 280 bytes a pixel and 70 more for each test
  // (peak resident memory at 1920x1080: 570 MB with one test, whose reference's L*a*b* is not kept,
  // 796 MB with two), at most what one call takes.
  reserve_heap_in_huge_pages(
      std::min(size_t(p.width) * size_t(p.height) * (280 + 70 * p.tests.size()), kMaxHugeReservation));

  // A new run's first frame is read while the journal's header hashes every input file.
  LoopSources sources = measure_sources(s, o, cm, frame_metrics);
  if (!o.resume) {
    for (auto* list : {&sources.variants, &sources.references})
      for (auto& source : *list) source->read_ahead(0);
    sources.motion->read_ahead(0);
  }
  const fs::path out_dir(o.out_dir);
  fs::create_directories(out_dir);
  std::unique_ptr<Journal> journal;
  const RunPlan plan = measure_plan(s);
  if (const int code = run_guarded(
          [&] {
            journal = std::make_unique<Journal>(out_dir, journal_header(s, cm), o.resume);
            journal->check_shape(int(plan.variants.size()), plan.frames, int(plan.references.size()));
            return int(kExitOk);
          },
          log);
      code != kExitOk)
    return code;
  log << "measure: " << p.tests.size() << " test sequence(s)" << (p.reference ? " against a reference" : ", no reference")
      << ", frames " << p.numbers.front() << " to " << p.numbers.back() << " at " << p.width << "x" << p.height
      << "; motion " << s.motion_kind << " (" << s.motion_source << "); disocclusion: " << s.disocclusion << "\n";
  if (p.reference_b)
    log << "noise floor: the reference's two halves (--reference and --reference-b): the truth is their mean, "
           "each metric's floor half their difference (frames.csv floor_*, summary.json references[].floor)\n";
  else if (p.reference)
    log << "no floor: the reference is one estimate; give it as two independent halves (--reference-b SEQ) for "
           "its noise floor\n";
  if (s.motion_kind == "estimated")
    log << "note: no motion vectors given: flicker is measured along optical flow estimated from "
        << (p.reference ? "the reference" : "the first test") << ", marked \"motion\": \"estimated\"\n";

  // ---- the frames the journal lacks (and the frame before each, for the temporal state), by the run's loop
  const WorkSchedule work = schedule_work(plan, *journal, 0, plan.frames);
  if (o.resume) log << "resume: " << journal->frames().size() << " frame record(s) done\n";
  ImageWriter images(out_dir, plan, cm);
  if (work.last_frame >= 0) {
    FrameLoop loop(plan, std::move(sources), &frame_metrics, log);
    loop.run(work, {journal.get(), &images});
  }
  return write_measure_outputs(s, o, plan, *journal, images, cm, out_dir, log);
}

}  // namespace glintlab
