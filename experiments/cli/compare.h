// `glintlab compare`: colour-managed image comparison in the manner of NVIDIA FLIP's command line
// (one obvious command, a mean printed per metric, FLIP's pooled statistics, an error map on request).
// Every image goes through OCIO to CIE XYZ D65 and every metric of the registry
// (metrics/metric_registry.h) is evaluated on it.
//
//   glintlab compare TEST REF [options]                    one test image against a reference
//   glintlab compare -r REF -t TEST [TEST ...] [options]   one or more test images against REF
//                                                          (--reference, --test; --test may repeat)
//   The two forms do not mix: with --reference/--test there are no positional arguments.
//
//   --space NAME         OCIO colour space of every input (default: each file's tag, else scene_linear)
//   --metric NAME ...    metrics to report (default: all)
//   --view DISPLAY/VIEW  measure display-referred, as that OCIO view shows the images
//   --itp-nits N         cd/m^2 of Y = 1 for deltaEITP (default 100)
//   --json               print JSON instead of text (below)
//   --csv FILE           also write FILE: one row per test image and metric (below)
//   --map OUT.exr        the first metric's per-pixel map as a 1-channel float EXR (one test image only)
//   --threshold X        exit 1 when the mean FLIP error of any test image is above X (X in [0, 1];
//                        FLIP's -et with its default quantity, the mean); needs the flip metric
//   FLIP, as NVIDIA FLIP v1.6's tool (its defaults and its option names):
//   --flip-ldr           LDR-FLIP instead of HDR-FLIP
//   --ppd X (--pixels-per-degree)  observer's pixels per degree; default from the viewing conditions:
//   --monitor-distance M, --monitor-width M, --monitor-width-pixels PX  (defaults 0.7 m, 0.7 m,
//                        3840 px: 67.0206 px/deg; ppd = distance * (pixels / width) * pi / 180)
//   --tone-mapper aces|hable|reinhard   HDR-FLIP tone mapper (default aces, any case)
//   --start-exposure C, --stop-exposure C, --num-exposures N   HDR-FLIP exposure range; each one not
//                        given is computed from the reference as FLIP does (metrics/flip.h)
//   The HDR options are an error with --flip-ldr; FLIP options without the flip metric are ignored
//   with a warning.
//
// Output. Text: one line per metric, "NAME: mean X UNIT, max Y UNIT"; for flip two more lines, FLIP's
// pooled values (weighted median, 1st and 3rd weighted quartile, min, max: metrics/flip_pooling.h)
// and its settings (LDR/HDR, px/deg, tone mapper, exposures). With several test images each block
// starts with "test 'FILE':" and its lines are indented.
// JSON (--json): with one test image
//   {"test": T, "reference": R, "metrics": {"<name>": {"mean": x, "max": y, "p95": z}, ...,
//    "flip": {"mean", "max", "min", "weighted_median", "weighted_quartile_1", "weighted_quartile_3"}},
//    "input": {"test": COUNTS, "ref": COUNTS}, "flip": SETTINGS, "threshold_exceeded": bool}
//   with COUNTS = {"pixels": n, "nan": n, "inf": n, "negative": n}, SETTINGS = {"mode": "hdr"|"ldr",
//   "ppd", "tone_mapper", "start_exposure", "stop_exposure", "num_exposures"} (the last four for HDR;
//   "flip" only when the flip metric ran, "threshold_exceeded" only with --threshold; "p95" the
//   nearest-rank 95th percentile of the metric's per-pixel map, null for psnr). With several
//   test images: {"reference": R, "flip": SETTINGS, "tests": [{"test", "metrics", "input",
//   "threshold_exceeded"}, ...]}. A value that is not finite is null.
// CSV (--csv, written whole, atomically): header
//   reference,test,metric,unit,mean,max,min,weighted_median,weighted_quartile_1,weighted_quartile_3,
//   test_nan,test_inf,test_negative,ref_nan,ref_inf,ref_negative
//   the pooled columns are filled for flip only; a value that is not finite is an empty field.
//
// Bad pixels (the rule): every input is scanned (its colour channels as decoded from the file, before
// any colour conversion) for NaN, +-Inf and negative values (metrics/pixel_scan.h). The counts are
// always reported ("input" in JSON, the CSV columns; in text a line "input test|ref 'FILE': ..."
// when any count is non-zero, and a message on stderr). When the test image or the reference has any
// NaN, Inf or negative pixel, every metric of that comparison is NaN: mean, max and FLIP's pooled
// values (null in JSON, "nan" in text, empty in CSV); nothing is averaged over the remaining pixels,
// since a spatial metric (FLIP) spreads a bad pixel over its neighbours. A --map is still written,
// with NaN at every bad pixel. The same holds when the colour conversion turns a finite input into a
// non-finite value. The exit code is then 1.
//
// Exit codes (experiments/cli/exit_codes.h): 0 ok; 1 any input pixel NaN, Inf or negative, or
// --threshold exceeded (the comparison is still printed in full); 2 bad input (unreadable image, size
// mismatch, unknown colour space or metric, bad option value: the message names it and what is
// allowed); 4 --map or --csv could not be written.
#pragma once

#include <cmath>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/util/image.h"
#include "metrics/flip.h"
#include "metrics/flip_pooling.h"
#include "metrics/metric_registry.h"
#include "metrics/pixel_scan.h"

namespace glintlab {

struct CompareOptions {
  std::string test;                   // test image (the positional form); may be empty when `tests` is set
  std::vector<std::string> tests;     // more test images, compared after `test`, each against `ref`
  std::string ref;                    // reference image (anything OpenImageIO reads)
  std::string space;                  // colour space of every input; empty = each file's oiio:ColorSpace
                                      // tag, else scene_linear
  std::vector<std::string> metrics;   // empty = all registered metrics
  std::string map_path;               // write the first metric's per-pixel map here (1-channel float EXR)
  bool json = false;                  // print JSON (see above)
  std::string csv_path;               // also write the CSV table here
  std::string ocio_config;            // empty = ColorManager::default_config_path()
  double itp_nits = 100;              // luminance of scene value 1.0 for ΔE_ITP, cd/m^2
  std::string display_view;           // "" = scene-referred; "DISPLAY/VIEW" = display-referred metrics
  double threshold = NAN;             // NaN = off; else exit 1 when a mean FLIP error is above it

  // FLIP (NaN / empty / 0 = FLIP's default).
  bool flip_ldr = false;              // LDR-FLIP instead of HDR-FLIP
  double ppd = NAN;                   // pixels per degree; NaN = from the viewing conditions
  double monitor_distance = NAN;      // m, default 0.7
  double monitor_width = NAN;         // m, default 0.7
  double monitor_width_pixels = NAN;  // px, default 3840
  std::string tone_mapper;            // "aces" (default), "hable", "reinhard"; any case
  double start_exposure = NAN;        // NaN = from the reference
  double stop_exposure = NAN;         // NaN = from the reference
  int num_exposures = 0;              // 0 = max(2, ceil(stop - start)); >= 1 otherwise
};

// One image of a comparison: a file, or pixels already decoded (the Python module's arrays), not owned.
// compare_images reads them once, into the RGBA image a file of `channels` channels reads as (grey to
// R, G and B, alpha 1 where there is none), which the conversion to CIE XYZ then changes in place;
// they are not copied before that, and must outlive the call.
struct CompareImage {
  std::string path;               // the file; with `pixels`, the name messages and the JSON give it
  const float* pixels = nullptr;  // height x width x channels floats, row-major, interleaved; null: read `path`
  int width = 0;
  int height = 0;
  int channels = 4;               // 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA (read_image's file_channels)
  std::string tag;                // their colour-space tag, "" for none (read_image's colorspace_tag)
};

// An input as compared: in CIE XYZ D65, with its scan (before any colour conversion).
struct CompareInput {
  std::string path;
  Image xyz;
  metrics::PixelScan scan;
  std::vector<bool> bad;          // per pixel: NaN, Inf or negative in a colour channel
  std::size_t converted_bad = 0;  // non-finite values the colour conversion produced from finite input
};

struct CompareMetric {
  metrics::MetricResult result;  // mean, max and the per-pixel map (NaN when the comparison is not clean)
  double p95 = NAN;              // nearest-rank 95th percentile of the map; NaN for psnr (its map is a squared error)
  metrics::FlipPooled pooled;    // flip only
  bool is_flip = false;
};

struct CompareTest {
  CompareInput input;
  std::vector<CompareMetric> metrics;  // in the order of the options' metrics
  bool clean = true;                   // no bad pixel in the test or the reference
  bool threshold_exceeded = false;
};

struct CompareFlipSetup {
  bool hdr = true;
  double ppd = metrics::kFlipDefaultPpd;
  metrics::HdrFlipOptions hdr_options;
  metrics::HdrFlipExposures exposures;  // resolved from the reference (HDR)
};

struct Comparison {
  CompareInput ref;
  std::vector<CompareTest> tests;
  CompareFlipSetup flip;
  bool want_flip = false;
  double threshold = NAN;
};

// Checks the options (the fields that are not about output: test, tests, ref, map_path, json and
// csv_path are ignored), reads every input and checks it before anything is computed, then evaluates
// every metric. Bad input (what `compare` exits 2 for) throws std::invalid_argument with the message
// the command prints after "compare: "; a file that cannot be read for the system's reason throws
// IoError. Warnings and the bad-pixel messages go to `err`.
Comparison compare_images(const CompareOptions& options, const CompareImage& ref, const std::vector<CompareImage>& tests,
                          std::ostream& err);

// What --json prints (above).
nlohmann::json comparison_json(const Comparison& c);

// Metric `metric` of test `test` as --map writes it: its first channel, NaN at every bad pixel.
Image comparison_map(const Comparison& c, std::size_t test, std::size_t metric);

// 1 when any test is not clean or is above the threshold, else 0.
int comparison_exit_code(const Comparison& c);

// Runs the comparison; results on `out`, diagnostics on `err`. Returns the exit code (above).
int run_compare(const CompareOptions& options, std::ostream& out, std::ostream& err);

}  // namespace glintlab
