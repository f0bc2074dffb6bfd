// Methods compared where they show the same number of glints. A glint method that shows fewer glints
// flickers less, so a table at each method's default density cannot say which method is steadier; the
// experiment's "density_sweep" (experiments/spec/experiment_spec.h) renders each named variant again at
// every value of one parameter of its "glints", against the run's own truth, and at the value where its
// glint density ratio is 1:
//  1. DIR/density-sweep: one run (no images, no report) whose variants are the named ones at every
//     value, named "<variant>.<parameter>_<value>";
//  2. DIR/matched-density/round-K: each variant at the parameter where ln(glint density ratio) crosses 0,
//     interpolated linearly in the parameter between the sweep's neighbouring values (extrapolated from
//     the end pair nearest to 1 when the sweep does not cross it and approaches 1 at an end; where the
//     ratio turns back before 1, the swept value nearest to 1 if its ratio is within [1/1.25, 1.25]),
//     then rendered. Where an interpolated value renders a ratio outside [1/1.25, 1.25] the rendered
//     point joins the sweep's and the variant is interpolated and rendered again, at most kMatchRounds
//     times.
// summary.json of the run gets
//   "density_sweep":   {VARIANT: [{"parameter": NAME, "value": X, <row>}, ...]}   (increasing X)
//   "matched_density": {VARIANT: {"parameter": NAME, "value": X, "rounds": K, "how": HOW, <row>}}
//     HOW: "interpolated", "extrapolated", "nearest" (a swept value); or "not matched" with "value": null,
//     "reason", "nearest_value" and "nearest_ratio" (the swept point nearest to ratio 1)
// (and "glints": the sweep's fixed keys, where it has them) with <row> = glint_density_ratio, glint_density_test, glint_density_ref, temporal_score, flicker_excess, temporal_lag,
// temporal_error_mc, deltaE2000 (means over the frames; null where not measured) and gpu_ms; the
// truth's floors are its "references" entry's. Both sub-runs resume with --resume.
#pragma once

#include "experiments/runner/runner.h"
#include "experiments/spec/experiment_spec.h"

#include <nlohmann/json.hpp>

#include <ostream>
#include <vector>

namespace glintlab {

constexpr int kMatchRounds = 3;

// One measured point of a sweep: the parameter and ln(glint density ratio) (NaN where undefined).
struct SweepPoint {
  double value = 0;
  double ln_ratio = 0;
};

// The parameter where ln ratio crosses 0: linear interpolation between the first neighbouring pair
// (by value) of opposite signs; else, where the point nearest to 0 is an end one, linear extrapolation
// of that end's pair (at most two steps past the end); points with a NaN ratio are left out.
// *bracketed says which. NaN where no value can match: fewer than two usable points, the nearest point
// inside the sweep (the ratio turns back before 1), or an end pair that is flat or leads away from 1.
double matched_value(std::vector<SweepPoint> points, bool* bracketed);

// Runs the sweep and the matched rounds of `spec` (the experiment as `source` gives it) and adds
// "density_sweep" and "matched_density" to *summary_extra. Returns an exit code (0, or a sub-run's
// 2, 3, 4 or 5).
int run_density_sweep(const RunOptions& opt, const nlohmann::json& source, const ExperimentSpec& spec,
                      std::ostream& log, nlohmann::json* summary_extra);

}  // namespace glintlab
