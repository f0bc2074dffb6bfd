// make_contact_sheet (experiments/runner/contact_sheet.h): the documented layout, tile placement, mean
// preservation of the box downscale, labels staying out of tiles, and input errors.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "experiments/runner/contact_sheet.h"

using glintlab::Image;
using glintlab::SheetTile;
using glintlab::kContactSheetGap;
using glintlab::make_contact_sheet;

namespace {

Image solid(int w, int h, float r, float g, float b) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      img.at(x, y, 0) = r;
      img.at(x, y, 1) = g;
      img.at(x, y, 2) = b;
    }
  return img;
}

// Distinct colour per grid cell, exactly representable.
float cell_value(int r, int c, int k) { return float(1 + r * 3 + c) / 8.0f * (k == 0 ? 1.0f : k == 1 ? 0.5f : 0.25f); }

std::vector<std::vector<SheetTile>> grid(int n_rows, int n_cols, int w, int h) {
  std::vector<std::vector<SheetTile>> rows(n_rows);
  for (int r = 0; r < n_rows; ++r)
    for (int c = 0; c < n_cols; ++c)
      rows[r].push_back({"v" + std::to_string(r) + "-f" + std::to_string(c),
                         solid(w, h, cell_value(r, c, 0), cell_value(r, c, 1), cell_value(r, c, 2))});
  return rows;
}

}  // namespace

TEST(ContactSheet, LayoutSizeOfTwoByThreeGrid) {
  const int g = kContactSheetGap, label = 20;
  // 2 variants x 3 frames of 64x36: no downscale.
  Image s = make_contact_sheet(grid(2, 3, 64, 36), 320, label);
  EXPECT_EQ(s.channels, 4);
  EXPECT_EQ(s.width, g + 3 * (64 + g));
  EXPECT_EQ(s.height, g + 2 * (label + 36 + g));
  // 640x360 tiles capped at 160 wide -> 160x90.
  Image d = make_contact_sheet(grid(2, 3, 640, 360), 160, label);
  EXPECT_EQ(d.width, g + 3 * (160 + g));
  EXPECT_EQ(d.height, g + 2 * (label + 90 + g));
}

TEST(ContactSheet, SolidTilesLandAtTheirPlace) {
  const int g = kContactSheetGap, label = 20, w = 24, h = 10;
  Image s = make_contact_sheet(grid(2, 3, w, h), 320, label);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) {
      const int x0 = g + c * (w + g), y0 = g + r * (label + h + g) + label;
      // Every pixel of the tile (labels must not overwrite tiles), alpha 1.
      for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x)
          for (int k = 0; k < 3; ++k) ASSERT_FLOAT_EQ(s.at(x, y, k), cell_value(r, c, k)) << r << "," << c << " @" << x << "," << y;
      EXPECT_FLOAT_EQ(s.at(x0, y0, 3), 1.0f);
      // Just outside the tile: background (the gap to the right and below).
      for (int k = 0; k < 3; ++k) {
        EXPECT_FLOAT_EQ(s.at(x0 + w, y0 + h / 2, k), glintlab::kContactSheetBackground);
        EXPECT_FLOAT_EQ(s.at(x0 + w / 2, y0 + h, k), glintlab::kContactSheetBackground);
      }
    }
  // The top-left corner is gap background.
  EXPECT_FLOAT_EQ(s.at(0, 0, 0), glintlab::kContactSheetBackground);
  EXPECT_FLOAT_EQ(s.at(0, 0, 3), 1.0f);
}

TEST(ContactSheet, DownscalePreservesTileMean) {
  // Vertical stripes of period 7 and a horizontal ramp: a non-integer 200 -> 64 reduction.
  const int w = 200, h = 100;
  Image t(w, h, 3);
  double mean[3] = {0, 0, 0};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v[3] = {x % 7 < 3 ? 1.0f : 0.0f, float(y) / (h - 1), 0.25f};
      for (int k = 0; k < 3; ++k) {
        t.at(x, y, k) = v[k];
        mean[k] += v[k] / (double(w) * h);
      }
    }
  const int label = 0, g = kContactSheetGap, tw = 64, th = 32;  // 100 * 64 / 200
  Image s = make_contact_sheet({{SheetTile{"", t}}}, tw, label);
  ASSERT_EQ(s.width, g + tw + g);
  ASSERT_EQ(s.height, g + th + g);
  double got[3] = {0, 0, 0};
  for (int y = g; y < g + th; ++y)
    for (int x = g; x < g + tw; ++x)
      for (int k = 0; k < 3; ++k) got[k] += s.at(x, y, k) / (double(tw) * th);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], mean[k], 0.01) << "channel " << k;
  // The stripes (period 7 px -> 2.24 px) must be averaged, not point-sampled: no pure 0/1 columns.
  int extremes = 0;
  for (int x = g; x < g + tw; ++x) extremes += s.at(x, g + th / 2, 0) < 0.02f || s.at(x, g + th / 2, 0) > 0.98f;
  EXPECT_LT(extremes, tw / 4);
}

TEST(ContactSheet, AlphaTilesAreCompositedOverBackground) {
  Image t(4, 4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      t.at(x, y, 0) = t.at(x, y, 1) = t.at(x, y, 2) = 1.0f;
      t.at(x, y, 3) = 0.5f;
    }
  Image s = make_contact_sheet({{SheetTile{"", t}}}, 320, 0);
  const int g = kContactSheetGap;
  EXPECT_FLOAT_EQ(s.at(g, g, 0), 0.5f * 1.0f + 0.5f * glintlab::kContactSheetBackground);
  EXPECT_FLOAT_EQ(s.at(g, g, 3), 1.0f);
}

TEST(ContactSheet, LabelsAreDrawnWhenAFontExists) {
  if (!glintlab::contact_sheet_has_font()) GTEST_SKIP() << "no font for OpenImageIO (install fonts-dejavu-core)";
  const int g = kContactSheetGap, label = 20;
  Image s = make_contact_sheet({{SheetTile{"WWWW", solid(80, 20, 0, 0, 0)}}}, 320, label);
  int lit = 0;
  for (int y = g; y < g + label; ++y)
    for (int x = g; x < g + 80; ++x) lit += s.at(x, y, 0) > 0.5f;
  EXPECT_GT(lit, 10);
}

TEST(ContactSheet, RejectsEmptyInput) {
  EXPECT_THROW(make_contact_sheet({}), std::invalid_argument);
  EXPECT_THROW(make_contact_sheet({{}, {}}), std::invalid_argument);
  EXPECT_THROW(make_contact_sheet({{SheetTile{"empty", Image()}}}), std::invalid_argument);
  EXPECT_THROW(make_contact_sheet(grid(1, 1, 4, 4), 0), std::invalid_argument);
  try {
    make_contact_sheet({{SheetTile{"a", solid(2, 2, 0, 0, 0)}, SheetTile{"frame-7", Image()}}});
    ADD_FAILURE() << "empty tile accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("frame-7"), std::string::npos) << e.what();
  }
}
