#include "experiments/runner/contact_sheet.h"

#include "core/util/oiio_plugin.h"

// The sheet is drawn with OpenImageIO's text rendering, in libglintlab_oiio.so (experiments/oiio_plugin/).
namespace glintlab {

bool contact_sheet_has_font() { return oiio::api().contact_sheet_has_font(); }

Image make_contact_sheet(const std::vector<std::vector<SheetTile>>& rows, int max_tile_width, int label_height) {
  return oiio::api().make_contact_sheet(rows, max_tile_width, label_height);
}

}  // namespace glintlab
