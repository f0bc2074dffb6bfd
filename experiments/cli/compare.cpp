#include "experiments/cli/compare.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "metrics/color/color_manager.h"
#include "metrics/color/image_io.h"
#include "metrics/color/measurement_space.h"
#include "metrics/metric_registry.h"

namespace glintlab {

namespace {

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::string size_str(const Image& img) { return std::to_string(img.width) + "x" + std::to_string(img.height); }

// The colour space an input file is in: --space if given, else the file's oiio:ColorSpace tag when
// the config knows it, else scene_linear (said on err, so the assumption is never silent).
std::string input_space(const metrics::ColorManager& cm, const std::string& forced, const std::string& tag,
                        const std::string& what, const std::string& path, std::ostream& err) {
  if (!forced.empty()) return cm.canonical_name(forced);
  if (!tag.empty() && cm.has_space(tag)) return cm.canonical_name(tag);
  err << "compare: " << what << " '" << path << "' has "
      << (tag.empty() ? std::string("no colour space tag") : "unknown colour space tag '" + tag + "'")
      << "; assuming scene_linear (" << cm.canonical_name("scene_linear") << "); use --space to say\n";
  return cm.canonical_name("scene_linear");
}

// First channel of a per-pixel map (maps are single-channel by convention).
Image first_channel(const Image& map) {
  if (map.channels == 1) return map;
  Image one(map.width, map.height, 1);
  for (std::size_t i = 0; i < one.pixel_count(); ++i) one.data[i] = map.data[i * map.channels];
  return one;
}

}  // namespace

int run_compare(const CompareOptions& o, std::ostream& out, std::ostream& err) {
  // ---- inputs (bad input -> 2)
  std::vector<std::string> names = o.metrics.empty() ? metrics::metric_names() : o.metrics;
  const std::vector<std::string> known = metrics::metric_names();
  for (const auto& n : names)
    if (std::find(known.begin(), known.end(), n) == known.end()) {
      err << "compare: unknown metric '" << n << "'; allowed: " << join(known) << "\n";
      return 2;
    }
  if (names.empty()) {
    err << "compare: no metrics registered\n";
    return 2;
  }
  if (!(o.itp_nits > 0.0) || !std::isfinite(o.itp_nits)) {
    err << "compare: --itp-nits must be a positive number of cd/m^2, got " << o.itp_nits << "\n";
    return 2;
  }

  metrics::MetricOptions mo;
  mo.itp_luminance_nits = o.itp_nits;
  mo.display_view = o.display_view;
  mo.flip_hdr = !o.flip_ldr;
  std::unique_ptr<metrics::ColorManager> cm;
  Image test_xyz, ref_xyz;
  try {
    if (!o.display_view.empty()) (void)metrics::parse_display_view(o.display_view);
    cm = std::make_unique<metrics::ColorManager>(o.ocio_config.empty() ? metrics::ColorManager::default_config_path()
                                                                        : o.ocio_config);
    if (!o.space.empty()) (void)cm->canonical_name(o.space);  // unknown --space: error before reading
    std::string test_tag, ref_tag;
    const Image test = metrics::read_image(o.test, &test_tag);
    const Image ref = metrics::read_image(o.ref, &ref_tag);
    if (!test.same_size(ref)) {
      err << "compare: image sizes differ: test '" << o.test << "' is " << size_str(test) << ", reference '"
          << o.ref << "' is " << size_str(ref) << "\n";
      return 2;
    }
    test_xyz = metrics::metric_xyz(*cm, test, input_space(*cm, o.space, test_tag, "test", o.test, err), mo);
    ref_xyz = metrics::metric_xyz(*cm, ref, input_space(*cm, o.space, ref_tag, "reference", o.ref, err), mo);
  } catch (const std::exception& e) {
    err << "compare: " << e.what() << "\n";
    return 2;
  }

  // ---- metrics
  std::vector<metrics::MetricResult> results;
  try {
    for (const auto& n : names) results.push_back(metrics::evaluate_metric(n, test_xyz, ref_xyz, mo));
  } catch (const std::invalid_argument& e) {
    err << "compare: " << e.what() << "\n";
    return 2;
  }

  if (o.json) {
    nlohmann::json j;
    j["metrics"] = nlohmann::json::object();
    for (const auto& r : results) j["metrics"][r.name] = {{"mean", r.mean}, {"max", r.max}};  // non-finite -> null
    out << j.dump(2) << "\n";
  } else {
    for (const auto& r : results)
      out << r.name << ": mean " << r.mean << " " << r.unit << ", max " << r.max << " " << r.unit << "\n";
  }

  // ---- error map of the first metric
  if (!o.map_path.empty()) {
    const metrics::MetricResult& first = results.front();
    if (first.map.empty()) {
      err << "compare: metric '" << first.name << "' has no per-pixel map; --map needs one (put a per-pixel metric "
          << "first with --metric)\n";
      return 2;
    }
    try {
      metrics::write_exr_data(o.map_path, first_channel(first.map));
    } catch (const std::exception& e) {
      err << "compare: " << e.what() << "\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace glintlab

// ---------------------------------------------------------------- the command line
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"

#include <iostream>

namespace glintlab {

void add_compare_command(CLI::App& app, int& exit_code) {
  auto cmp = std::make_shared<CompareOptions>();
  CLI::App* c = app.add_subcommand("compare", "compare a test image with a reference image");
  c->add_option("test", cmp->test, "test image (any format OpenImageIO reads)")->required();
  c->add_option("ref", cmp->ref, "reference image")->required();
  c->add_option("--space", cmp->space, "OCIO colour space of both inputs (default: file tag, else scene_linear)");
  c->add_option("--metric", cmp->metrics, "metric(s) to report (default: all)");
  c->add_option("--map", cmp->map_path, "write the first metric's per-pixel map as a 1-channel EXR");
  c->add_flag("--json", cmp->json, "print {\"metrics\": {name: {\"mean\", \"max\"}}}");
  c->add_option("--ocio-config", cmp->ocio_config, "OCIO config (default: $OCIO, else the shipped config)");
  c->add_option("--itp-nits", cmp->itp_nits, "cd/m^2 of Y = 1 for deltaEITP (default 100)");
  c->add_option("--view", cmp->display_view,
                "measure display-referred, as this OCIO DISPLAY/VIEW shows the images (e.g. sRGB/Standard)");
  c->add_flag("--flip-ldr", cmp->flip_ldr, "LDR-FLIP instead of HDR-FLIP");
  c->callback([cmp, &exit_code] {
    exit_code = run_guarded([&] { return run_compare(*cmp, std::cout, std::cerr); }, std::cerr);
  });
}

}  // namespace glintlab
