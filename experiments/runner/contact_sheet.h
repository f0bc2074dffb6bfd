// Contact sheet: one overview image of an experiment's saved frames, one row per variant and one
// column per frame, each tile labelled above with its name. Pure image layout (no colour
// management): tiles come in display-encoded and are copied as they are.
//
// Layout (all in pixels, gap = kContactSheetGap):
//   tile (r, c) of size w x h is box-downscaled to w' = min(w, max_tile_width),
//   h' = max(1, round(h * w' / w)); column c is as wide as its widest tile (col_w[c]), row r as tall
//   as its tallest (row_h[r]);
//   sheet width  = gap + sum_c (col_w[c] + gap),
//   sheet height = gap + sum_r (label_height + row_h[r] + gap);
//   tile (r, c) has its top-left corner at
//   x = gap + sum_{c' < c} (col_w[c'] + gap),  y = gap + sum_{r' < r} (label_height + row_h[r'] + gap) + label_height;
//   its label is drawn in the label_height strip above it (clipped to the column), when a font is
//   found (contact_sheet_has_font()); without one the strip stays empty.
// Rows may have different lengths (missing tiles leave background).
#pragma once

#include "core/util/image.h"

#include <string>
#include <vector>

namespace glintlab {

struct SheetTile {
  std::string label;
  Image image;  // display-encoded RGB(A) (1 = grey, 2 = grey + alpha, 3, 4 channels) in [0, 1]
};

constexpr int kContactSheetGap = 4;
// Background of the sheet (display-encoded dark grey), alpha 1.
constexpr float kContactSheetBackground = 0.15f;

// Returns a 4-channel image (alpha 1 everywhere; tiles with alpha are composited over the
// background). Throws std::invalid_argument for no tiles at all, an empty tile image, an
// unsupported channel count, max_tile_width < 1 or label_height < 0.
Image make_contact_sheet(const std::vector<std::vector<SheetTile>>& rows, int max_tile_width = 320,
                         int label_height = 20);

// Whether OpenImageIO found a font for the labels on this machine (e.g. fonts-dejavu-core).
bool contact_sheet_has_font();

}  // namespace glintlab
