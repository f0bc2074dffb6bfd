// The CIE XYZ D65 image a per-pixel metric is measured on: scene-referred by
// default, or display-referred through a named OCIO display/view
// (MetricOptions::display_view), where what the view clips compares as clipped.
#pragma once

#include "core/util/image.h"
#include "metrics/color/color_manager.h"
#include "metrics/metric_registry.h"

#include <string>
#include <utility>

namespace glintlab::metrics {

// Splits "DISPLAY/VIEW"; throws std::invalid_argument for anything else.
std::pair<std::string, std::string> parse_display_view(const std::string& display_view);

// XYZ D65 (Y = 1 white) of `img` given in colour space `from`, scene- or
// display-referred per `options.display_view`.
Image metric_xyz(const ColorManager& cm, const Image& img, const std::string& from, const MetricOptions& options);

}  // namespace glintlab::metrics
