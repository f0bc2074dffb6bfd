// Environment light: lat-long mapping, Preetham sky, SH irradiance against fp64 quadrature and
// closed forms, mips, HDR/EXR loading.
#include "core/scene/environment.h"
#include "core/util/json_check.h"
#include "core/scene/sky_preetham.h"
#include "core/scene/spherical_harmonics.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

using namespace glintlab;
using namespace glintlab::core;

namespace {

LatLong map_of(int W, const std::function<glm::dvec3(glm::dvec3)>& L) {
  LatLong m;
  m.width = W;
  m.height = W / 2;
  m.rgb.resize(size_t(W) * m.height * 3);
  for (int j = 0; j < m.height; ++j)
    for (int i = 0; i < W; ++i)
      m.set_texel(i, j, glm::vec3(L(glm::dvec3(latlong_direction({(i + 0.5f) / W, (j + 0.5f) / m.height})))));
  return m;
}

// E(n) = ∫ L max(0, n·ω) dω of the piecewise-constant map, by dense fp64 quadrature: every texel
// split into s x s sub-cells with exact solid angle sin θ dθ dφ.
glm::dvec3 brute_force_irradiance(const LatLong& m, glm::dvec3 n, int s = 4) {
  glm::dvec3 E(0.0);
  const int W = m.width, H = m.height;
  for (int j = 0; j < H; ++j)
    for (int jj = 0; jj < s; ++jj) {
      double t0 = M_PI * (j + double(jj) / s) / H, t1 = M_PI * (j + double(jj + 1) / s) / H;
      double tc = 0.5 * (t0 + t1), domega = (std::cos(t0) - std::cos(t1)) * 2.0 * M_PI / (W * s);
      for (int i = 0; i < W; ++i) {
        glm::dvec3 L(m.texel(i, j));
        for (int ii = 0; ii < s; ++ii) {
          double p = 2.0 * M_PI * (i + (ii + 0.5) / s) / W;
          glm::dvec3 w(std::sin(tc) * std::cos(p), std::cos(tc), std::sin(tc) * std::sin(p));
          E += L * std::max(0.0, glm::dot(n, w)) * domega;
        }
      }
    }
  return E;
}

double rel(glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) / glm::length(b); }

const glm::dvec3 kNormals[] = {
    {0, 1, 0}, {0, -1, 0},                                        // straight up, straight down
    {1, 0, 0}, {-1, 0, 0}, {0, 0, 1},                             // horizontal
    {0.5, 0.0871557, 0.86}, {0.3, -0.2, -0.93},                   // grazing, slightly down
};

}  // namespace

TEST(Environment, LatLongMappingConventions) {
  auto near2 = [](glm::vec2 a, glm::vec2 b) { return glm::length(a - b) < 1e-6f; };
  EXPECT_NEAR(latlong_uv({0, 1, 0}).y, 0.0f, 1e-7f);   // zenith = row 0
  EXPECT_NEAR(latlong_uv({0, -1, 0}).y, 1.0f, 1e-7f);
  EXPECT_TRUE(near2(latlong_uv({1, 0, 0}), {0.0f, 0.5f}));    // u = 0 is +X
  EXPECT_TRUE(near2(latlong_uv({0, 0, 1}), {0.25f, 0.5f}));   // u = 0.25 is +Z
  EXPECT_TRUE(near2(latlong_uv({-1, 0, 0}), {0.5f, 0.5f}));
  EXPECT_TRUE(near2(latlong_uv({0, 0, -3}), {0.75f, 0.5f}));  // need not be unit
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> U(0.001f, 0.999f);
  for (int k = 0; k < 100; ++k) {
    glm::vec2 uv(U(rng), U(rng));
    EXPECT_LT(glm::length(latlong_uv(latlong_direction(uv)) - uv), 2e-5f);
  }
  glm::vec3 s = direction_from_elevation_azimuth(30.0, 90.0);
  EXPECT_NEAR(s.x, 0.0f, 1e-6f);
  EXPECT_NEAR(s.y, 0.5f, 1e-6f);
  EXPECT_NEAR(s.z, std::sqrt(3.0f) / 2.0f, 1e-6f);
  EXPECT_THROW(latlong_uv({0, 0, 0}), std::invalid_argument);
}

TEST(Environment, BilinearSampleReproducesTexelCentresAndWrapsU) {
  LatLong m = map_of(16, [](glm::dvec3 d) { return glm::dvec3(d.x + 2.0, d.y + 2.0, 1.0); });
  EXPECT_EQ(m.sample(glm::vec2(3.5f / 16, 2.5f / 8)), m.texel(3, 2));
  // At u = 0 the sample is the average of the first and last column (u repeats).
  glm::vec3 seam = m.sample(glm::vec2(0.0f, 2.5f / 8));
  glm::vec3 avg = 0.5f * (m.texel(0, 2) + m.texel(15, 2));
  EXPECT_LT(glm::length(seam - avg), 1e-6f);
}

TEST(SphericalHarmonics, ConstantMapIsBandZeroAndIrradianceIsPiL) {
  const glm::dvec3 c(0.7, 1.3, 2.1);
  LatLong m = map_of(64, [&](glm::dvec3) { return c; });
  SH9 L = project_sh(m);
  // L_00 = c ∫ Y_00 dω = c 2 sqrt(π).
  EXPECT_LT(rel(glm::dvec3(L[0]), c * 2.0 * std::sqrt(M_PI)), 1e-6);
  for (int k = 1; k < 9; ++k) EXPECT_LT(glm::length(L[k]), 1e-6f) << "coefficient " << k;
  SH9 E = convolve_clamped_cosine(L);
  for (glm::dvec3 n : kNormals) EXPECT_LT(rel(glm::dvec3(eval_sh_irradiance(E, glm::vec3(n))), M_PI * c), 1e-4);
}

TEST(SphericalHarmonics, QuadraticMapMatchesClosedFormIrradiance) {
  // L(ω) = a + b (ω·d) + c (ω·d)² has only l <= 2, so the SH result is exact up to the map's
  // discretisation. Funk-Hecke with the clamped cosine (R&H 2001): P_l(ω·d) -> Â_l P_l(n·d), so
  // with μ = n·d: E(n) = π a + (2π/3) b μ + c (π/3 + (2/3)(π/4) P_2(μ)).
  const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, 0.8, -0.5));
  const double a = 2.0, b = 1.5, c = 0.8;
  LatLong m = map_of(256, [&](glm::dvec3 w) {
    double t = glm::dot(w, d);
    return glm::dvec3(a + b * t + c * t * t);
  });
  SH9 E = convolve_clamped_cosine(project_sh(m));
  for (glm::dvec3 n : kNormals) {
    n = glm::normalize(n);
    double mu = glm::dot(n, d);
    // (ω·d)² = 1/3 + (2/3) P_2; Â_0 = π, Â_1 = 2π/3, Â_2 = π/4, P_2(μ) = (3μ² - 1)/2.
    double ref = M_PI * a + 2.0 * M_PI / 3.0 * b * mu + c * (M_PI / 3.0 + (2.0 / 3.0) * (M_PI / 4.0) * 0.5 * (3 * mu * mu - 1));
    EXPECT_NEAR(eval_sh_irradiance(E, glm::vec3(n)).x / ref, 1.0, 2e-4) << "n = " << n.x << "," << n.y << "," << n.z;
  }
}

TEST(SphericalHarmonics, PreethamSkyIrradianceMatchesQuadratureWithinTruncationError) {
  SkySpec spec;
  spec.resolution = 128;
  spec.turbidity = 3.0f;
  spec.sun.direction = direction_from_elevation_azimuth(35.0, 20.0);
  Environment env = make_procedural_sky(spec);
  compute_sh_irradiance(env);
  std::vector<glm::dvec3> normals(std::begin(kNormals), std::end(kNormals));
  normals.push_back(glm::dvec3(spec.sun.direction));
  normals.push_back(-glm::dvec3(spec.sun.direction));
  for (glm::dvec3 n : normals) {
    n = glm::normalize(n);
    glm::dvec3 ref = brute_force_irradiance(env.sky, n);
    glm::dvec3 sh(eval_sh_irradiance(env.sh_irradiance, glm::vec3(n)));
    EXPECT_LT(rel(sh, ref), 0.03) << "n = " << n.x << "," << n.y << "," << n.z;
  }
}

TEST(SphericalHarmonics, BrightLobeLightsTheNormalFacingIt) {
  for (glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0)}) {
    LatLong m = map_of(64, [&](glm::dvec3 w) { return glm::dvec3(0.1 + 20.0 * std::pow(std::max(0.0, glm::dot(w, axis)), 8.0)); });
    SH9 E = convolve_clamped_cosine(project_sh(m));
    glm::dvec3 side = glm::cross(axis, glm::dvec3(0.3, 0.5, 0.8));
    side = glm::normalize(side);
    double toward = eval_sh_irradiance(E, glm::vec3(axis)).x, away = eval_sh_irradiance(E, glm::vec3(-axis)).x;
    double s1 = eval_sh_irradiance(E, glm::vec3(side)).x, s2 = eval_sh_irradiance(E, glm::vec3(-side)).x;
    EXPECT_GT(toward, 5.0 * away);
    EXPECT_NEAR(s1 / s2, 1.0, 1e-3);  // symmetric about the lobe axis
    EXPECT_NEAR(toward / brute_force_irradiance(m, axis, 2).x, 1.0, 0.05);
  }
}

TEST(PreethamSky, BehavesLikeAClearSky) {
  const glm::dvec3 sun = glm::dvec3(direction_from_elevation_azimuth(30.0, 0.0));
  PreethamSky sky(3.0, sun);
  // Y is relative to the zenith.
  EXPECT_NEAR(sky.xyY({0, 1, 0}).z, 1.0, 1e-12);
  // Zenith chromaticity: bluish white, near the daylight locus (x, y in ~[0.24, 0.33]).
  glm::dvec2 xy = sky.zenith_chromaticity();
  EXPECT_GT(xy.x, 0.2);
  EXPECT_LT(xy.x, 0.33);
  EXPECT_GT(xy.y, 0.2);
  EXPECT_LT(xy.y, 0.35);
  // Absolute zenith luminance of a clear sky: a few kcd/m².
  EXPECT_GT(sky.zenith_luminance_kcd(), 1.0);
  EXPECT_LT(sky.zenith_luminance_kcd(), 15.0);
  // Circumsolar brightening: brighter next to the sun than opposite it at the same elevation.
  glm::dvec3 near_sun = glm::dvec3(direction_from_elevation_azimuth(30.0, 10.0));
  glm::dvec3 opposite = glm::dvec3(direction_from_elevation_azimuth(30.0, 180.0));
  EXPECT_GT(sky.xyY(near_sun).z, 2.0 * sky.xyY(opposite).z);
  // Turbidity outside the fit and a sun below the horizon are rejected.
  EXPECT_THROW(PreethamSky(1.0, sun), std::invalid_argument);
  EXPECT_THROW(PreethamSky(3.0, glm::dvec3(1, -0.2, 0)), std::invalid_argument);
}

TEST(Environment, ProceduralSkyMapHasNoSunDiskAndALitGround) {
  SkySpec spec;
  spec.resolution = 128;
  spec.sky_intensity = 2.0f;
  spec.ground_albedo = 0.25f;
  Environment env = make_procedural_sky(spec);
  const LatLong& m = env.sky;
  EXPECT_EQ(m.color_space, "CIE-XYZ-D65");
  EXPECT_EQ(m.width, 128);
  EXPECT_EQ(m.height, 64);
  double maxY = 0.0;
  for (size_t p = 0; p < m.rgb.size(); p += 3) {
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(m.rgb[p + c]) && m.rgb[p + c] >= 0.0f);
    maxY = std::max(maxY, double(m.rgb[p + 1]));
  }
  EXPECT_LT(maxY, 30.0 * spec.sky_intensity);  // a sun disk would be ~1e5 x the sky
  EXPECT_NEAR(m.texel(0, 0).y, spec.sky_intensity, 0.05 * spec.sky_intensity);  // zenith row
  // Nadir = Lambertian ground lit by the sky: ρ E_up / π, with E_up by independent quadrature.
  double E_up = 0.0;
  for (int j = 0; j < m.height / 2; ++j) {
    double t0 = M_PI * j / m.height, t1 = M_PI * (j + 1) / m.height;
    for (int i = 0; i < m.width; ++i)
      E_up += m.texel(i, j).y * std::cos(0.5 * (t0 + t1)) * (std::cos(t0) - std::cos(t1)) * 2.0 * M_PI / m.width;
  }
  EXPECT_NEAR(m.texel(7, m.height - 1).y, spec.ground_albedo * E_up / M_PI, 1e-4 * E_up);
  // Continuous across the horizon: the fade starts at the horizon colour (a wide fade so that the
  // first row below, 1.4° down, is still almost all horizon).
  spec.ground_fade_deg = 30.0f;
  const LatLong& f = make_procedural_sky(spec).sky;
  for (int i = 0; i < f.width; i += 9) {
    double above = f.texel(i, f.height / 2 - 1).y, below = f.texel(i, f.height / 2).y;
    EXPECT_NEAR(below / above, 1.0, 0.05) << "column " << i;
  }
  EXPECT_NEAR(f.texel(7, f.height - 1).y, spec.ground_albedo * E_up / M_PI, 1e-4 * E_up);
  EXPECT_EQ(env.sun.direction, spec.sun.direction);
}

TEST(Environment, MipChainIsABoxPyramid) {
  LatLong m;
  m.width = 10;
  m.height = 5;
  m.rgb.resize(150);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> U(0.0f, 4.0f);
  for (float& v : m.rgb) v = U(rng);
  auto mips = build_mips(m);
  ASSERT_EQ(mips.size(), 4u);  // 10x5, 5x2, 2x1, 1x1
  EXPECT_EQ(mips[1].width, 5);
  EXPECT_EQ(mips[1].height, 2);
  EXPECT_EQ(mips[3].width, 1);
  EXPECT_EQ(mips[3].height, 1);
  glm::vec3 box = 0.25f * (m.texel(4, 0) + m.texel(5, 0) + m.texel(4, 1) + m.texel(5, 1));
  EXPECT_LT(glm::length(mips[1].texel(2, 0) - box), 1e-6f);
  // Odd height 5 -> 2: the last row averages source rows 2..4.
  glm::vec3 tall(0.0f);
  for (int y = 2; y < 5; ++y) tall += m.texel(0, y) + m.texel(1, y);
  EXPECT_LT(glm::length(mips[1].texel(0, 1) - tall / 6.0f), 1e-6f);

  LatLong p = map_of(64, [](glm::dvec3 d) { return glm::dvec3(1.0 + d.x, 2.0 + d.y * d.z, 0.5); });
  auto pm = build_mips(p);
  ASSERT_EQ(pm.size(), 7u);  // 64x32 ... 2x1, 1x1
  glm::dvec3 mean(0.0);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) mean += glm::dvec3(p.texel(x, y));
  mean /= 64.0 * 32.0;
  EXPECT_LT(rel(glm::dvec3(pm.back().texel(0, 0)), mean), 1e-5);
}

TEST(Environment, LoadsLatLongFilesWithTheirColourSpace) {
  const std::string dir = ::testing::TempDir();
  auto write = [&](const std::string& name, int W, int H, const float* chroma) {
    std::string path = dir + name;
    OIIO::ImageSpec spec(W, H, 3, OIIO::TypeDesc::FLOAT);
    if (chroma) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma);
    std::vector<float> px(size_t(W) * H * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = 0.01f * float(i % 97);
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close());
    return path;
  };
  Sun sun;
  sun.intensity = 7.0f;
  std::string p709 = write("glintlab_env_709.exr", 16, 8, nullptr);
  Environment e = load_latlong(p709, sun);
  EXPECT_EQ(e.sky.width, 16);
  EXPECT_EQ(e.sky.height, 8);
  EXPECT_EQ(e.sky.color_space, "lin_rec709");
  EXPECT_EQ(e.sky.texel(5, 2).y, 0.01f * float(((2 * 16 + 5) * 3 + 1) % 97));
  EXPECT_EQ(e.sun.intensity, 7.0f);
  const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  EXPECT_EQ(read_latlong(write("glintlab_env_ap1.exr", 16, 8, ap1)).color_space, "ACEScg");
  EXPECT_EQ(read_latlong(p709, "ACES2065-1").color_space, "ACES2065-1");  // explicit override
  try {
    read_latlong(dir + "glintlab_no_such_sky.hdr");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("glintlab_no_such_sky.hdr"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_latlong(write("glintlab_env_square.exr", 8, 8, nullptr)), std::runtime_error);
}

TEST(Environment, SkySpecFromJsonValidates) {
  nlohmann::json ok = {{"turbidity", 4}, {"sun_elevation_deg", 90}, {"sun_color", {1, 0.9, 0.8}},
                       {"sun_color_space", "ACEScg"}, {"sun_intensity", 12}};
  JsonReader r(ok, "exp.json", "sky");
  SkySpec s = SkySpec::from_json(r);
  EXPECT_EQ(s.turbidity, 4.0f);
  EXPECT_NEAR(s.sun.direction.y, 1.0f, 1e-6f);
  EXPECT_EQ(s.sun.color_space, "ACEScg");
  EXPECT_EQ(s.sun.intensity, 12.0f);

  auto error_of = [](nlohmann::json j) {
    JsonReader rr(j, "exp.json", "sky");
    try {
      SkySpec::from_json(rr);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of({{"turbidity", 12}}).find("sky.turbidity"), std::string::npos);
  EXPECT_NE(error_of({{"sun_direction", {0, 1, 0}}, {"sun_elevation_deg", 10}}).find("sun_direction"), std::string::npos);
  EXPECT_NE(error_of({{"sun_elevation_deg", -5}}).find("sun_elevation_deg"), std::string::npos);
  EXPECT_NE(error_of({{"hdri", "sky.exr"}, {"turbidity", 3}}).find("turbidity"), std::string::npos);  // not an hdri key
  EXPECT_NE(error_of({{"sun_intensty", 3}}).find("sun_intensty"), std::string::npos);
  nlohmann::json h = {{"hdri", "maps/sky.exr"}};
  JsonReader rh(h, "/data/experiments/exp.json", "sky");
  EXPECT_EQ(SkySpec::from_json(rh).hdri, "/data/experiments/maps/sky.exr");  // relative to the file
}
