#include "experiments/runner/contact_sheet.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace glintlab {

namespace {

// The first font OpenImageIO can load, or "" when none is found. OIIO's own default
// ("DroidSans") is not packaged on Debian; DejaVu (fonts-dejavu-core) usually is.
const std::string& label_font() {
  static const std::string font = [] {
    for (const char* name : {"DejaVuSans", "", "LiberationSans-Regular", "FreeSans"}) {
      OIIO::ImageBuf probe(OIIO::ImageSpec(16, 16, 1, OIIO::TypeDesc::FLOAT));
      if (OIIO::ImageBufAlgo::render_text(probe, 1, 12, "A", 10, name)) return std::string(name);
      (void)probe.geterror();  // clear the failed attempt's message
    }
    return std::string("<none>");
  }();
  return font;
}

// Tile -> RGBA (grey replicated, missing alpha = 1), area-averaged down to w x h: every output
// pixel is the exact coverage-weighted mean of the source pixels under it (a box filter as wide as
// one output pixel), so the tile's mean colour is preserved for any reduction ratio.
std::vector<float> downscale_rgba(const Image& img, int w, int h) {
  auto weights = [](int n_src, int n_dst) {  // per output index: (source index, weight) pairs
    std::vector<std::vector<std::pair<int, double>>> out(n_dst);
    const double scale = double(n_src) / n_dst;
    for (int i = 0; i < n_dst; ++i) {
      const double lo = i * scale, hi = (i + 1) * scale;
      for (int s = int(std::floor(lo)); s < n_src && s < hi; ++s) {
        const double cover = std::min(hi, s + 1.0) - std::max(lo, double(s));
        if (cover > 0) out[i].push_back({s, cover / scale});
      }
    }
    return out;
  };
  const auto wx = weights(img.width, w), wy = weights(img.height, h);
  std::vector<float> out(size_t(w) * h * 4);
  const bool grey = img.channels <= 2;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double acc[4] = {0, 0, 0, 0};
      for (const auto& [sy, fy] : wy[y])
        for (const auto& [sx, fx] : wx[x]) {
          const float* p = img.px(sx, sy);
          const double a = img.channels == 2 ? p[1] : img.channels == 4 ? p[3] : 1.0;
          for (int k = 0; k < 3; ++k) acc[k] += fx * fy * p[grey ? 0 : k];
          acc[3] += fx * fy * a;
        }
      for (int k = 0; k < 4; ++k) out[(size_t(y) * w + x) * 4 + k] = float(acc[k]);
    }
  return out;
}

}  // namespace

bool contact_sheet_has_font() { return label_font() != "<none>"; }

Image make_contact_sheet(const std::vector<std::vector<SheetTile>>& rows, int max_tile_width, int label_height) {
  if (max_tile_width < 1) throw std::invalid_argument("make_contact_sheet: max_tile_width must be >= 1");
  if (label_height < 0) throw std::invalid_argument("make_contact_sheet: label_height must be >= 0");
  size_t n_cols = 0;
  for (const auto& row : rows) n_cols = std::max(n_cols, row.size());
  if (rows.empty() || n_cols == 0) throw std::invalid_argument("make_contact_sheet: no tiles (no variants or no frames)");

  // Downscale every tile (box filter, aspect kept) and size the grid.
  struct Tile {
    int w, h;
    std::vector<float> rgba;
  };
  std::vector<std::vector<Tile>> tiles(rows.size());
  std::vector<int> col_w(n_cols, 0), row_h(rows.size(), 0);
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < rows[r].size(); ++c) {
      const SheetTile& t = rows[r][c];
      const std::string where = "make_contact_sheet: tile (" + std::to_string(r) + ", " + std::to_string(c) + ") \"" +
                                t.label + "\"";
      if (t.image.width < 1 || t.image.height < 1 || t.image.empty()) throw std::invalid_argument(where + " is empty");
      if (t.image.channels < 1 || t.image.channels > 4)
        throw std::invalid_argument(where + " has " + std::to_string(t.image.channels) + " channels; expected 1-4");
      if (t.image.data.size() != t.image.pixel_count() * size_t(t.image.channels))
        throw std::invalid_argument(where + ": data size does not match width x height x channels");
      const int w = std::min(t.image.width, max_tile_width);
      const int h = std::max(1, int(std::lround(double(t.image.height) * w / t.image.width)));
      tiles[r].push_back({w, h, downscale_rgba(t.image, w, h)});
      col_w[c] = std::max(col_w[c], w);
      row_h[r] = std::max(row_h[r], h);
    }

  const int gap = kContactSheetGap;
  std::vector<int> col_x(n_cols), row_y(rows.size());
  int width = gap, height = gap;
  for (size_t c = 0; c < n_cols; ++c) col_x[c] = width, width += col_w[c] + gap;
  for (size_t r = 0; r < rows.size(); ++r) row_y[r] = height + label_height, height += label_height + row_h[r] + gap;

  const float bg[4] = {kContactSheetBackground, kContactSheetBackground, kContactSheetBackground, 1.0f};
  OIIO::ImageBuf sheet(OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::fill(sheet, bg);

  const bool labels = label_height >= 6 && contact_sheet_has_font();
  const int font_size = std::max(6, label_height - 6);
  const float text_colour[4] = {0.9f, 0.9f, 0.9f, 1.0f};
  for (size_t r = 0; r < rows.size(); ++r)
    for (size_t c = 0; c < tiles[r].size(); ++c) {
      const Tile& t = tiles[r][c];
      // Composite over the background: out = a * tile + (1 - a) * bg, alpha 1.
      for (int y = 0; y < t.h; ++y)
        for (int x = 0; x < t.w; ++x) {
          const float* p = &t.rgba[(size_t(y) * t.w + x) * 4];
          const float a = std::clamp(p[3], 0.0f, 1.0f);
          float out[4];
          for (int k = 0; k < 3; ++k) out[k] = a * p[k] + (1.0f - a) * bg[k];
          out[3] = 1.0f;
          sheet.setpixel(col_x[c] + x, row_y[r] + y, out, 4);
        }
      if (labels && !rows[r][c].label.empty()) {
        // The strip above the tile, as wide as the column: text never touches a tile.
        OIIO::ROI strip(col_x[c], col_x[c] + col_w[c], row_y[r] - label_height, row_y[r], 0, 1, 0, 4);
        if (!OIIO::ImageBufAlgo::render_text(sheet, col_x[c] + 2, row_y[r] - 4, rows[r][c].label, font_size,
                                             label_font(), text_colour, OIIO::ImageBufAlgo::TextAlignX::Left,
                                             OIIO::ImageBufAlgo::TextAlignY::Baseline, 0, strip))
          (void)sheet.geterror();  // a label that cannot be drawn is left out, not an error
      }
    }

  Image out(width, height, 4);
  sheet.get_pixels(OIIO::ROI(0, width, 0, height, 0, 1, 0, 4), OIIO::TypeDesc::FLOAT, out.data.data());
  return out;
}

}  // namespace glintlab
