// Colour management through OpenColorIO: every colour conversion of glintlab goes through the
// shipped config (metrics/color/ocio/config.ocio) or the one named by $OCIO. Metrics consume images in
// CIE XYZ D65 with Y = 1 for scene white (to_xyz_d65); PNG previews go through a display/view.
// OpenColorIO itself is called from libglintlab_ocio.so (core/util/ocio_plugin.h), loaded by a
// ColorManager when it needs OpenColorIO's answer: at once for a config without a valid bake, and only
// for what the bake does not hold where it has one (metrics/color/color_bake.h: names and the matrix
// conversions between linear spaces, equal to OpenColorIO's to the bit). A process that converts no
// colour never loads OpenColorIO.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/util/image.h"

namespace glintlab::metrics {

// Name of the scene-referred CIE XYZ D65 space of the shipped config.
inline constexpr const char* kXyzD65Space = "CIE-XYZ-D65";
inline constexpr const char* kXyzD65DisplaySpace = "CIE-XYZ-D65 display";  // the display reference

class ColorManager {
 public:
  // Loads and validates an OCIO config (OpenColorIO does, unless the bake beside it is valid: then it was
  // valid when baked); throws std::runtime_error naming the file on failure.
  explicit ColorManager(const std::string& config_path);
  // Loads default_config_path().
  ColorManager();
  ~ColorManager();
  ColorManager(const ColorManager&) = delete;
  ColorManager& operator=(const ColorManager&) = delete;

  // $OCIO if set and non-empty, else the shipped config (metrics/color/ocio/config.ocio of the data
  // folder, core/util/data_dir.h).
  static std::string default_config_path();

  const std::string& config_path() const { return config_path_; }

  // True for colour space names, aliases and roles of the config (OCIO lookup: case-insensitive).
  bool has_space(const std::string& name) const;
  // Canonical name of a space/alias/role; throws std::invalid_argument listing the allowed ones.
  std::string canonical_name(const std::string& name) const;
  // All colour spaces (scene- and display-referred) of the config.
  std::vector<std::string> spaces() const;
  // Displays of the config and the views of one display.
  std::vector<std::string> displays() const;
  std::vector<std::string> views(const std::string& display) const;

  // Converts the RGB channels of img (3 or 4 channels) in place; alpha untouched.
  // Throws std::invalid_argument naming an unknown space and listing the allowed ones.
  void convert(Image& img, const std::string& from, const std::string& to) const;
  // A copy of img in CIE XYZ D65 (Y = 1 = scene white): what every metric consumes.
  Image to_xyz_d65(const Image& img, const std::string& from) const;
  glm::vec3 convert_color(const glm::vec3& rgb, const std::string& from, const std::string& to) const;

  // Display-referred encoded values (e.g. sRGB code values in [0,1]) of a scene-referred image
  // in from_space, through the display/view of the config. Alpha is copied.
  Image display(const Image& scene, const std::string& from_space, const std::string& display,
                const std::string& view) const;

  // Display-referred CIE XYZ D65 (display white Y = 1; for Rec.2100-PQ, 1 = 100 cd/m^2) of a
  // scene-referred image as display/view shows it: the view's encoded output decoded into the
  // display reference ("CIE-XYZ-D65 display"). Display-referred metrics consume this: values the
  // view clips compare as clipped. Alpha is copied.
  Image display_referred_xyz(const Image& scene, const std::string& from_space, const std::string& display,
                             const std::string& view) const;

  // CIE 1931 xy of the R, G, B primaries and white (Rx Ry Gx Gy Bx By Wx Wy) of the RGB encoding
  // a space stands for, for the OpenEXR `chromaticities` attribute. Known for lin_rec709 (ITU-R
  // BT.709), ACEScg (AP1) and ACES2065-1 (AP0); throws std::invalid_argument for others.
  std::array<float, 8> chromaticities(const std::string& space) const;

 private:
  // display() (decode_to "") and display_referred_xyz() (decode_to the display reference): one processor.
  Image through_view(const Image& scene, const std::string& from_space, const std::string& display,
                     const std::string& view, const std::string& decode_to) const;
  struct Impl;
  std::string config_path_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace glintlab::metrics
