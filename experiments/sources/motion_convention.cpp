#include "experiments/sources/motion_convention.h"

#include "core/util/json_check.h"
#include "metrics/parallel.h"

#include <algorithm>
#include <cmath>

namespace glintlab {

namespace {

// How a convention's stored 2-vector maps to glintlab's: v_px = (sx · x · ux, sy · y · uy).
struct Mapping {
  double sign = 1;    // +1: stored p_t − p_{t−1}; −1: stored p_{t−1} − p_t
  bool y_up = false;  // the stored y grows upwards (glintlab's grows downwards)
  enum Unit { Pixels, Ndc, Uv } unit = Pixels;
};

Mapping mapping_of(MotionConvention c) {
  switch (c) {
    case MotionConvention::Pixels: return {1, false, Mapping::Pixels};
    case MotionConvention::Blender: return {-1, true, Mapping::Pixels};
    case MotionConvention::Unreal: return {1, true, Mapping::Ndc};
    case MotionConvention::Unity: return {1, true, Mapping::Uv};
  }
  return {};
}

// Pixels per stored unit along x and y (NDC spans 2 units over the image, UV 1).
void unit_scale(const Mapping& m, int w, int h, double* ux, double* uy) {
  switch (m.unit) {
    case Mapping::Pixels: *ux = *uy = 1; return;
    case Mapping::Ndc: *ux = 0.5 * w, *uy = 0.5 * h; return;
    case Mapping::Uv: *ux = w, *uy = h; return;
  }
}

// stored 2-vectors (channels c0, c0 + 1 of raw) -> glintlab pixels, or the inverse.
Image map_vectors(const Image& raw, int c0, const Mapping& m, bool inverse) {
  Image out = Image::unfilled(raw.width, raw.height, 2);  // every pixel written below
  double ux = 1, uy = 1;
  unit_scale(m, raw.width, raw.height, &ux, &uy);
  const double sx = m.sign * ux, sy = m.sign * (m.y_up ? -1.0 : 1.0) * uy;
  for (size_t i = 0; i < raw.pixel_count(); ++i) {
    const float* s = raw.data.data() + i * size_t(raw.channels) + size_t(c0);
    out.data[2 * i] = float(inverse ? s[0] / sx : s[0] * sx);
    out.data[2 * i + 1] = float(inverse ? s[1] / sy : s[1] * sy);
  }
  return out;
}

std::string convention_channels_text(MotionConvention c) {
  switch (c) {
    case MotionConvention::Pixels: return "R, G (or X, Y), optionally B, A (distances)";
    case MotionConvention::Blender: return "X, Y, Z, W (Blender's Vector pass)";
    case MotionConvention::Unreal: return "R, G (or X, Y): the decoded velocity";
    case MotionConvention::Unity: return "R, G (or X, Y): the motion-vector texture";
  }
  return "";
}

}  // namespace

const std::vector<std::string>& motion_layer_names(MotionConvention c) {
  static const std::vector<std::string> pixels = {"motion", "Motion"}, blender = {"Vector"},
                                        unreal = {"Velocity", "MotionVectors", "velocity"},
                                        unity = {"MotionVectors", "Motion", "motion"};
  switch (c) {
    case MotionConvention::Pixels: return pixels;
    case MotionConvention::Blender: return blender;
    case MotionConvention::Unreal: return unreal;
    case MotionConvention::Unity: return unity;
  }
  return pixels;
}

MotionChannels motion_channels(MotionConvention c, const FrameHeader& header, const std::string& layer,
                               const std::string& path) {
  MotionChannels mc;
  auto all = [](const std::vector<std::string>& v) {
    return !v.empty() && std::all_of(v.begin(), v.end(), [](const std::string& s) { return !s.empty(); });
  };
  if (c == MotionConvention::Blender) {
    const auto xyzw = find_channels(header, layer, {{"X", "x"}, {"Y", "y"}, {"Z", "z"}, {"W", "w"}});
    if (all(xyzw)) {
      mc.backward = {xyzw[0], xyzw[1]};
      mc.forward = {xyzw[2], xyzw[3]};
    }
  } else {
    auto xy = find_channels(header, layer, {{"R", "r"}, {"G", "g"}});
    const bool rgba = all(xy);
    if (!rgba) xy = find_channels(header, layer, {{"X", "x"}, {"Y", "y"}});
    if (all(xy)) mc.backward = xy;
    // glintlab writes R, G, B, A: B and A are its distances. X, Y, Z, W is another renderer's layout
    // (Blender's Vector pass holds a second vector in Z, W), so no distances are read from it.
    if (c == MotionConvention::Pixels && rgba) {
      auto d = find_channels(header, layer, {{"B", "b"}, {"A", "a"}});
      if (all(d)) mc.distances = d;
    }
  }
  if (mc.backward.empty())
    throw ConfigError("'" + path + "': --motion-convention " + std::string(enum_name(kMotionConventionNames, c)) +
                      " reads " + (layer.empty() ? std::string() : "layer '" + layer + "', channels ") +
                      convention_channels_text(c) + ", which the file does not have; the file has: " +
                      channel_list(header));
  return mc;
}

MotionVectors convert_motion(MotionConvention c, const Image& raw, const MotionChannels& ch) {
  const Mapping m = mapping_of(c);
  MotionVectors v;
  v.backward = map_vectors(raw, 0, m, false);
  int next = 2;
  if (!ch.forward.empty()) {
    v.forward = map_vectors(raw, next, m, false);
    next += 2;
  }
  if (!ch.distances.empty()) {
    Image d = Image::unfilled(raw.width, raw.height, 2);
    for (size_t i = 0; i < raw.pixel_count(); ++i)
      for (int k = 0; k < 2; ++k) d.data[2 * i + size_t(k)] = raw.data[i * size_t(raw.channels) + size_t(next + k)];
    v.distances = std::move(d);
  }
  return v;
}

bool is_flicker_motion(MotionConvention c, const MotionChannels& ch) {
  // mapping_of(pixels) scales by 1 and flips nothing; flicker_motion takes the distances over depth.
  return c == MotionConvention::Pixels && ch.backward.size() == 2 && ch.distances.size() == 2 && ch.forward.empty();
}

Image to_convention(MotionConvention c, const MotionVectors& v) {
  const Mapping m = mapping_of(c);
  const int w = v.backward.width, h = v.backward.height;
  const bool fwd = c == MotionConvention::Blender && v.forward;
  const bool dist = c == MotionConvention::Pixels && v.distances;
  Image out(w, h, 2 + (fwd ? 2 : 0) + (dist ? 2 : 0));
  auto put = [&](const Image& src, int c0, bool vectors) {
    const Image mapped = vectors ? map_vectors(src, 0, m, true) : src;
    for (size_t i = 0; i < out.pixel_count(); ++i)
      for (int k = 0; k < 2; ++k)
        out.data[i * size_t(out.channels) + size_t(c0 + k)] = mapped.data[i * size_t(mapped.channels) + size_t(k)];
  };
  put(v.backward, 0, true);
  if (fwd) put(*v.forward, 2, true);
  if (dist) put(*v.distances, 2, false);
  return out;
}

Image flicker_motion(const MotionVectors& v, const Image* depth_now, const Image* prev_forward) {
  const int w = v.backward.width, h = v.backward.height;
  Image out = Image::unfilled(w, h, 4);  // all four channels of every pixel written below
  metrics::parallel_for(h, [&](long yl) {
    const int y = int(yl);
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      float* o = out.data.data() + 4 * i;
      const float vx = v.backward.data[2 * i], vy = v.backward.data[2 * i + 1];
      o[0] = vx;
      o[1] = vy;
      if (v.distances) {  // glintlab's own: exactly as the renderer wrote them
        o[2] = v.distances->data[2 * i];
        o[3] = v.distances->data[2 * i + 1];
        continue;
      }
      float z = 1.0f;
      if (depth_now) {
        const float d = depth_now->data[i * size_t(depth_now->channels)];
        z = (std::isfinite(d) && d > 0.0f && d < float(kDepthBackground)) ? d : 0.0f;
      }
      o[2] = z;
      o[3] = z;
      if (prev_forward && z > 0.0f) {
        // Sundaram et al. 2010: the forward vector of frame t−1 at p − v should bring it back to p.
        const double qx = x - double(vx), qy = y - double(vy);
        if (!(std::isfinite(qx) && std::isfinite(qy) && qx >= 0 && qy >= 0 && qx <= w - 1 && qy <= h - 1)) continue;
        const int x0 = std::min(int(qx), w - 1), y0 = std::min(int(qy), h - 1);
        const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
        const double fx = qx - x0, fy = qy - y0;
        auto at = [&](int xx, int yy, int c) {
          return double(prev_forward->data[(size_t(yy) * size_t(w) + size_t(xx)) * 2 + size_t(c)]);
        };
        double f[2];
        for (int c = 0; c < 2; ++c)
          f[c] = (1 - fx) * (1 - fy) * at(x0, y0, c) + fx * (1 - fy) * at(x1, y0, c) + (1 - fx) * fy * at(x0, y1, c) +
                 fx * fy * at(x1, y1, c);
        const double dx = f[0] - vx, dy = f[1] - vy;
        const double lhs = dx * dx + dy * dy;
        const double rhs = 0.01 * (double(vx) * vx + double(vy) * vy + f[0] * f[0] + f[1] * f[1]) + 0.5;
        if (!(lhs <= rhs)) o[3] = -1.0f;
      }
    }
  });
  return out;
}

}  // namespace glintlab
