// `glintlab measure`: the run's metrics for image sequences of any renderer
// (experiments/runner/measure.h).
#include "core/util/data_dir.h"
#include "experiments/cli/commands.h"
#include "experiments/cli/exit_codes.h"
#include "experiments/runner/measure.h"
#include "metrics/color/measurement_space.h"

#include <filesystem>
#include <iostream>
#include <memory>
#include <regex>
#include <tuple>

namespace glintlab {

namespace {

// "NAME=SEQ" -> (NAME, SEQ) when NAME is a plain name and the whole text is not an existing path.
MeasureSource split_test(const std::string& text) {
  static const std::regex named(R"(([A-Za-z0-9._-]{1,100})=(.+))");
  std::smatch m;
  std::error_code ec;
  if (std::regex_match(text, m, named) && !std::filesystem::exists(text, ec)) return {m[1], m[2]};
  return {"", text};
}

// "FIRST:LAST" (either side may be empty: open).
bool parse_range(const std::string& s, int* first, int* last) {
  static const std::regex re(R"((-?[0-9]{1,9})?:(-?[0-9]{1,9})?)");
  std::smatch m;
  if (!std::regex_match(s, m, re) || (!m[1].matched && !m[2].matched)) return false;
  if (m[1].matched) *first = std::stoi(m[1]);
  if (m[2].matched) *last = std::stoi(m[2]);
  return true;
}

}  // namespace

void add_measure_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<MeasureOptions>();
  auto tests = std::make_shared<std::vector<std::string>>();
  auto frames = std::make_shared<std::string>();
  auto no_report = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand(
      "measure", "measure image sequences of any renderer against a reference: flicker along the motion, "
                 "colour-managed error; frames.csv, summary.json, report.html (as run)");
  c->add_option("--reference", o->reference,
                "reference SEQ: a folder of numbered frames, a pattern with %04d or ####, optionally :LAYER "
                "(default: none; then only each test's own flicker_contrast)");
  c->add_option("--reference-b", o->reference_b,
                "SEQ of the reference's second half: --reference and this are two independent halves of the truth "
                "(each of half its samples); the truth is their mean and their difference its noise floor "
                "(default: none, no floor)");
  c->add_option("--test", *tests, "[NAME=]SEQ of a test sequence (repeat for several)")->required();
  c->add_option("--out", o->out_dir, "output folder (default: results/measure)");
  c->add_option("--motion", o->motion, "SEQ of motion vectors (default: estimated by optical flow)");
  c->add_option("--motion-from", o->motion_from, "the vectors are in the reference's or the first test's files")
      ->check(CLI::IsMember({"reference", "test"}));
  c->add_option("--motion-convention", o->motion_convention, "pixels, blender, unreal or unity (default: pixels)");
  c->add_option("--depth", o->depth, "SEQ of depth, for disocclusion (default: none)");
  c->add_option("--space", o->space, "OCIO colour space of every input (default: file tag, else scene_linear)");
  c->add_option("--metrics", o->metrics, "per-pixel metrics and groups (flicker, glints, pooled), comma-separated; naming "
                                       "a group measures flicker and the named groups only, else every group "
                                       "(default: deltaE2000,flip)")
      ->delimiter(',');
  c->add_option("--frames", *frames, "FIRST:LAST frame numbers, inclusive (default: all of the reference's)");
  c->add_option("--fps", o->fps, "frames per second, for time_s (default: 24)");
  c->add_option("--name", o->name, "the summary's experiment name, what check matches (default: measure)");
  c->add_option("--ocio-config", o->ocio_config, "OCIO config (default: $OCIO, else the shipped config)");
  auto view = std::make_shared<std::string>();
  c->add_option("--view", *view,
                "DISPLAY/VIEW the previews and temporal_score show the frames through; sRGB/Standard for frames "
                "that are already display-referred (8-bit PNG) (default: sRGB/ACES 1.0 SDR-video)");
  c->add_flag("--resume", o->resume, "continue the measurement in --out: do only what its journal lacks");
  c->add_flag("--no-report", *no_report, "do not write report.html");
  c->callback([=, &exit_code] {
    exit_code = run_guarded(
        [=] {
          o->report = !*no_report;
          o->tests.clear();
          for (const auto& t : *tests) o->tests.push_back(split_test(t));
          if (!frames->empty() && !parse_range(*frames, &o->first, &o->last)) {
            std::cerr << "error: --frames: expected FIRST:LAST (frame numbers, e.g. 1:48), got \"" << *frames << "\"\n";
            return int(kExitBadInput);
          }
          if (!view->empty()) {
            try {
              std::tie(o->display, o->view) = metrics::parse_display_view(*view);
            } catch (const std::invalid_argument& e) {
              std::cerr << "error: --view: " << e.what() << "\n";
              return int(kExitBadInput);
            }
          }
          if (o->out_dir.empty()) o->out_dir = results_path("measure");
          return measure_sequences(*o, std::cerr);
        },
        std::cerr);
  });
}

}  // namespace glintlab
