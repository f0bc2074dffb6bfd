// Internals of the stress suite (experiments/stress/stress.h): the case table
// and the helpers the case files share.
#pragma once

#include "core/vk/vk_context.h"
#include "experiments/stress/stress.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace glintlab {
struct Image;
}

namespace glintlab::stress {

struct Env {
  core::VkContext& ctx;
  bool fast;  // the fast suite: cases may evaluate fewer items
};

struct Case {
  std::string name;
  std::string category;
  bool fast;  // part of the --fast subset
  std::function<StressCaseResult(Env&)> run;
};

// Each file of the suite adds its cases.
void add_sand_cases(std::vector<Case>& cases);    // cases_sand.cpp: sand terms vs fp64 (compute harness)
void add_glint_cases(std::vector<Case>& cases);   // cases_glint.cpp: glint models, binomial vs fp64
void add_math_cases(std::vector<Case>& cases);    // cases_math.cpp: shared helpers vs fp64
void add_render_cases(std::vector<Case>& cases);  // cases_render.cpp: the renderer at small sizes
void add_taa_cases(std::vector<Case>& cases);     // cases_taa.cpp: TAA resolve on hostile inputs

std::vector<Case> all_cases();

// ---- helpers

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

inline float f32(double x) { return static_cast<float>(x); }

inline std::string fmt(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

// Largest-error accumulator: err = max(0, |gpu - ref| - allowance) / max(|ref|, floor)
// (`allowance`: an absolute error the case states separately, 0 for most).
struct ErrorStat {
  double max_rel = 0;
  size_t compared = 0;
  std::string worst;  // description of the worst comparison
  void add(double gpu, double ref, double floor, const std::string& where = {}, double allowance = 0) {
    ++compared;
    double e = std::isfinite(gpu) ? std::max(0.0, std::fabs(gpu - ref) - allowance) / std::max(std::fabs(ref), floor)
                                  : kInf;
    if (e > max_rel || (compared == 1 && e >= max_rel)) {
      if (e > max_rel) max_rel = e;
      worst = where + " gpu " + fmt(gpu) + " ref " + fmt(ref);
    }
  }
};

// Counts of the values of one output that must be finite (and >= 0 when `nonneg`).
struct ValueScan {
  size_t nonfinite = 0, negative = 0, items = 0;
  void add(double v, bool nonneg = true) {
    ++items;
    if (!std::isfinite(v)) ++nonfinite;
    else if (nonneg && v < 0) ++negative;
  }
};

// Per-pixel counts over an RGBA image (a pixel counts once whatever its channels).
struct PixelScan {
  size_t nonfinite = 0, negative = 0, pixels = 0;
  double max_value = 0;  // largest finite channel value (rgb)
  double sum = 0;        // sum of the finite rgb values
};
PixelScan scan_image(const Image& img, int channels = 4);

// A result with the counts and the comparison filled in; pass = no bad value
// and max_rel_error <= bound (when both exist) and `ok`.
StressCaseResult make_result(const std::string& name, const std::string& category, const ValueScan& scan,
                             const ErrorStat* err, std::optional<double> bound, bool ok, std::string detail);

// Log-uniform in [lo, hi].
inline double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> U;
  return std::exp(std::log(lo) + U(rng) * (std::log(hi) - std::log(lo)));
}

}  // namespace glintlab::stress
