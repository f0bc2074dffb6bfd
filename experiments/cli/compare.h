// `glintlab compare TEST REF [--space NAME] [--metric NAME ...] [--map OUT.exr] [--json]
//                  [--view DISPLAY/VIEW] [--flip-ldr] [--itp-nits N]`:
// colour-managed image comparison in the manner of NVIDIA FLIP's command line (one obvious command,
// a mean printed per metric, an error map on request). Both images go through OCIO to CIE XYZ D65
// and every metric of the registry (metrics/metric_registry.h) is evaluated on them.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace glintlab {

struct CompareOptions {
  std::string test, ref;              // image files (anything OpenImageIO reads)
  std::string space;                  // colour space of both; empty = each file's oiio:ColorSpace tag,
                                      // else scene_linear
  std::vector<std::string> metrics;   // empty = all registered metrics
  std::string map_path;               // write the first metric's per-pixel map here (1-channel float EXR)
  bool json = false;                  // print {"metrics": {"<name>": {"mean": x, "max": y}}}
  std::string ocio_config;            // empty = ColorManager::default_config_path()
  double itp_nits = 100;              // luminance of scene value 1.0 for ΔE_ITP, cd/m^2
  std::string display_view;           // "" = scene-referred; "DISPLAY/VIEW" = display-referred metrics
  bool flip_ldr = false;              // LDR-FLIP instead of HDR-FLIP
};

// Runs the comparison; results on `out`, diagnostics on `err`.
// Returns 0 on success, 2 on bad input (unreadable file, size mismatch, unknown space or metric,
// bad option) and 1 when writing the map fails.
int run_compare(const CompareOptions& options, std::ostream& out, std::ostream& err);

}  // namespace glintlab
