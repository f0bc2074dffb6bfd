#include "metrics/color/measurement_space.h"

#include <stdexcept>

namespace glintlab::metrics {

std::pair<std::string, std::string> parse_display_view(const std::string& dv) {
  auto slash = dv.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == dv.size() || dv.find('/', slash + 1) != std::string::npos)
    throw std::invalid_argument("display/view \"" + dv + "\": expected DISPLAY/VIEW, e.g. \"sRGB/Standard\"");
  return {dv.substr(0, slash), dv.substr(slash + 1)};
}

Image metric_xyz(const ColorManager& cm, const Image& img, const std::string& from, const MetricOptions& options) {
  if (options.display_view.empty()) return cm.to_xyz_d65(img, from);
  auto [display, view] = parse_display_view(options.display_view);
  return cm.display_referred_xyz(img, from, display, view);
}

std::string input_space(const ColorManager& cm, const std::string& forced, const std::string& tag,
                        const std::string& what, const std::string& path, std::ostream& err) {
  if (!forced.empty()) return cm.canonical_name(forced);
  if (!tag.empty() && cm.has_space(tag)) return cm.canonical_name(tag);
  err << what << " '" << path << "' has "
      << (tag.empty() ? std::string("no colour space tag") : "unknown colour space tag '" + tag + "'")
      << "; assuming scene_linear (" << cm.canonical_name("scene_linear") << "); use --space to say\n";
  return cm.canonical_name("scene_linear");
}

}  // namespace glintlab::metrics
