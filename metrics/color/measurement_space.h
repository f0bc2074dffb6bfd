// The CIE XYZ D65 image a per-pixel metric is measured on: scene-referred by
// default, or display-referred through a named OCIO display/view
// (MetricOptions::display_view), where what the view clips compares as clipped.
#pragma once

#include "core/util/image.h"
#include "metrics/color/color_manager.h"
#include "metrics/metric_registry.h"

#include <ostream>
#include <string>
#include <utility>

namespace glintlab::metrics {

// Splits "DISPLAY/VIEW"; throws std::invalid_argument for anything else.
std::pair<std::string, std::string> parse_display_view(const std::string& display_view);

// XYZ D65 (Y = 1 white) of `img` given in colour space `from`, scene- or
// display-referred per `options.display_view`.
Image metric_xyz(const ColorManager& cm, const Image& img, const std::string& from, const MetricOptions& options);

// The colour space an input file is in: `forced` (--space) if given, else the file's oiio:ColorSpace
// tag when the config knows it, else scene_linear, said on `err` ("<what> '<path>' has no colour
// space tag; assuming ...") so the assumption is never silent. Throws std::invalid_argument for an
// unknown forced name.
std::string input_space(const ColorManager& cm, const std::string& forced, const std::string& tag,
                        const std::string& what, const std::string& path, std::ostream& err);

}  // namespace glintlab::metrics
