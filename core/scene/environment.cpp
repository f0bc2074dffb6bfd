#include "core/scene/environment.h"
#include <cstring>
#include <cerrno>
#include <unistd.h>
#include <fcntl.h>
#include <sys/stat.h>
#include "core/util/io_error.h"

#include "core/util/json_check.h"
#include "core/scene/sky_preetham.h"
#include "core/scene/spherical_harmonics.h"

#include "core/util/oiio_plugin.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace glintlab::core {

namespace {
constexpr double kPi = 3.14159265358979323846;

int wrap(int x, int n) { return ((x % n) + n) % n; }

bool near_chromaticities(const float* c, const float (&ref)[8]) {
  for (int i = 0; i < 8; ++i)
    if (std::fabs(c[i] - ref[i]) > 2e-3f) return false;
  return true;
}
}  // namespace

// ---------------------------------------------------------------- mapping

glm::vec2 latlong_uv(glm::vec3 dir) {
  double len = glm::length(glm::dvec3(dir));
  if (!(len > 0.0)) throw std::invalid_argument("latlong_uv: zero direction");
  glm::dvec3 d = glm::dvec3(dir) / len;
  double u = (d.x == 0.0 && d.z == 0.0) ? 0.0 : std::atan2(d.z, d.x) / (2.0 * kPi);
  if (u < 0.0) u += 1.0;
  if (u >= 1.0) u = 0.0;
  double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
  return {float(u), float(v)};
}

glm::vec3 latlong_direction(glm::vec2 uv) {
  double phi = 2.0 * kPi * uv.x, theta = kPi * uv.y;
  return glm::vec3(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                   float(std::sin(theta) * std::sin(phi)));
}

glm::vec3 direction_from_elevation_azimuth(double elevation_deg, double azimuth_deg) {
  double e = elevation_deg * kPi / 180.0, a = azimuth_deg * kPi / 180.0;
  return glm::vec3(float(std::cos(e) * std::cos(a)), float(std::sin(e)), float(std::cos(e) * std::sin(a)));
}

glm::vec3 LatLong::texel(int x, int y) const {
  x = wrap(x, width);
  y = std::clamp(y, 0, height - 1);
  const float* p = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
  return {p[0], p[1], p[2]};
}

void LatLong::set_texel(int x, int y, glm::vec3 c) {
  float* p = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
  p[0] = c.x, p[1] = c.y, p[2] = c.z;
}

glm::vec3 LatLong::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0) throw std::invalid_argument("LatLong::sample: empty map");
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) throw std::invalid_argument("LatLong::sample: non-finite uv");
  double u = uv.x - std::floor(double(uv.x));          // repeat
  double v = std::clamp(double(uv.y), 0.0, 1.0);       // clamp to edge
  double x = u * width - 0.5, y = v * height - 0.5;    // texel centres at (i + 0.5) / W
  double fx0 = std::floor(x), fy0 = std::floor(y);     // bounded: |x| <= width
  int x0 = int(fx0), y0 = int(fy0);
  float tx = float(x - fx0), ty = float(y - fy0);
  glm::vec3 a = glm::mix(texel(x0, y0), texel(x0 + 1, y0), tx);
  glm::vec3 b = glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), tx);
  return glm::mix(a, b, ty);
}

// ---------------------------------------------------------------- spec

SkySpec SkySpec::from_json(JsonReader& r) {
  SkySpec s;
  if (r.has("hdri")) {
    s.hdri = r.get_string("hdri");
    if (s.hdri.empty()) r.fail("hdri", "must be a file path");
    std::filesystem::path p(s.hdri);
    if (p.is_relative()) s.hdri = (std::filesystem::path(r.file()).parent_path() / p).lexically_normal().string();
    s.hdri_color_space = r.get_string("hdri_color_space", "");
  } else {
    s.turbidity = float(r.get_number("turbidity", 3.0, 1.7, 10.0));
    s.sky_intensity = float(r.get_number("sky_intensity", 1.0, 0.0, 1e6));
    s.ground_albedo = float(r.get_number("ground_albedo", 0.3, 0.0, 1.0));
    s.ground_fade_deg = float(r.get_number("ground_fade_deg", 5.0, 0.0, 90.0));
    s.resolution = r.get_int("resolution", 256, 8, 16384);
    if (s.resolution % 2) r.fail("resolution", "must be even (the map is resolution x resolution/2)");
  }
  bool has_dir = r.has("sun_direction");
  if (has_dir && (r.has("sun_elevation_deg") || r.has("sun_azimuth_deg")))
    r.fail("sun_direction", "give either \"sun_direction\" or \"sun_elevation_deg\"/\"sun_azimuth_deg\", not both");
  if (has_dir) {
    auto d = r.get_numbers("sun_direction", 3, -1e6, 1e6);
    glm::dvec3 v(d[0], d[1], d[2]);
    if (!(glm::length(v) > 1e-9)) r.fail("sun_direction", "must not be the zero vector");
    s.sun.direction = glm::vec3(glm::normalize(v));
  } else {
    double el = r.get_number("sun_elevation_deg", 30.0, -90.0, 90.0);
    double az = r.get_number("sun_azimuth_deg", 0.0, -360.0, 360.0);
    s.sun.direction = direction_from_elevation_azimuth(el, az);
  }
  if (s.hdri.empty() && s.sun.direction.y < 0.0f)
    r.fail(has_dir ? "sun_direction" : "sun_elevation_deg", "the Preetham sky needs the sun at or above the horizon");
  auto c = r.get_numbers("sun_color", {1.0, 1.0, 1.0}, 0.0, 1e6);
  s.sun.color = glm::vec3(float(c[0]), float(c[1]), float(c[2]));
  s.sun.color_space = r.get_string("sun_color_space", "lin_rec709");
  s.sun.intensity = float(r.get_number("sun_intensity", 10.0, 0.0, 1e9));
  s.sun.angular_diameter_deg = float(r.get_number("sun_angular_diameter_deg", 0.53, 1e-3, 20.0));
  r.finish();
  return s;
}

// ---------------------------------------------------------------- builders

Environment make_procedural_sky(const SkySpec& spec) {
  if (spec.resolution < 2 || spec.resolution % 2)
    throw std::invalid_argument("make_procedural_sky: resolution must be even and >= 2");
  if (!(spec.sky_intensity >= 0.0f) || !(spec.ground_albedo >= 0.0f) || !(spec.ground_fade_deg >= 0.0f))
    throw std::invalid_argument("make_procedural_sky: sky_intensity, ground_albedo, ground_fade_deg must be >= 0");
  PreethamSky sky(spec.turbidity, glm::dvec3(spec.sun.direction));
  Environment env;
  env.sun = spec.sun;
  env.sun.direction = glm::normalize(spec.sun.direction);
  LatLong& m = env.sky;
  m.width = spec.resolution;
  m.height = spec.resolution / 2;
  m.color_space = "CIE-XYZ-D65";
  m.rgb.assign(size_t(m.width) * size_t(m.height) * 3, 0.0f);
  const double k = spec.sky_intensity;
  const double dphi = 2.0 * kPi / m.width;

  // Sky rows (texel centres above the horizon), and their irradiance on an upward plane.
  glm::dvec3 E_up(0.0);
  for (int j = 0; j < m.height; ++j) {
    double theta = kPi * (j + 0.5) / m.height;
    if (theta >= 0.5 * kPi) continue;
    double domega = dphi * (std::cos(kPi * j / m.height) - std::cos(kPi * (j + 1) / m.height));
    for (int i = 0; i < m.width; ++i) {
      glm::dvec3 d(latlong_direction({float((i + 0.5) / m.width), float((j + 0.5) / m.height)}));
      glm::dvec3 L = k * sky.XYZ(d);
      m.set_texel(i, j, glm::vec3(L));
      E_up += L * std::cos(theta) * domega;
    }
  }
  // Ground: Lambertian, albedo ρ, lit by the sky dome: L = ρ E_up / π, faded in from the horizon.
  const glm::dvec3 L_ground = double(spec.ground_albedo) * E_up / kPi;
  const double fade = spec.ground_fade_deg * kPi / 180.0;
  for (int j = 0; j < m.height; ++j) {
    double theta = kPi * (j + 0.5) / m.height;
    if (theta < 0.5 * kPi) continue;
    double depression = theta - 0.5 * kPi;
    double w = 1.0;
    if (fade > 0.0) {
      double t = std::clamp(depression / fade, 0.0, 1.0);
      w = t * t * (3.0 - 2.0 * t);
    }
    for (int i = 0; i < m.width; ++i) {
      double phi = dphi * (i + 0.5);
      glm::dvec3 L_horizon = k * sky.XYZ(glm::dvec3(std::cos(phi), 0.0, std::sin(phi)));
      m.set_texel(i, j, glm::vec3((1.0 - w) * L_horizon + w * L_ground));
    }
  }
  return env;
}

LatLong read_latlong(const std::string& path, const std::string& color_space) {
  // Only a regular file (a FIFO or /dev/zero would block or never end), opened with the system's
  // reason on failure.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int e = errno;  // a path that names no file is bad input; any other reason is the system's
    if (e == ENOENT || e == ENOTDIR || e == ENAMETOOLONG || e == ELOOP)
      throw ConfigError(path + ": no such environment map (" + std::strerror(e) + ")");
    throw IoError(path + ": cannot open environment map: " + std::strerror(e));
  }
  if (!S_ISREG(st.st_mode)) throw ConfigError(path + ": the environment map is not a regular file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw IoError(path + ": cannot open environment map: " + std::strerror(errno));
  ::close(fd);
  oiio::EnvironmentInfo spec;
  std::vector<float> all;
  oiio::api().read_environment(path, [&](const oiio::EnvironmentInfo& info) {
    const int W = info.width, H = info.height, nch = info.channels;
    if (W <= 0 || H <= 0 || nch <= 0) throw ConfigError(path + ": empty image");
    if (int64_t(W) * H > (int64_t(64) << 20) || nch > 1024)
      throw ConfigError(path + ": the environment map's header claims " + std::to_string(W) + "x" + std::to_string(H) +
                        " pixels and " + std::to_string(nch) + " channels; allowed: at most 64 Mpix and 1024 channels");
    if (W != 2 * H)
      throw ConfigError(path + ": not an equirectangular lat-long map: expected width = 2 x height, got " +
                               std::to_string(W) + "x" + std::to_string(H));
    spec = info;
  }, all);
  const int W = spec.width, H = spec.height, nch = spec.channels;

  LatLong m;
  m.width = W;
  m.height = H;
  m.rgb.resize(size_t(W) * size_t(H) * 3);
  for (size_t p = 0; p < size_t(W) * size_t(H); ++p)
    for (int c = 0; c < 3; ++c) {
      float v = all[p * nch + size_t(nch >= 3 ? c : 0)];
      if (!std::isfinite(v))
        throw ConfigError(path + ": pixel (" + std::to_string(p % W) + ", " + std::to_string(p / W) +
                                 ") is NaN or infinite");
      m.rgb[p * 3 + c] = std::max(v, 0.0f);  // negative radiance is not light
    }

  if (!color_space.empty()) {
    m.color_space = color_space;
  } else {
    static const float kRec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    static const float kAP0[8] = {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f};
    static const float kAP1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    const std::string& oiio_cs = spec.colorspace;
    if (spec.has_chromaticities) {
      const float* c = spec.chromaticities.data();
      if (near_chromaticities(c, kRec709)) m.color_space = "lin_rec709";
      else if (near_chromaticities(c, kAP0)) m.color_space = "ACES2065-1";
      else if (near_chromaticities(c, kAP1)) m.color_space = "ACEScg";
      else
        throw ConfigError(path + ": unsupported chromaticities in the file; name the colour space explicitly "
                                        "(\"hdri_color_space\")");
    } else if (oiio_cs == "sRGB" || oiio_cs == "srgb") {
      m.color_space = "sRGB";
    } else {
      m.color_space = "lin_rec709";
    }
  }
  return m;
}

Environment load_latlong(const std::string& path, const Sun& sun, const std::string& color_space) {
  Environment env;
  env.sun = sun;
  env.sky = read_latlong(path, color_space);
  return env;
}

Environment make_environment(const SkySpec& spec) {
  if (!spec.hdri.empty()) return load_latlong(spec.hdri, spec.sun, spec.hdri_color_space);
  return make_procedural_sky(spec);
}

void compute_sh_irradiance(Environment& env) {
  env.sh_irradiance = convolve_clamped_cosine(project_sh(env.sky));
}

std::vector<LatLong> build_mips(const LatLong& map) {
  if (map.width <= 0 || map.height <= 0 || map.rgb.size() != size_t(map.width) * size_t(map.height) * 3)
    throw std::invalid_argument("build_mips: lat-long map is empty or its data size does not match");
  std::vector<LatLong> levels{map};
  while (levels.back().width > 1 || levels.back().height > 1) {
    const LatLong& s = levels.back();
    LatLong d;
    d.width = std::max(1, s.width / 2);
    d.height = std::max(1, s.height / 2);
    d.color_space = s.color_space;
    d.rgb.assign(size_t(d.width) * size_t(d.height) * 3, 0.0f);
    for (int y = 0; y < d.height; ++y) {
      // Source rows [y0, y1): 2 rows, 3 for the last one of an odd height, 1 if the source has 1.
      int y0 = int(int64_t(y) * s.height / d.height), y1 = int(int64_t(y + 1) * s.height / d.height);
      for (int x = 0; x < d.width; ++x) {
        int x0 = int(int64_t(x) * s.width / d.width), x1 = int(int64_t(x + 1) * s.width / d.width);
        glm::vec3 sum(0.0f);
        for (int yy = y0; yy < y1; ++yy)
          for (int xx = x0; xx < x1; ++xx) sum += s.texel(xx, yy);
        d.set_texel(x, y, sum / float((y1 - y0) * (x1 - x0)));
      }
    }
    levels.push_back(std::move(d));
  }
  return levels;
}

}  // namespace glintlab::core
