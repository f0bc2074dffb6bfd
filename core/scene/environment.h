// Environment light: a separate directional sun (Kajs sec. 4.2.1: "a separate directional light
// source to model the sun") plus a sky radiance lat-long map WITHOUT the sun disk, and the sky's
// cosine-weighted hemisphere integral as l <= 2 spherical harmonics (core/scene/spherical_harmonics.h).
//
// Lat-long mapping (mirrored exactly in shaders/common/environment.glsl):
//   direction d = (sin θ cos φ, cos θ, sin θ sin φ)   θ in [0, π] from +Y (zenith), φ azimuth from +X
//   towards +Z;  u = φ / 2π wrapped to [0, 1),  v = θ / π.  Row 0 (v = 0) is the zenith at the top,
//   u = 0 is +X, u = 0.25 is +Z. Texel (i, j) covers u in [i/W, (i+1)/W), v in [j/H, (j+1)/H); its
//   centre is ((i + 0.5)/W, (j + 0.5)/H). Sample with u repeating and v clamped to edge.
// The same azimuth convention is used for sun and camera angles: elevation e and azimuth a give
//   d = (cos e cos a, sin e, cos e sin a).
//
// Colour: the procedural sky is CIE XYZ (tag "CIE-XYZ-D65"), the sun colour carries the space its
// config named. The renderer converts both to its working space (OCIO) and THEN calls
// compute_sh_irradiance(); the builders here never compute SH.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <string>
#include <vector>

namespace glintlab {
class JsonReader;
}

namespace glintlab::core {

// The mapping above. `dir` need not be unit (must be non-zero); the pole gives u = 0.
glm::vec2 latlong_uv(glm::vec3 dir);
glm::vec3 latlong_direction(glm::vec2 uv);  // unit
// d = (cos e cos a, sin e, cos e sin a), degrees.
glm::vec3 direction_from_elevation_azimuth(double elevation_deg, double azimuth_deg);

struct Sun {
  glm::vec3 direction{0, 1, 0};  // unit, towards the sun
  glm::vec3 color{1.0f};
  std::string color_space = "lin_rec709";
  float intensity = 1;                 // L_i = intensity * color (Kajs eq. 4.10)
  float angular_diameter_deg = 0.53f;  // for soft glint / shadow models; not drawn into the sky map
};

struct LatLong {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3 floats, row-major, row 0 = +Y (zenith) at the top
  std::string color_space = "lin_rec709";

  glm::vec3 texel(int x, int y) const;  // x wraps, y clamps
  void set_texel(int x, int y, glm::vec3 c);
  // Bilinear at `uv` (u repeat, v clamp; texel centres at (i + 0.5) / W) = what the GPU sampler gives.
  glm::vec3 sample(glm::vec2 uv) const;
  glm::vec3 sample(glm::vec3 dir) const { return sample(latlong_uv(dir)); }
};

struct Environment {
  Sun sun;
  LatLong sky;
  // Irradiance SH coefficients E_lm = Â_l L_lm (Ramamoorthi & Hanrahan 2001), order of
  // core/scene/spherical_harmonics.h, in sky.color_space; E(n) = Σ E_lm Y_lm(n). Zero until
  // compute_sh_irradiance() is called.
  std::array<glm::vec3, 9> sh_irradiance{};
};

// JSON keys (all optional):
//   "hdri": path of an .hdr/.exr lat-long (relative to the JSON file's folder); then "hdri_color_space"
//       overrides the file's metadata. Without "hdri": the Preetham sky with "turbidity" [1.7, 10]
//       (default 3), "sky_intensity" (zenith luminance Y, default 1), "ground_albedo" [0, 1]
//       (default 0.3), "ground_fade_deg" (default 5), "resolution" (map width, height = width/2,
//       default 256).
//   Sun (both cases): "sun_elevation_deg" [-90, 90] (default 30) and "sun_azimuth_deg" (default 0),
//       or "sun_direction" [3] (towards the sun; not with the angles); "sun_color" [3] (default
//       [1,1,1]), "sun_color_space" (default "lin_rec709"), "sun_intensity" (default 10),
//       "sun_angular_diameter_deg" (0, 20] (default 0.53). The Preetham sky needs the sun at or
//       above the horizon.
struct SkySpec {
  std::string hdri;
  std::string hdri_color_space;
  float turbidity = 3;
  float sky_intensity = 1;
  float ground_albedo = 0.3f;
  float ground_fade_deg = 5;
  int resolution = 256;
  Sun sun{direction_from_elevation_azimuth(30.0, 0.0), glm::vec3(1.0f), "lin_rec709", 10.0f, 0.53f};

  static SkySpec from_json(JsonReader& r);  // validates; calls r.finish()
};

// Preetham, Shirley & Smits 1999 sky (core/scene/sky_preetham.h) as a lat-long in CIE XYZ, tagged
// "CIE-XYZ-D65" (the model's xyY is CIE 1931; its white point is taken as D65), zenith luminance
// = sky_intensity. No sun disk in the map. Below the horizon: a Lambertian ground of albedo
// `ground_albedo` lit by the sky dome only (L = ρ E_sky(+Y) / π; the sun is the separate light),
// blended from the horizon colour over `ground_fade_deg` degrees below the horizon (smoothstep) so
// the map stays continuous. Throws std::invalid_argument if the sun is below the horizon or the
// spec is out of range.
Environment make_procedural_sky(const SkySpec& spec);

// Reads an equirectangular (2:1) HDR/EXR/any-OIIO image as RGB float. Colour space: `color_space`
// if non-empty, else from the file (EXR chromaticities Rec.709 / AP0 / AP1 -> "lin_rec709" /
// "ACES2065-1" / "ACEScg"; oiio:ColorSpace "sRGB" -> "sRGB"), else "lin_rec709". Errors
// (std::runtime_error) name the file.
LatLong read_latlong(const std::string& path, const std::string& color_space = "");
Environment load_latlong(const std::string& hdr_or_exr_path, const Sun& sun, const std::string& color_space = "");

// "hdri" -> load_latlong, else make_procedural_sky.
Environment make_environment(const SkySpec& spec);

// Fills env.sh_irradiance from env.sky (call after converting env.sky to the working space).
void compute_sh_irradiance(Environment& env);

// Mip chain for env_radiance(dir, lod): level 0 = `map`, each next level a 2x2 box average
// (odd sizes: the last output texel averages the remaining 3 texels), down to 1x1.
std::vector<LatLong> build_mips(const LatLong& map);

}  // namespace glintlab::core
