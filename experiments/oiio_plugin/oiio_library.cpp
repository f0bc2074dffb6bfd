// libglintlab_oiio.so: every call glintlab makes into OpenImageIO (core/util/oiio_plugin.h), loaded
// on first use so that a process that reads no image through OpenImageIO never loads its libraries.
// Only glintlab_oiio_api is exported (the rest is hidden).
#include "core/util/oiio_plugin.h"

#include "core/util/io_error.h"
#include "core/util/json_check.h"
#include "experiments/runner/contact_sheet.h"
#include "metrics/color/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace glintlab::oiio {
namespace {

std::string oiio_error(const OIIO::ImageOutput* out) {
  std::string e = out ? out->geterror() : std::string();
  if (e.empty()) e = OIIO::geterror();
  return e.empty() ? std::string("unknown OpenImageIO error") : e;
}

// Writes through `format` into tmp; IoError naming `path` on failure.
void write_oiio(const std::string& tmp, const std::string& path, const char* format, const OIIO::ImageSpec& spec,
                OIIO::TypeDesc data_type, const void* data) {
  auto fail = [&](const std::string& why) { throw IoError("cannot write '" + path + "': " + why); };
  auto out = OIIO::ImageOutput::create(format);
  if (!out) fail(std::string("no OpenImageIO writer for ") + format + ": " + oiio_error(nullptr));
  if (!out->open(tmp, spec)) fail(oiio_error(out.get()));
  if (!out->write_image(data_type, data)) {
    std::string e = oiio_error(out.get());
    out->close();
    fail(e);
  }
  if (!out->close()) fail(oiio_error(out.get()));
}

std::vector<std::string> channel_names(int channels) {
  switch (channels) {
    case 1: return {"Y"};
    case 2: return {"Y", "A"};
    case 3: return {"R", "G", "B"};
    case 4: return {"R", "G", "B", "A"};
    default: {
      std::vector<std::string> n = {"R", "G", "B", "A"};
      for (int c = 4; c < channels; ++c) n.push_back("channel" + std::to_string(c));
      return n;
    }
  }
}

Image read_image(const std::string& path, std::string* colorspace_tag, int* file_channels) {
  // Values as stored: no premultiplication of unassociated (PNG, TIFF) alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    std::string e = OIIO::geterror();
    throw std::runtime_error("cannot read image '" + path + "': " + (e.empty() ? "unknown error" : e));
  }
  const OIIO::ImageSpec& spec = in->spec();
  const int w = spec.width, h = spec.height, n = spec.nchannels;
  if (w <= 0 || h <= 0 || n <= 0) throw std::runtime_error("cannot read image '" + path + "': empty image");
  if ((long long)w * h > metrics::kMaxImagePixels || n > 1024)
    throw std::invalid_argument("'" + path + "': its header claims " + std::to_string(w) + "x" + std::to_string(h) +
                                " pixels and " + std::to_string(n) + " channels; allowed: at most " +
                                std::to_string(metrics::kMaxImagePixels) + " pixels and 1024 channels");
  std::vector<float> raw(static_cast<std::size_t>(w) * h * n);
  if (!in->read_image(0, 0, 0, n, OIIO::TypeDesc::FLOAT, raw.data())) {
    std::string e = in->geterror();
    throw std::runtime_error("cannot read image '" + path + "': " + (e.empty() ? "read failed" : e));
  }
  if (colorspace_tag) *colorspace_tag = spec.get_string_attribute("oiio:ColorSpace");
  if (file_channels) *file_channels = n;
  in->close();

  int alpha = spec.alpha_channel;
  if (alpha < 0 && n == 2) alpha = 1;  // grey + alpha
  if (alpha < 0 && n >= 4) alpha = 3;
  Image img(w, h, 4, 1.0f);
  for (std::size_t i = 0; i < img.pixel_count(); ++i) {
    const float* s = raw.data() + i * n;
    float* d = img.data.data() + i * 4;
    if (n >= 3) {
      d[0] = s[0], d[1] = s[1], d[2] = s[2];
    } else {
      d[0] = d[1] = d[2] = s[0];
    }
    if (alpha > 0 && alpha < n) d[3] = s[alpha];
  }
  return img;
}

void write_exr(const std::string& tmp, const std::string& path, const Image& img, const float* chromaticities,
               bool half, const std::vector<std::string>& names) {
  OIIO::ImageSpec spec(img.width, img.height, img.channels, half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  spec.channelnames = names.empty() ? channel_names(img.channels) : names;
  spec.alpha_channel = !names.empty() ? -1 : (img.channels == 2) ? 1 : (img.channels >= 4 ? 3 : -1);
  spec.attribute("compression", "zip");
  if (chromaticities) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chromaticities);
  write_oiio(tmp, path, "exr", spec, OIIO::TypeDesc::FLOAT, img.data.data());
}

void write_png(const std::string& tmp, const std::string& path, int width, int height, int channels,
               const unsigned char* values) {
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  spec.alpha_channel = (channels == 2) ? 1 : (channels == 4 ? 3 : -1);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // values as given: no un-premultiplication
  // zlib level 3, the strongest of its fast (non-lazy) levels, instead of OpenImageIO's default 6: the
  // default experiment with a warm cache and without its report 8.6, 9.5, 10.1 -> 7.6, 7.9, 8.1 s (three
  // interleaved runs), its PNGs 10.8 -> 11.4 MB.
  spec.attribute("png:compressionLevel", 3);
  write_oiio(tmp, path, "png", spec, OIIO::TypeDesc::UINT8, values);
}

std::vector<Part> frame_parts(const std::string& path, int max_parts) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string e = OIIO::geterror();
    throw ConfigError("'" + path + "' is not an image OpenImageIO can read (" + (e.empty() ? "unknown format" : e) +
                      ")");
  }
  std::vector<Part> parts;
  for (int part = 0; part < max_parts && in->seek_subimage(part, 0); ++part) {
    const OIIO::ImageSpec& spec = in->spec();
    Part p;
    p.width = spec.width;
    p.height = spec.height;
    p.channels = spec.nchannels;
    for (int c = 0; c < std::min(spec.nchannels, 1 << 20); ++c) p.names.push_back(spec.channel_name(c));
    p.colorspace = spec.get_string_attribute("oiio:ColorSpace");
    parts.push_back(std::move(p));
  }
  return parts;
}

void read_frame_channels(const std::string& path, const std::vector<std::string>& channels, int width, int height,
                         int max_parts, Image& out, std::vector<bool>& done) {
  const int nc = out.channels;
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw ConfigError("'" + path + "': " + OIIO::geterror());
  for (int part = 0; part < max_parts && in->seek_subimage(part, 0); ++part) {
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width != width || spec.height != height) continue;
    std::vector<int> index(channels.size(), -1);
    bool any = false;
    for (size_t k = 0; k < channels.size(); ++k)
      for (int c = 0; c < spec.nchannels && !done[k]; ++c)
        if (spec.channel_name(c) == channels[k]) index[k] = c, any = true;
    if (!any) continue;
    // One read of the contiguous channel range the part needs: straight into the image where the
    // channels it gives are the image's next ones in the same order (R, G, B; X, Y, Z, W), else
    // through a buffer.
    int lo = spec.nchannels, hi = 0;
    for (int c : index)
      if (c >= 0) lo = std::min(lo, c), hi = std::max(hi, c + 1);
    const int n = hi - lo;
    size_t first = 0;
    while (index[first] < 0) ++first;
    bool direct = first + size_t(n) <= channels.size();
    for (size_t k = 0; k < channels.size(); ++k)
      direct = direct && (k >= first && k < first + size_t(n) ? index[k] == lo + int(k - first) : index[k] < 0);
    auto read = [&](float* data, int stride_channels) {
      if (in->read_image(part, 0, lo, hi, OIIO::TypeDesc::FLOAT, data, OIIO::stride_t(sizeof(float)) * stride_channels))
        return;
      std::string e = in->geterror();
      throw ConfigError("'" + path + "': cannot read its pixels (" + (e.empty() ? "read failed" : e) +
                        "; a truncated or damaged file?)");
    };
    if (direct) {
      read(out.data.data() + first, nc);
      for (size_t k = first; k < first + size_t(n); ++k) done[k] = true;
      continue;
    }
    std::vector<float> raw(size_t(width) * height * size_t(n));
    read(raw.data(), n);
    const size_t px = out.pixel_count();
    for (size_t k = 0; k < channels.size(); ++k) {
      if (index[k] < 0) continue;
      const int c = index[k] - lo;
      for (size_t i = 0; i < px; ++i) out.data[i * size_t(nc) + k] = raw[i * size_t(n) + size_t(c)];
      done[k] = true;
    }
  }
}

void read_environment(const std::string& path, const std::function<void(const EnvironmentInfo&)>& check,
                      std::vector<float>& pixels) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw ConfigError(path + ": cannot open environment map: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  EnvironmentInfo info;
  info.width = spec.width;
  info.height = spec.height;
  info.channels = spec.nchannels;
  if (const OIIO::ParamValue* c = spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8))) {
    info.has_chromaticities = true;
    std::copy_n(static_cast<const float*>(c->data()), 8, info.chromaticities.begin());
  }
  info.colorspace = spec.get_string_attribute("oiio:ColorSpace");
  check(info);
  pixels.resize(size_t(info.width) * size_t(info.height) * size_t(info.channels));
  if (!in->read_image(0, 0, 0, info.channels, OIIO::TypeDesc::FLOAT, pixels.data()))
    throw ConfigError(path + ": cannot read pixels: " + in->geterror());
}

// ---------------------------------------------------------------- the contact sheet
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


}  // namespace
}  // namespace glintlab::oiio

// The table, untyped: load_plugin (core/util/plugin.h) calls every plugin's function as const void* ().
extern "C" __attribute__((visibility("default"))) const void* glintlab_oiio_api() {
  using namespace glintlab::oiio;
  static const Api api{kApiVersion,          &read_image,       &write_exr,          &write_png,
                       &frame_parts,         &read_frame_channels, &read_environment, &make_contact_sheet,
                       &contact_sheet_has_font};
  return &api;
}
