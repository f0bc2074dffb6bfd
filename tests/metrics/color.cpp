// ColorManager against the shipped OCIO config: published constants (BT.709, IEC 61966-2-1 sRGB,
// SMPTE ST 2084 PQ, ACES AP1) and fp64 references computed here from the primaries.
#include "tests/support/temp_dir.h"
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include <OpenColorIO/OpenColorIO.h>
#include <unistd.h>

#include "metrics/color/color_manager.h"

namespace OCIO = OCIO_NAMESPACE;
using glintlab::Image;
using glintlab::metrics::ColorManager;

namespace {

using M3 = std::array<std::array<double, 3>, 3>;
using V3 = std::array<double, 3>;

V3 mul(const M3& m, const V3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}
M3 mul(const M3& a, const M3& b) {
  M3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}
M3 inverse(const M3& m) {
  const double d = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                   m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  M3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      r[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / d;
    }
  return r;
}
V3 xy_to_XYZ(double x, double y) { return {x / y, 1.0, (1.0 - x - y) / y}; }

// Bradford von Kries adaptation from white ws to white wd (Lam 1985; Lindbloom's matrix).
M3 bradford(const V3& ws, const V3& wd) {
  const M3 B = {{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
  const V3 s = mul(B, ws), d = mul(B, wd);
  const M3 D = {{{d[0] / s[0], 0, 0}, {0, d[1] / s[1], 0}, {0, 0, d[2] / s[2]}}};
  return mul(inverse(B), mul(D, B));
}

// Encoding per IEC 61966-2-1 (fp64 reference).
double srgb_encode(double L) { return L <= 0.0031308 ? 12.92 * L : 1.055 * std::pow(L, 1.0 / 2.4) - 0.055; }

// SMPTE ST 2084 inverse EOTF, L in cd/m^2 (fp64 reference).
double pq_encode(double nits) {
  const double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0, c1 = 3424.0 / 4096.0,
               c2 = 2413.0 / 4096.0 * 32.0, c3 = 2392.0 / 4096.0 * 32.0;
  const double Y = std::pow(nits / 10000.0, m1);
  return std::pow((c1 + c2 * Y) / (1.0 + c3 * Y), m2);
}

const ColorManager& cm() {
  static ColorManager m(GLINTLAB_OCIO_CONFIG);
  return m;
}

// Sets an environment variable for the lifetime of the guard and restores the previous value.
class EnvGuard {
 public:
  EnvGuard(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~EnvGuard() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace

TEST(ColorConfig, ShippedConfigLoadsAndValidates) {
  auto config = OCIO::Config::CreateFromFile(GLINTLAB_OCIO_CONFIG);
  EXPECT_NO_THROW(config->validate());
  EXPECT_EQ(config->getMajorVersion(), 2u);
  EXPECT_LE(config->getMinorVersion(), 1u);  // readable by OCIO 2.1
  for (const char* space : {"lin_rec709", "ACEScg", "ACES2065-1", "CIE-XYZ-D65", "sRGB", "raw"})
    EXPECT_TRUE(cm().has_space(space)) << space;
  EXPECT_EQ(cm().canonical_name("scene_linear"), "lin_rec709");
  EXPECT_EQ(cm().canonical_name("linear"), "lin_rec709");
  EXPECT_EQ(cm().canonical_name("Linear"), "lin_rec709");  // OIIO's oiio:ColorSpace tag of EXR files
  EXPECT_EQ(cm().canonical_name("sRGB"), "sRGB");          // ... and of 8-bit PNG files
  EXPECT_EQ(cm().canonical_name("data"), "raw");
  EXPECT_FALSE(cm().has_space("no-such-space"));
  const auto views = cm().views("Rec.2100-PQ");
  EXPECT_NE(std::find(views.begin(), views.end(), "Standard"), views.end());
}

TEST(ColorConfig, Rec709WhiteAndPrimariesToXyz) {
  const glm::vec3 w = cm().convert_color({1, 1, 1}, "lin_rec709", "CIE-XYZ-D65");
  EXPECT_NEAR(w.x, 0.950456, 1e-4);
  EXPECT_NEAR(w.y, 1.0, 1e-4);
  EXPECT_NEAR(w.z, 1.089058, 1e-4);
  // BT.709 primaries (ITU-R BT.709-6 table 1) as xy of the converted unit vectors.
  const double p[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
  for (int i = 0; i < 3; ++i) {
    glm::vec3 rgb(0.0f);
    rgb[i] = 1.0f;
    const glm::vec3 X = cm().convert_color(rgb, "lin_rec709", "XYZ");
    const double s = double(X.x) + X.y + X.z;
    EXPECT_NEAR(X.x / s, p[i][0], 1e-5) << i;
    EXPECT_NEAR(X.y / s, p[i][1], 1e-5) << i;
  }
}

TEST(ColorConfig, RoundTripsAreIdentity) {
  Image img(4, 2, 4);
  const float values[8][3] = {{1, 1, 1}, {0.18f, 0.18f, 0.18f}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                              {0.3f, 0.02f, 0.7f}, {12.5f, 3.0f, 0.25f}, {0, 0, 0}};
  for (int i = 0; i < 8; ++i)
    for (int c = 0; c < 3; ++c) img.data[i * 4 + c] = values[i][c];
  for (const char* via : {"ACEScg", "CIE-XYZ-D65", "ACES2065-1", "ACEScct", "sRGB"}) {
    Image t = img;
    cm().convert(t, "lin_rec709", via);
    cm().convert(t, via, "lin_rec709");
    for (std::size_t i = 0; i < t.data.size(); ++i)
      EXPECT_NEAR(t.data[i], img.data[i], 1e-5 * std::max(1.0f, std::abs(img.data[i]))) << via << " " << i;
  }
}

TEST(ColorConfig, AcesCgPrimariesArePublishedAp1) {
  // The config adapts ACES white to D65 with Bradford (OCIO's *_BFD builtins); undoing that
  // adaptation in fp64 must give the AP1 primaries of SMPTE S-2014-004.
  const V3 w_aces = xy_to_XYZ(0.32168, 0.33767), w_d65 = xy_to_XYZ(0.3127, 0.3290);
  const M3 to_aces_white = bradford(w_d65, w_aces);
  const double ap1[4][2] = {{0.713, 0.293}, {0.165, 0.830}, {0.128, 0.044}, {0.32168, 0.33767}};
  for (int i = 0; i < 4; ++i) {
    glm::vec3 rgb(i == 3 ? 1.0f : 0.0f);
    if (i < 3) rgb[i] = 1.0f;
    const glm::vec3 X = cm().convert_color(rgb, "ACEScg", "CIE-XYZ-D65");
    const V3 Xa = mul(to_aces_white, V3{X.x, X.y, X.z});
    const double s = Xa[0] + Xa[1] + Xa[2];
    EXPECT_NEAR(Xa[0] / s, ap1[i][0], 2e-4) << "primary " << i;
    EXPECT_NEAR(Xa[1] / s, ap1[i][1], 2e-4) << "primary " << i;
  }
  // ACEScg white is scene white: Y = 1 and D65 chromaticity after adaptation.
  const glm::vec3 W = cm().convert_color({1, 1, 1}, "ACEScg", "CIE-XYZ-D65");
  EXPECT_NEAR(W.x, 0.950456, 2e-4);
  EXPECT_NEAR(W.y, 1.0, 1e-4);
  EXPECT_NEAR(W.z, 1.089058, 2e-4);
}

TEST(ColorConfig, SrgbEncodingMatchesIec61966) {
  // Published: linear 0.5 -> 0.7354 (IEC 61966-2-1); linear segment below 0.0031308.
  const glm::vec3 half = cm().convert_color({0.5f, 0.5f, 0.5f}, "lin_rec709", "sRGB");
  EXPECT_NEAR(half.x, 0.7354, 1e-4);
  for (float L : {0.001f, 0.0031308f, 0.01f, 0.2f, 0.9f}) {
    const glm::vec3 e = cm().convert_color({L, L, L}, "lin_rec709", "sRGB");
    // OCIO's ExponentWithLinearTransform uses the C1-continuous toe (slope 12.923, break 0.00304)
    // rather than IEC's rounded 12.92 / 0.0031308: <= 3.3e-6 apart, 1/1000 of an 8-bit code.
    EXPECT_NEAR(e.y, srgb_encode(L), 4e-6) << L;
  }
  // The sRGB display's Standard view: same encoding, clamped to [0, 1].
  Image img(3, 1, 4, 1.0f);
  img.data = {0.5f, 0.5f, 0.5f, 0.25f, 4.0f, 4.0f, 4.0f, 1.0f, -1.0f, 0.0f, 0.5f, 1.0f};
  const Image d = cm().display(img, "lin_rec709", "sRGB", "Standard");
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(d.at(0, 0, c), 0.7354, 1e-4);
    EXPECT_NEAR(d.at(1, 0, c), 1.0, 1e-5);
  }
  EXPECT_NEAR(d.at(2, 0, 0), 0.0, 1e-6);
  EXPECT_NEAR(d.at(2, 0, 2), srgb_encode(0.5), 1e-4);
  EXPECT_EQ(d.at(0, 0, 3), 0.25f);  // alpha copied
}

TEST(ColorConfig, Rec2100PqDisplayOfSceneWhite) {
  // Scene 1.0 = 100 cd/m^2; PQ(100 cd/m^2) = 0.5081 (SMPTE ST 2084).
  ASSERT_NEAR(pq_encode(100.0), 0.5081, 1e-4);
  Image img(2, 1, 3);
  img.data = {1, 1, 1, 0.1f, 0.1f, 0.1f};
  const Image d = cm().display(img, "lin_rec709", "Rec.2100-PQ", "Standard");
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(d.at(0, 0, c), pq_encode(100.0), 5e-4) << c;
    EXPECT_NEAR(d.at(1, 0, c), pq_encode(10.0), 5e-4) << c;
  }
}

TEST(ColorConfig, ConvertLeavesAlphaUntouched) {
  Image img(2, 1, 4);
  img.data = {0.2f, 0.4f, 0.6f, 0.5f, 3.0f, 0.0f, 1.0f, -2.0f};
  cm().convert(img, "lin_rec709", "ACES2065-1");
  EXPECT_EQ(img.data[3], 0.5f);
  EXPECT_EQ(img.data[7], -2.0f);
  EXPECT_NE(img.data[0], 0.2f);  // the colour did change
  const Image xyz = cm().to_xyz_d65(img, "ACES2065-1");
  EXPECT_EQ(xyz.data[3], 0.5f);
  Image grey(1, 1, 1);
  EXPECT_THROW(cm().convert(grey, "lin_rec709", "ACEScg"), std::invalid_argument);
}

// RGBA is converted through OCIO's RGBA path in bands of rows: the colours are those of the same
// image as RGB to the bit, and alpha stays as it was, also beside infinite and NaN colours (where
// OCIO's matrix would write NaN into it) and across the bands' edges.
TEST(ColorConfig, RgbaConvertsLikeRgbAndKeepsAlpha) {
  const int w = 7, h = 37;  // more rows than a band, and not a multiple of it
  Image rgba(w, h, 4), rgb(w, h, 3);
  for (int i = 0; i < w * h; ++i)
    for (int c = 0; c < 4; ++c) {
      const float v = float(std::sin(1.3 * i + 0.7 * c)) * 2.0f;
      rgba.data[4 * size_t(i) + c] = v;
      if (c < 3) rgb.data[3 * size_t(i) + c] = v;
    }
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (Image* im : {&rgba, &rgb}) {
    im->at(1, 0, 0) = inf, im->at(2, 16, 1) = nan, im->at(3, 36, 2) = -inf;
  }
  const Image before = rgba;
  cm().convert(rgba, "lin_rec709", "CIE-XYZ-D65");
  cm().convert(rgb, "lin_rec709", "CIE-XYZ-D65");
  for (int i = 0; i < w * h; ++i) {
    for (int c = 0; c < 3; ++c) {
      const float a = rgba.data[4 * size_t(i) + c], b = rgb.data[3 * size_t(i) + c];
      EXPECT_TRUE(std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b))) << i << " " << c;
    }
    EXPECT_EQ(std::memcmp(&rgba.data[4 * size_t(i) + 3], &before.data[4 * size_t(i) + 3], sizeof(float)), 0) << i;
  }
  EXPECT_NE(rgba.at(0, 0, 0), before.at(0, 0, 0));  // the colours did change
}

// A conversion runs over bands of 16 rows on the metric threads: the colours are those of converting the
// image one row at a time (another grouping of the same per-pixel calls), to the bit, RGB and RGBA alike,
// for a display transform (ACES 1.0 SDR-video, the view temporal_score sees through) and a plain
// conversion.
TEST(ColorConfig, BandsOnTheMetricThreadsEqualOneRowAtATime) {
  for (int channels : {3, 4}) {
    const int w = 37, h = 53;
    Image img(w, h, channels);
    for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(4.0 * std::abs(std::sin(0.37 * double(i))));
    const Image whole = cm().display_referred_xyz(img, "lin_rec709", "sRGB", "ACES 1.0 SDR-video");
    Image plain = img;
    cm().convert(plain, "lin_rec709", "ACEScg");
    for (int y = 0; y < h; ++y) {
      Image row(w, 1, channels);
      std::copy(img.px(0, y), img.px(0, y) + std::size_t(w) * channels, row.data.begin());
      Image row_plain = row;
      const Image shown = cm().display_referred_xyz(row, "lin_rec709", "sRGB", "ACES 1.0 SDR-video");
      cm().convert(row_plain, "lin_rec709", "ACEScg");
      EXPECT_EQ(std::memcmp(shown.data.data(), whole.px(0, y), sizeof(float) * std::size_t(w) * channels), 0)
          << channels << " channels, row " << y;
      EXPECT_EQ(std::memcmp(row_plain.data.data(), plain.px(0, y), sizeof(float) * std::size_t(w) * channels), 0)
          << channels << " channels, row " << y;
    }
  }
}

TEST(ColorConfig, UnknownSpaceErrorNamesItAndListsAllowed) {
  Image img(1, 1, 3);
  try {
    cm().convert(img, "lin_rec709", "ProPhotoRGB-nope");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("ProPhotoRGB-nope"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ACEScg"), std::string::npos) << msg;
  }
  try {
    (void)cm().display(img, "lin_rec709", "sRGB", "NoSuchView");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("NoSuchView"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("Standard"), std::string::npos);
  }
}

TEST(ColorConfig, ChromaticitiesForExr) {
  const auto r = cm().chromaticities("scene_linear");
  EXPECT_FLOAT_EQ(r[0], 0.64f);
  EXPECT_FLOAT_EQ(r[7], 0.3290f);
  EXPECT_FLOAT_EQ(cm().chromaticities("ACEScg")[2], 0.165f);
  EXPECT_FLOAT_EQ(cm().chromaticities("ACES2065-1")[5], -0.0770f);
  EXPECT_THROW((void)cm().chromaticities("sRGB"), std::invalid_argument);
}

TEST(ColorConfig, OcioEnvironmentOverride) {
  namespace fs = std::filesystem;
  const glintlab::test::TempDir tmp("color");
  const fs::path dir = tmp.path();
  const fs::path copy = dir / "other.ocio";
  fs::copy_file(GLINTLAB_OCIO_CONFIG, copy, fs::copy_options::overwrite_existing);
  {
    EnvGuard env("OCIO", copy.string());
    EXPECT_EQ(ColorManager::default_config_path(), copy.string());
    ColorManager m;
    EXPECT_EQ(m.config_path(), copy.string());
    EXPECT_TRUE(m.has_space("ACEScg"));
  }
  {
    const std::string missing = (dir / "missing.ocio").string();
    EnvGuard env("OCIO", missing);
    try {
      ColorManager m;
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
  }
  {
    const fs::path bad = dir / "bad.ocio";
    std::ofstream(bad) << "ocio_profile_version: 2\nthis is: [not a config\n";
    try {
      ColorManager m(bad.string());
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
    }
  }
  {
    EnvGuard env("OCIO", "");
    EXPECT_EQ(ColorManager::default_config_path(), std::string(GLINTLAB_OCIO_CONFIG));
  }
  fs::remove_all(dir);
}

TEST(ColorConfig, DisplayReferredXyzDecodesTheViewOutput) {
  ColorManager cm(GLINTLAB_OCIO_CONFIG);
  Image img(3, 1, 3);
  img.data = {0.5f, 0.5f, 0.5f, 2.0f, 2.0f, 2.0f, 0.2f, 0.0f, 0.0f};
  // sRGB/Standard clamps to [0, 1] and encodes; decoding gives back display XYZ:
  // in-range values equal their scene XYZ, values above 1 clip to white.
  Image d = cm.display_referred_xyz(img, "lin_rec709", "sRGB", "Standard");
  Image s = cm.to_xyz_d65(img, "lin_rec709");
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(d.data[c], s.data[c], 1e-4) << c;
    EXPECT_NEAR(d.data[6 + c], s.data[6 + c], 1e-4) << c;
  }
  EXPECT_NEAR(d.data[3], 0.950456, 1e-4);
  EXPECT_NEAR(d.data[4], 1.0, 1e-4);
  EXPECT_NEAR(d.data[5], 1.089058, 1e-4);
  // The PQ display keeps HDR: scene 2.0 (200 cd/m^2) stays 2.0 x white.
  Image p = cm.display_referred_xyz(img, "lin_rec709", "Rec.2100-PQ", "Standard");
  EXPECT_NEAR(p.data[4], 2.0, 2e-3);
  EXPECT_THROW(cm.display_referred_xyz(img, "lin_rec709", "sRGB", "Nope"), std::invalid_argument);
}
