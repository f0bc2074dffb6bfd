#include "experiments/cli/compare.h"
#include "core/util/strings.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/util/atomic_file.h"
#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/sources/exr_scanlines.h"
#include "metrics/color/color_manager.h"
#include "metrics/color/image_io.h"
#include "metrics/color/measurement_space.h"
#include "metrics/flip.h"
#include "metrics/flip_pooling.h"
#include "metrics/metric_registry.h"
#include "metrics/pixel_scan.h"

namespace glintlab {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string size_str(const Image& img) { return std::to_string(img.width) + "x" + std::to_string(img.height); }

std::string num_str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Per pixel: true where any of the first three channels is NaN, infinite or negative.
std::vector<bool> bad_pixels(const Image& img) {
  const int nc = std::min(img.channels, 3);
  std::vector<bool> bad(img.pixel_count(), false);
  for (std::size_t i = 0; i < bad.size(); ++i)
    for (int c = 0; c < nc; ++c) {
      const float v = img.data[i * img.channels + c];
      if (!std::isfinite(v) || v < 0.0f) bad[i] = true;
    }
  return bad;
}

// The RGBA image metrics::read_image makes of a file with `in.channels` channels, from pixels in
// memory: grey (1, 2) to R, G and B, alpha 1 where there is none.
Image rgba_of(const CompareImage& in) {
  const int c = in.channels;
  if (c < 1 || c > 4 || in.width < 1 || in.height < 1)
    throw std::invalid_argument("'" + in.path + "': pixels of " + std::to_string(in.width) + "x" +
                                std::to_string(in.height) + "x" + std::to_string(c) +
                                "; allowed: at least 1x1, with 1 to 4 channels");
  Image img = Image::unfilled(in.width, in.height, 4);
  const float* src = in.pixels;
  float* dst = img.data.data();
  for (std::size_t i = 0, n = img.pixel_count(); i < n; ++i, src += c, dst += 4) {
    dst[0] = src[0];
    dst[1] = c >= 3 ? src[1] : src[0];
    dst[2] = c >= 3 ? src[2] : src[0];
    dst[3] = c == 2 ? src[1] : c == 4 ? src[3] : 1.0f;
  }
  return img;
}

std::size_t nonfinite_pixels(const Image& img) {
  const metrics::PixelScan s = metrics::scan_pixels(img, 3);
  return s.nan + s.infinite;  // a pixel can be in both: an upper bound of the count, > 0 exactly when any
}

nlohmann::json scan_json(const metrics::PixelScan& s) {
  return {{"pixels", s.pixels}, {"nan", s.nan}, {"inf", s.infinite}, {"negative", s.negative}};
}

std::string scan_text(const metrics::PixelScan& s) {
  return std::to_string(s.nan) + " NaN, " + std::to_string(s.infinite) + " Inf, " + std::to_string(s.negative) +
         " negative (of " + std::to_string(s.pixels) + " pixels)";
}

nlohmann::json num_json(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string csv_num(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s << std::setprecision(7) << v;
  return s.str();
}

std::string csv_field(const std::string& s) {  // RFC 4180 quoting where needed
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

nlohmann::json flip_settings_json(const CompareFlipSetup& f) {
  nlohmann::json j = {{"mode", f.hdr ? "hdr" : "ldr"}, {"ppd", f.ppd}};
  if (f.hdr) {
    j["tone_mapper"] = enum_name(metrics::kFlipToneMapperNames, f.hdr_options.tone_mapper);
    j["start_exposure"] = num_json(f.exposures.start);
    j["stop_exposure"] = num_json(f.exposures.stop);
    j["num_exposures"] = f.exposures.count;
  }
  return j;
}

std::string flip_settings_text(const CompareFlipSetup& f) {
  std::ostringstream s;
  s << (f.hdr ? "HDR-FLIP" : "LDR-FLIP") << ", " << f.ppd << " px/deg";
  if (f.hdr)
    s << ", tone mapper " << enum_name(metrics::kFlipToneMapperNames, f.hdr_options.tone_mapper) << ", exposures "
      << f.exposures.start << " to " << f.exposures.stop << " (" << f.exposures.count << ")";
  return s.str();
}

nlohmann::json metrics_json(const CompareTest& t) {
  nlohmann::json j = nlohmann::json::object();
  for (const CompareMetric& e : t.metrics) {
    nlohmann::json m = {{"mean", num_json(e.result.mean)}, {"max", num_json(e.result.max)}, {"p95", num_json(e.p95)}};
    if (e.is_flip) {
      m["min"] = num_json(e.pooled.min);
      m["weighted_median"] = num_json(e.pooled.weighted_median);
      m["weighted_quartile_1"] = num_json(e.pooled.weighted_quartile_1);
      m["weighted_quartile_3"] = num_json(e.pooled.weighted_quartile_3);
    }
    j[e.result.name] = m;
  }
  return j;
}

void print_text(const CompareTest& t, const CompareInput& ref, const CompareFlipSetup& flip, const std::string& indent,
                std::ostream& out) {
  if (!t.input.scan.clean()) out << indent << "input test '" << t.input.path << "': " << scan_text(t.input.scan) << "\n";
  if (!ref.scan.clean()) out << indent << "input ref '" << ref.path << "': " << scan_text(ref.scan) << "\n";
  for (const CompareMetric& e : t.metrics) {
    const metrics::MetricResult& r = e.result;
    out << indent << r.name << ": mean " << r.mean << " " << r.unit << ", max " << r.max << " " << r.unit << "\n";
    if (e.is_flip) {
      const metrics::FlipPooled& p = e.pooled;
      out << indent << "  weighted median " << p.weighted_median << ", 1st weighted quartile " << p.weighted_quartile_1
          << ", 3rd weighted quartile " << p.weighted_quartile_3 << ", min " << p.min << ", max " << p.max << "\n";
      out << indent << "  " << flip_settings_text(flip) << "\n";
    }
  }
}

std::string csv_table(const std::vector<CompareTest>& results, const CompareInput& ref) {
  std::ostringstream s;
  s << "reference,test,metric,unit,mean,max,min,weighted_median,weighted_quartile_1,weighted_quartile_3,"
       "test_nan,test_inf,test_negative,ref_nan,ref_inf,ref_negative\n";
  for (const CompareTest& t : results)
    for (const CompareMetric& e : t.metrics) {
      const metrics::MetricResult& r = e.result;
      s << csv_field(ref.path) << "," << csv_field(t.input.path) << "," << csv_field(r.name) << "," << csv_field(r.unit)
        << "," << csv_num(r.mean) << "," << csv_num(r.max) << ",";
      if (e.is_flip)
        s << csv_num(e.pooled.min) << "," << csv_num(e.pooled.weighted_median) << ","
          << csv_num(e.pooled.weighted_quartile_1) << "," << csv_num(e.pooled.weighted_quartile_3) << ",";
      else
        s << ",,,,";
      s << t.input.scan.nan << "," << t.input.scan.infinite << "," << t.input.scan.negative << "," << ref.scan.nan << ","
        << ref.scan.infinite << "," << ref.scan.negative << "\n";
    }
  return s.str();
}

// Option checks: the message names the option and what it allows; empty when fine.
std::string check_positive(double v, const char* option, const char* what) {
  if (std::isnan(v) || (v > 0.0 && std::isfinite(v))) return {};
  return std::string(option) + " must be a finite number > 0 (" + what + "), got " + num_str(v);
}

// Bad input: what the CLI exits 2 for (cli/exit_codes.h).
std::invalid_argument bad_input(const std::string& msg) { return std::invalid_argument(msg); }

// The metric names asked for (all by default), each known. std::invalid_argument naming the allowed.
std::vector<std::string> checked_metric_names(const CompareOptions& o) {
  std::vector<std::string> names = o.metrics.empty() ? metrics::metric_names() : o.metrics;
  const std::vector<std::string> known = metrics::metric_names();
  for (const auto& n : names)
    if (std::find(known.begin(), known.end(), n) == known.end())
      throw bad_input("unknown metric '" + n + "'; allowed: " + join(known));
  if (names.empty()) throw bad_input("no metrics registered");
  if (!(o.itp_nits > 0.0) || !std::isfinite(o.itp_nits))
    throw bad_input("--itp-nits must be a positive number of cd/m^2, got " + num_str(o.itp_nits));
  return names;
}

// FLIP's viewing conditions and HDR settings from the options, each checked (std::invalid_argument
// naming the option); the exposures are resolved later, from the reference.
CompareFlipSetup checked_flip_setup(const CompareOptions& o, bool want_flip, std::ostream& err) {
  CompareFlipSetup flip;
  flip.hdr = !o.flip_ldr;
  for (const std::string& m : {check_positive(o.ppd, "--ppd", "pixels per degree"),
                               check_positive(o.monitor_distance, "--monitor-distance", "metres"),
                               check_positive(o.monitor_width, "--monitor-width", "metres"),
                               check_positive(o.monitor_width_pixels, "--monitor-width-pixels", "pixels")})
    if (!m.empty()) throw bad_input(m);
  const bool viewing = !std::isnan(o.monitor_distance) || !std::isnan(o.monitor_width) ||
                       !std::isnan(o.monitor_width_pixels);
  if (!std::isnan(o.ppd) && viewing)
    throw bad_input("--ppd and --monitor-distance/--monitor-width/--monitor-width-pixels both set the pixels per "
                    "degree: give one or the other");
  flip.ppd = !std::isnan(o.ppd) ? o.ppd
                                : metrics::flip_pixels_per_degree(
                                      std::isnan(o.monitor_distance) ? metrics::kFlipDefaultMonitorDistance : o.monitor_distance,
                                      std::isnan(o.monitor_width) ? metrics::kFlipDefaultMonitorWidth : o.monitor_width,
                                      std::isnan(o.monitor_width_pixels) ? metrics::kFlipDefaultMonitorWidthPixels
                                                                         : o.monitor_width_pixels);
  if (!(flip.ppd <= metrics::kFlipMaxPpd))
    throw bad_input((!std::isnan(o.ppd) ? std::string("--ppd") : std::string("--monitor-distance/--monitor-width/--monitor-width-pixels")) +
                    " give " + num_str(flip.ppd) + " pixels per degree; allowed: up to " + num_str(metrics::kFlipMaxPpd));
  if (!o.tone_mapper.empty()) {
    const std::string tm = ascii_lower(o.tone_mapper);
    const auto v = enum_from_name(metrics::kFlipToneMapperNames, tm);
    if (!v)
      throw bad_input("--tone-mapper must be one of " + enum_name_list(metrics::kFlipToneMapperNames) +
                      " (any case), got '" + o.tone_mapper + "'");
    flip.hdr_options.tone_mapper = *v;
  }
  if (std::isinf(o.start_exposure)) throw bad_input("--start-exposure must be a finite number of stops");
  if (std::isinf(o.stop_exposure)) throw bad_input("--stop-exposure must be a finite number of stops");
  if (o.num_exposures < 0)
    throw bad_input("--num-exposures must be an integer >= 1, got " + std::to_string(o.num_exposures));
  if (!std::isnan(o.start_exposure) && !std::isnan(o.stop_exposure) && o.start_exposure > o.stop_exposure)
    throw bad_input("--start-exposure (" + num_str(o.start_exposure) + ") must not be above --stop-exposure (" +
                    num_str(o.stop_exposure) + ")");
  flip.hdr_options.start_exposure = o.start_exposure;
  flip.hdr_options.stop_exposure = o.stop_exposure;
  flip.hdr_options.num_exposures = o.num_exposures;
  const bool hdr_options_given = !o.tone_mapper.empty() || !std::isnan(o.start_exposure) ||
                                 !std::isnan(o.stop_exposure) || o.num_exposures != 0;
  if (o.flip_ldr && hdr_options_given)
    throw bad_input("--tone-mapper, --start-exposure, --stop-exposure and --num-exposures are HDR-FLIP settings; "
                    "they do not go with --flip-ldr");
  if (!std::isnan(o.threshold) && !(o.threshold >= 0.0 && o.threshold <= 1.0))
    throw bad_input("--threshold must be a number in [0, 1] (a mean FLIP error), got " + num_str(o.threshold));
  if (!std::isnan(o.threshold) && !want_flip)
    throw bad_input("--threshold tests the mean FLIP error, but --metric leaves out flip; add --metric flip");
  if (!want_flip && (hdr_options_given || o.flip_ldr || !std::isnan(o.ppd) || viewing))
    err << "compare: warning: FLIP options given, but --metric leaves out flip; they are ignored\n";

  return flip;
}

// One test against the reference: every metric asked for, NaN where an input has bad pixels, and
// whether the mean FLIP error is above --threshold (said on err).
void compare_test(const CompareOptions& o, const std::vector<std::string>& names, const CompareFlipSetup& flip,
                  const metrics::HdrFlipOptions& resolved, const metrics::MetricOptions& mo, const CompareInput& ref,
                  bool clean_pair, CompareTest& tr, std::ostream& err) {
  const CompareInput& test = tr.input;
  tr.clean = clean_pair;
  for (const auto& n : names) {
    CompareMetric e;
    if (n == "flip") {
      e.is_flip = true;
      e.result.name = n;
      e.result.unit = "FLIP";
      e.result.map = flip.hdr ? metrics::hdr_flip_map(test.xyz, ref.xyz, flip.ppd, resolved)
                              : metrics::ldr_flip_map(test.xyz, ref.xyz, flip.ppd);
      e.pooled = metrics::flip_pooled(e.result.map);
      e.result.mean = e.pooled.mean;
      e.result.max = e.pooled.max;
    } else {
      e.result = metrics::evaluate_metric(n, test.xyz, ref.xyz, mo);
    }
    if (n != "psnr") e.p95 = metrics::map_percentile(e.result.map, 0.95);
    if (!tr.clean) {
      e.result.mean = e.result.max = e.p95 = kNaN;
      e.pooled.mean = e.pooled.weighted_median = e.pooled.weighted_quartile_1 = e.pooled.weighted_quartile_3 =
          e.pooled.min = e.pooled.max = kNaN;
    }
    if (e.is_flip && !std::isnan(o.threshold) && e.result.mean > o.threshold) tr.threshold_exceeded = true;
    tr.metrics.push_back(std::move(e));
  }
  if (!tr.clean)
    err << "compare: test '" << test.path << "' against '" << ref.path
        << "': NaN, Inf or negative input pixels, so every metric is NaN\n";
  if (tr.threshold_exceeded) {
    const double m = std::find_if(tr.metrics.begin(), tr.metrics.end(), [](const CompareMetric& e) {
                       return e.is_flip;
                     })->result.mean;
    err << "compare: mean FLIP error of '" << test.path << "' is " << m << ", above --threshold " << o.threshold
        << "\n";
  }
}

}  // namespace

Comparison compare_images(const CompareOptions& o, const CompareImage& ref_image, const std::vector<CompareImage>& test_images,
                          std::ostream& err) {

  // ---- options (bad input)
  if (test_images.empty() || (ref_image.path.empty() && !ref_image.pixels))
    throw bad_input("need a test image and a reference: `compare TEST REF` or `compare --reference REF --test TEST "
                    "[TEST ...]`");
  for (const CompareImage& t : test_images)
    if (t.path.empty() && !t.pixels) throw bad_input("empty test image path");
  const std::vector<std::string> names = checked_metric_names(o);
  Comparison c;
  c.want_flip = std::find(names.begin(), names.end(), "flip") != names.end();
  c.threshold = o.threshold;
  const bool want_flip = c.want_flip;
  c.flip = checked_flip_setup(o, want_flip, err);
  CompareFlipSetup& flip = c.flip;

  metrics::MetricOptions mo;
  mo.itp_luminance_nits = o.itp_nits;
  mo.display_view = o.display_view;
  mo.flip_hdr = flip.hdr;
  mo.flip_ppd = flip.ppd;

  // ---- inputs (bad input): every image is read and checked before anything is computed
  CompareInput& ref = c.ref;
  c.tests.resize(test_images.size());
  try {
    if (!o.display_view.empty()) (void)metrics::parse_display_view(o.display_view);
    const metrics::ColorManager cm(o.ocio_config.empty() ? metrics::ColorManager::default_config_path()
                                                         : o.ocio_config);
    if (!o.space.empty()) (void)cm.canonical_name(o.space);  // unknown --space: error before reading
    auto load = [&](CompareInput& in, const CompareImage& source, const std::string& what) {
      std::string tag = source.tag;
      int channels = source.channels;
      in.path = source.path;
      // The input as RGBA, then in XYZ in place: the one image an input becomes (CompareImage).
      Image img = source.pixels ? rgba_of(source) : read_image_file(source.path, &tag, &channels);
      if (channels < 3)  // said, never silent: what the file's channels are taken for
        err << "compare: " << what << " '" << in.path << "' has " << channels << " channel" << (channels == 1 ? "" : "s")
            << ": read as grey" << (channels == 2 ? " (the first) and alpha (the second)" : "") << "\n";
      in.scan = metrics::scan_pixels(img, 3);
      in.bad = bad_pixels(img);
      const std::string from = metrics::input_space(cm, o.space, tag, "compare: " + what, in.path, err);
      if (mo.display_view.empty()) {
        cm.convert(img, from, metrics::kXyzD65Space);  // what metric_xyz gives, without its copy
        in.xyz = std::move(img);
      } else {
        in.xyz = metrics::metric_xyz(cm, img, from, mo);
      }
      if (in.scan.nan + in.scan.infinite == 0) in.converted_bad = nonfinite_pixels(in.xyz);
    };
    load(ref, ref_image, "reference");
    for (std::size_t i = 0; i < c.tests.size(); ++i) {
      CompareInput& t = c.tests[i].input;
      load(t, test_images[i], "test");
      if (!t.xyz.same_size(ref.xyz))
        throw bad_input("image sizes differ: test '" + t.path + "' is " + size_str(t.xyz) + ", reference '" +
                        ref.path + "' is " + size_str(ref.xyz));
    }
    if (want_flip && flip.hdr) {
      // One exposure given, the other from the reference: they must still be in order.
      const bool start_given = !std::isnan(o.start_exposure), stop_given = !std::isnan(o.stop_exposure);
      if (start_given != stop_given) {
        const metrics::HdrFlipExposures a = metrics::hdr_flip_exposures(ref.xyz, flip.hdr_options.tone_mapper);
        if (start_given && o.start_exposure > a.stop)
          throw bad_input("--start-exposure (" + num_str(o.start_exposure) + ") is above the stop exposure " +
                          num_str(a.stop) + " computed from the reference '" + ref.path + "'; give --stop-exposure too");
        if (stop_given && o.stop_exposure < a.start)
          throw bad_input("--stop-exposure (" + num_str(o.stop_exposure) + ") is below the start exposure " +
                          num_str(a.start) + " computed from the reference '" + ref.path +
                          "'; give --start-exposure too");
      }
      flip.exposures = metrics::resolve_hdr_flip_exposures(ref.xyz, flip.hdr_options);
    }
  } catch (const IoError&) {
    throw;  // the system's reason
  } catch (const std::invalid_argument&) {
    throw;
  } catch (const std::exception& e) {
    throw bad_input(e.what());
  }

  // ---- bad pixels: reported on err; the metrics of that comparison become NaN (compare.h)
  auto report = [&](const CompareInput& in, const char* what) {
    if (!in.scan.clean())
      err << "compare: " << what << " '" << in.path << "' has " << scan_text(in.scan) << "\n";
    if (in.converted_bad)
      err << "compare: " << what << " '" << in.path << "' gives " << in.converted_bad
          << " non-finite pixels after colour conversion\n";
  };
  auto clean = [](const CompareInput& in) { return in.scan.clean() && in.converted_bad == 0; };
  report(ref, "reference");
  for (const CompareTest& t : c.tests) report(t.input, "test");

  // ---- metrics (HDR-FLIP: the exposures resolved once, from the reference, for every test image)
  metrics::HdrFlipOptions resolved = flip.hdr_options;
  resolved.start_exposure = flip.exposures.start;
  resolved.stop_exposure = flip.exposures.stop;
  resolved.num_exposures = flip.exposures.count;
  for (CompareTest& tr : c.tests)
    compare_test(o, names, flip, resolved, mo, ref, clean(tr.input) && clean(ref), tr, err);
  return c;
}

nlohmann::json comparison_json(const Comparison& c) {
  nlohmann::json j;
  auto test_json = [&](const CompareTest& t, nlohmann::json& into) {
    into["test"] = t.input.path;
    into["metrics"] = metrics_json(t);
    into["input"] = {{"test", scan_json(t.input.scan)}, {"ref", scan_json(c.ref.scan)}};
    if (!std::isnan(c.threshold)) into["threshold_exceeded"] = t.threshold_exceeded;
  };
  j["reference"] = c.ref.path;
  if (c.want_flip) j["flip"] = flip_settings_json(c.flip);
  if (c.tests.size() == 1) {
    test_json(c.tests.front(), j);
  } else {
    j["tests"] = nlohmann::json::array();
    for (const CompareTest& t : c.tests) {
      nlohmann::json tj;
      test_json(t, tj);
      j["tests"].push_back(tj);
    }
  }
  return j;
}

Image comparison_map(const Comparison& c, std::size_t test, std::size_t metric) {
  const CompareTest& t = c.tests.at(test);
  const Image& full = t.metrics.at(metric).result.map;
  if (full.empty()) return {};
  Image map = Image::unfilled(full.width, full.height, 1);
  for (std::size_t p = 0; p < map.pixel_count(); ++p)
    map.data[p] = (t.input.bad[p] || c.ref.bad[p]) ? std::numeric_limits<float>::quiet_NaN()
                                                   : full.data[p * std::size_t(full.channels)];
  return map;
}

int comparison_exit_code(const Comparison& c) {
  for (const CompareTest& t : c.tests)
    if (!t.clean || t.threshold_exceeded) return kExitDefect;
  return kExitOk;
}

int run_compare(const CompareOptions& o, std::ostream& out, std::ostream& err) {
  auto bad_input = [&](const std::string& msg) {
    err << "compare: " << msg << "\n";
    return int(kExitBadInput);
  };
  std::vector<CompareImage> tests;
  if (!o.test.empty()) tests.push_back({o.test});
  for (const auto& t : o.tests) tests.push_back({t});
  if (!o.map_path.empty() && tests.size() > 1)
    return bad_input("--map writes one map: give it with one test image (got " + std::to_string(tests.size()) + ")");
  Comparison c;
  try {
    c = compare_images(o, {o.ref}, tests, err);
  } catch (const IoError&) {
    throw;  // the system's reason: exit 4
  } catch (const std::invalid_argument& e) {
    return bad_input(e.what());
  }

  // ---- output
  if (o.json) {
    out << dump_json(comparison_json(c), 2) << "\n";
  } else {
    const bool single = c.tests.size() == 1;
    for (const CompareTest& t : c.tests) {
      if (!single) out << "test '" << t.input.path << "':\n";
      print_text(t, c.ref, c.flip, single ? "" : "  ", out);
    }
  }

  // ---- files (I/O failure -> 4)
  try {
    if (!o.csv_path.empty()) write_text_atomic(o.csv_path, csv_table(c.tests, c.ref));
    if (!o.map_path.empty()) {
      const CompareMetric& first = c.tests.front().metrics.front();
      if (first.result.map.empty()) {
        err << "compare: metric '" << first.result.name << "' has no per-pixel map; --map needs one (put a per-pixel "
            << "metric first with --metric)\n";
        return kExitBadInput;
      }
      metrics::write_exr_data(o.map_path, comparison_map(c, 0, 0));
    }
  } catch (const std::exception& e) {
    err << "compare: " << e.what() << "\n";
    return kExitIo;
  }
  return comparison_exit_code(c);
}

}  // namespace glintlab

// ---------------------------------------------------------------- the command line
#include "experiments/cli/commands.h"

#include <iostream>

namespace glintlab {

void add_compare_command(CLI::App& app, int& exit_code) {
  auto cmp = std::make_shared<CompareOptions>();
  auto reference = std::make_shared<std::string>();
  CLI::App* c = app.add_subcommand(
      "compare",
      "compare test image(s) with a reference image: `compare TEST REF` or `compare -r REF -t TEST [TEST ...]`");
  c->add_option("test", cmp->test, "test image (any format OpenImageIO reads)");
  c->add_option("ref", cmp->ref, "reference image");
  c->add_option("-r,--reference", *reference, "reference image, with --test (instead of TEST REF)");
  c->add_option("-t,--test", cmp->tests, "test image(s) compared with --reference; repeat or list several");
  c->add_option("--space", cmp->space, "OCIO colour space of every input (default: file tag, else scene_linear)");
  c->add_option("--metric", cmp->metrics, "metric(s) to report (default: all)");
  c->add_option("--map", cmp->map_path, "write the first metric's per-pixel map as a 1-channel EXR (one test image)");
  c->add_flag("--json", cmp->json, "print JSON: {\"metrics\": {name: {\"mean\", \"max\", ...}}, \"input\": ...}");
  c->add_option("--csv", cmp->csv_path, "write a CSV table: one row per test image and metric");
  CLI::Option* threshold =
      c->add_option("--threshold", cmp->threshold, "exit 1 when the mean FLIP error of a test image is above this, in [0, 1]");
  c->add_option("--ocio-config", cmp->ocio_config, "OCIO config (default: $OCIO, else the shipped config)");
  c->add_option("--itp-nits", cmp->itp_nits, "cd/m^2 of Y = 1 for deltaEITP (default 100)");
  c->add_option("--view", cmp->display_view,
                "measure display-referred, as this OCIO DISPLAY/VIEW shows the images (e.g. sRGB/Standard)");
  c->add_flag("--flip-ldr", cmp->flip_ldr, "LDR-FLIP instead of HDR-FLIP");
  CLI::Option* ppd = c->add_option("--ppd,--pixels-per-degree", cmp->ppd,
                "FLIP: observer's pixels per degree (default 67.0206: 0.7 m from a 0.7 m wide 3840 px monitor)");
  c->add_option("--monitor-distance", cmp->monitor_distance, "FLIP: distance to the monitor in metres (default 0.7)");
  c->add_option("--monitor-width", cmp->monitor_width, "FLIP: monitor width in metres (default 0.7)");
  c->add_option("--monitor-width-pixels", cmp->monitor_width_pixels, "FLIP: monitor width in pixels (default 3840)");
  c->add_option("--tone-mapper", cmp->tone_mapper, "HDR-FLIP tone mapper: aces (default), hable or reinhard");
  c->add_option("--start-exposure", cmp->start_exposure, "HDR-FLIP start exposure in stops (default: from the reference)");
  c->add_option("--stop-exposure", cmp->stop_exposure, "HDR-FLIP stop exposure in stops (default: from the reference)");
  CLI::Option* num = c->add_option("--num-exposures", cmp->num_exposures,
                                    "HDR-FLIP number of exposures, >= 1 (default: max(2, ceil(stop - start)))");
  c->callback([cmp, reference, num, threshold, ppd, &exit_code] {
    exit_code = run_guarded(
        [&] {
          if (threshold->count() > 0 && std::isnan(cmp->threshold)) {  // NaN means "not given" in CompareOptions
            std::cerr << "compare: --threshold must be a number in [0, 1] (a mean FLIP error), got nan\n";
            return int(kExitBadInput);
          }
          if (ppd->count() > 0 && std::isnan(cmp->ppd)) {  // likewise
            std::cerr << "compare: --ppd must be a finite number of pixels per degree > 0, got nan\n";
            return int(kExitBadInput);
          }
          if (num->count() > 0 && (cmp->num_exposures < 1 || cmp->num_exposures > metrics::kFlipMaxExposures)) {
            // 0 means automatic in CompareOptions
            std::cerr << "compare: --num-exposures must be an integer >= 1, got " << cmp->num_exposures
                      << " (at most " << metrics::kFlipMaxExposures << ")\n";
            return int(kExitBadInput);
          }
          const bool named = !reference->empty() || !cmp->tests.empty();
          if (named && (!cmp->test.empty() || !cmp->ref.empty())) {
            std::cerr << "compare: give `compare TEST REF` or `compare --reference REF --test TEST [TEST ...]`, not "
                         "both forms\n";
            return int(kExitBadInput);
          }
          if (named && reference->empty()) {
            std::cerr << "compare: --test needs --reference REF\n";
            return int(kExitBadInput);
          }
          if (named && cmp->tests.empty()) {
            std::cerr << "compare: --reference needs one or more --test TEST\n";
            return int(kExitBadInput);
          }
          if (!named && cmp->ref.empty()) {
            std::cerr << "compare: need TEST and REF (or --reference REF --test TEST [TEST ...])\n";
            return int(kExitBadInput);
          }
          CompareOptions o = *cmp;
          if (named) o.ref = *reference;
          return run_compare(o, std::cout, std::cerr);
        },
        std::cerr);
  });
}

}  // namespace glintlab
