#include "core/scene/mesh.h"

#include "core/util/json_check.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/noise.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace glintlab::core {

namespace {

constexpr float kTwoPi = 6.28318530717958647692f;
constexpr float kPi = 3.14159265358979323846f;

// splitmix64 (Steele et al. 2014): integer hash for the per-octave seed offsets of the dune noise.
uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Offset in [0, 256)^2 of octave `o`: decorrelates octaves and seeds without float->int casts.
glm::vec2 octave_offset(uint32_t seed, int o) {
  uint64_t h = splitmix64((uint64_t(seed) << 32) ^ uint64_t(o));
  float a = float(h >> 40) * (256.0f / 16777216.0f);
  float b = float((h >> 16) & 0xFFFFFFull) * (256.0f / 16777216.0f);
  return {a, b};
}

// Ridged multi-octave noise (Musgrave's ridged multifractal without the feedback term): each octave
// contributes (1 - |perlin|)^2, sharp crests where the noise crosses zero, like dune ridges.
float ridged_dunes(const MeshSpec& s, float x, float z) {
  glm::vec2 p = glm::vec2(x, z) / s.wavelength;
  float sum = 0.0f, norm = 0.0f, amp = 1.0f, freq = 1.0f;
  for (int o = 0; o < s.octaves; ++o) {
    float n = glm::perlin(p * freq + octave_offset(s.seed, o));
    float r = 1.0f - std::min(1.0f, std::fabs(n));
    sum += amp * r * r;
    norm += amp;
    amp *= s.gain;
    freq *= s.lacunarity;
  }
  return s.amplitude * sum / norm;  // in [0, amplitude]
}

void validate(const MeshSpec& s) {
  auto bad = [&](const std::string& m) { throw std::invalid_argument("mesh \"" + s.type + "\": " + m); };
  if (s.type != "plane" && s.type != "wavy" && s.type != "sphere" && s.type != "dunes")
    throw std::invalid_argument("mesh: unknown type \"" + s.type + "\"; expected plane, wavy, sphere or dunes");
  if (!(s.size > 0.0f) || !std::isfinite(s.size)) bad("size must be > 0");
  if (s.tessellation < 1 || s.tessellation > 4096) bad("tessellation must be in [1, 4096]");
  if (s.type == "sphere" && s.tessellation < 3) bad("sphere tessellation must be >= 3");
  if (s.type == "wavy" || s.type == "dunes") {
    if (!std::isfinite(s.amplitude)) bad("amplitude must be finite");
    if (!(s.wavelength > 0.0f) || !std::isfinite(s.wavelength)) bad("wavelength must be > 0");
  }
  if (s.type == "dunes" && (s.octaves < 1 || s.octaves > 16)) bad("octaves must be in [1, 16]");
  if (!(s.max_edge_px >= 0.0f) || !std::isfinite(s.max_edge_px)) bad("max_edge_px must be >= 0");
  if (s.type == "sphere" && s.max_edge_px > 0.0f) bad("max_edge_px applies to height fields only");
  if (!(s.max_error_px >= 0.0f) || !std::isfinite(s.max_error_px)) bad("max_error_px must be >= 0");
  if (s.max_error_px > 0.0f && !(s.max_edge_px > 0.0f)) bad("max_error_px needs max_edge_px > 0");
  if (s.type == "sphere" && (s.layers < 1 || !(s.layer_spacing >= 0.0f) || float(s.layers - 1) * s.layer_spacing >= 1.0f))
    bad("layers must be >= 1 and (layers - 1) * layer_spacing < 1 (inner shells need a positive radius)");
}

// Completes tangent (Gram-Schmidt against n) and handedness from d(position)/dv.
Vertex make_vertex(glm::vec3 p, glm::vec3 n, glm::vec3 dpdu, glm::vec3 dpdv, glm::vec2 uv) {
  n = glm::normalize(n);
  glm::vec3 t = glm::normalize(dpdu - n * glm::dot(n, dpdu));
  float w = glm::dot(glm::cross(n, t), dpdv) < 0.0f ? -1.0f : 1.0f;
  return Vertex{p, n, glm::vec4(t, w), uv};
}

// Regular grid of (nu + 1) x (nv + 1) vertices, index i + j (nu + 1). `flip` reverses the winding
// for parameterisations where cross(dP/du, dP/dv) points against the outward normal.
void grid_indices(Mesh& m, uint32_t base, int nu, int nv, bool flip, bool skip_top_pole, bool skip_bottom_pole) {
  auto id = [&](int i, int j) { return base + uint32_t(i + j * (nu + 1)); };
  auto tri = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (flip) std::swap(b, c);
    m.indices.insert(m.indices.end(), {a, b, c});
  };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      uint32_t p00 = id(i, j), p10 = id(i + 1, j), p01 = id(i, j + 1), p11 = id(i + 1, j + 1);
      // At a pole row one triangle of the quad has zero area (p00 == p10 on top, p01 == p11 below).
      if (!(skip_top_pole && j == 0)) tri(p00, p10, p11);
      if (!(skip_bottom_pole && j == nv - 1)) tri(p00, p11, p01);
    }
}

// h_grad(x, z) = (h, dh/dx, dh/dz) of a height field.
using HeightGrad = std::function<glm::vec3(float, float)>;

// Vertex (i, j) of the n x n grid of a height field: u along +x, v along +z.
Vertex height_field_vertex(const MeshSpec& s, const HeightGrad& h_grad, int i, int j) {
  const int n = s.tessellation;
  const float half = 0.5f * s.size;
  glm::vec2 uv(float(i) / float(n), float(j) / float(n));
  float x = -half + uv.x * s.size, z = -half + uv.y * s.size;
  glm::vec3 hg = h_grad(x, z);
  glm::vec3 p(x, hg.x, z);
  glm::vec3 dpdu = glm::vec3(1.0f, hg.y, 0.0f) * s.size;
  glm::vec3 dpdv = glm::vec3(0.0f, hg.z, 1.0f) * s.size;
  glm::vec3 normal(-hg.y, 1.0f, -hg.z);  // normal of y = h(x, z)
  return make_vertex(p, normal, dpdu, dpdv, uv);
}

void height_field_mesh(Mesh& m, const MeshSpec& s, const HeightGrad& h_grad) {
  const int n = s.tessellation;
  m.vertices.reserve(size_t(n + 1) * size_t(n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.push_back(height_field_vertex(s, h_grad, i, j));
  // cross(+x, +z) = -y: reverse so that triangles face +Y.
  grid_indices(m, 0, n, n, /*flip=*/true, false, false);
}

// The adaptive grid of MeshSpec::max_edge_px (and max_error_px): a restricted quadtree whose leaves
// are aligned squares of the n x n grid, 2^k grid cells wide (k <= the number of times n divides by
// 2). `level` holds, for every grid cell, log2 of the width of the leaf that covers it.
void adaptive_height_field_mesh(Mesh& m, const MeshSpec& s, const HeightGrad& h_grad,
                                const std::vector<MeshView>& views, double h_lo, double h_hi) {
  const int n = s.tessellation;
  int top = 0;  // the widest leaf is 2^top cells
  while (top < 16 && (n >> top) % 2 == 0) ++top;
  const double unit = double(s.size) / double(n), half = 0.5 * double(s.size);
  // The full grid's heights (what a leaf's error is measured against), only when an error bound is set.
  std::vector<double> height;
  if (s.max_error_px > 0.0f) {
    height.resize(size_t(n + 1) * size_t(n + 1));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) height[size_t(j) * size_t(n + 1) + size_t(i)] = height_field_vertex(s, h_grad, i, j).position.y;
  }
  auto h = [&](int i, int j) { return height[size_t(j) * size_t(n + 1) + size_t(i)]; };
  // The largest vertical distance between the full grid and one triangle of grid points (a, b, c).
  // Both surfaces are linear between the points where their edges cross: the grid points, and, where
  // the triangle's edge runs across the full grid's quads (a fan's edge from the centre to corner
  // (1, 0) or (0, 1)), the quads' centres, where the full grid has the mean of its diagonal's ends.
  // Coordinates are doubled so that both kinds of point are integers and the inside test exact.
  auto triangle_error = [&](glm::ivec2 a, glm::ivec2 b, glm::ivec2 c) {
    a *= 2, b *= 2, c *= 2;
    const int64_t det = int64_t(b.x - a.x) * (c.y - a.y) - int64_t(c.x - a.x) * (b.y - a.y);
    const double ha = h(a.x / 2, a.y / 2), hb = h(b.x / 2, b.y / 2), hc = h(c.x / 2, c.y / 2);
    const glm::ivec2 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
    double d = 0.0;
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x + ((lo.x + y) & 1); x <= hi.x; x += 2) {  // x + y even: grid points, quad centres
        const int64_t wb = int64_t(x - a.x) * (c.y - a.y) - int64_t(c.x - a.x) * (y - a.y);
        const int64_t wc = int64_t(b.x - a.x) * (y - a.y) - int64_t(x - a.x) * (b.y - a.y);
        const int64_t wa = det - wb - wc;
        if (det > 0 ? (wa < 0 || wb < 0 || wc < 0) : (wa > 0 || wb > 0 || wc > 0)) continue;
        const double full = x % 2 == 0 ? h(x / 2, y / 2) : 0.5 * (h(x / 2, y / 2) + h(x / 2 + 1, y / 2 + 1));
        d = std::max(d, std::abs(full - (ha + (double(wb) * (hb - ha) + double(wc) * (hc - ha)) / double(det))));
      }
    return d;
  };
  // A leaf's error: the largest of the errors of the triangles it may be emitted with (its two, or a
  // fan around its centre through the midpoint of any of its sides, see the emission below) and,
  // since the restriction below may split it further, of those of every cell inside it. Exact where
  // it matters: a cell is kept whole exactly when no surface it can become strays too far.
  std::vector<std::vector<double>> memo(size_t(top) + 1);  // per level; < 0: not computed yet
  std::function<double(int, int, int)> leaf_error = [&](int i0, int j0, int k) -> double {
    if (k == 0) return 0.0;  // the full grid's own quad
    std::vector<double>& mk = memo[size_t(k)];
    const int cells = n >> k;
    if (mk.empty()) mk.assign(size_t(cells) * size_t(cells), -1.0);
    double& slot = mk[size_t(j0 >> k) * size_t(cells) + size_t(i0 >> k)];
    if (slot >= 0.0) return slot;
    const int w = 1 << k, hw = w / 2;
    const glm::ivec2 p00(i0, j0), p10(i0 + w, j0), p11(i0 + w, j0 + w), p01(i0, j0 + w), c(i0 + hw, j0 + hw);
    double e = std::max(triangle_error(p00, p11, p10), triangle_error(p00, p01, p11));
    const glm::ivec2 ring[4][3] = {{p00, {i0 + hw, j0}, p10},
                                   {p10, {i0 + w, j0 + hw}, p11},
                                   {p11, {i0 + hw, j0 + w}, p01},
                                   {p01, {i0, j0 + hw}, p00}};
    for (const auto& side : ring)
      e = std::max({e, triangle_error(c, side[0], side[2]), triangle_error(c, side[0], side[1]),
                    triangle_error(c, side[1], side[2])});
    for (int q = 0; q < 4; ++q) e = std::max(e, leaf_error(i0 + (q & 1) * hw, j0 + (q >> 1) * hw, k - 1));
    return slot = e;
  };
  // Split a cell while some view sees its edge wider than max_edge_px and (with max_error_px) its
  // error larger than max_error_px; the cell's box spans the field's whole height range
  // (nearer to the eye than the cell itself: errs towards splitting).
  auto too_wide = [&](int i0, int j0, int k) {
    const double edge = (1 << k) * unit;
    const glm::dvec3 lo(-half + i0 * unit, h_lo, -half + j0 * unit), hi = lo + glm::dvec3(edge, h_hi - h_lo, edge);
    double error = -1.0;  // computed on first need
    for (const MeshView& v : views) {
      const glm::dvec3 e(v.eye), d = e - glm::clamp(e, lo, hi);
      const double dist = std::sqrt(glm::dot(d, d));
      if (!(edge * double(v.focal_px) > double(s.max_edge_px) * dist)) continue;
      if (!(s.max_error_px > 0.0f)) return true;
      if (error < 0.0) error = leaf_error(i0, j0, k);
      if (error * double(v.focal_px) > double(s.max_error_px) * dist) return true;
    }
    return false;
  };
  std::vector<uint8_t> level(size_t(n) * size_t(n), uint8_t(top));
  auto lvl = [&](int i, int j) -> uint8_t& { return level[size_t(j) * size_t(n) + size_t(i)]; };
  auto set_leaf = [&](int i0, int j0, int k) {
    const int w = 1 << k;
    for (int j = j0; j < j0 + w; ++j)
      for (int i = i0; i < i0 + w; ++i) lvl(i, j) = uint8_t(k);
  };
  struct Cell {
    int i0, j0, k;
  };
  std::vector<Cell> stack;
  for (int j = 0; j < n; j += 1 << top)
    for (int i = 0; i < n; i += 1 << top) stack.push_back({i, j, top});
  while (!stack.empty()) {
    const Cell c = stack.back();
    stack.pop_back();
    if (c.k > 0 && too_wide(c.i0, c.j0, c.k)) {
      const int h = 1 << (c.k - 1);
      for (int q = 0; q < 4; ++q) stack.push_back({c.i0 + (q & 1) * h, c.j0 + (q >> 1) * h, c.k - 1});
    } else {
      set_leaf(c.i0, c.j0, c.k);
    }
  }
  // Restrict: a leaf whose neighbour across an edge is more than twice finer is split, until none is.
  auto is_origin = [&](int i, int j) {
    const int w = 1 << lvl(i, j);
    return i % w == 0 && j % w == 0;
  };
  auto finest_across = [&](int i0, int j0, int w) {  // smallest leaf width along the four edges outside
    int f = 1 << 30;
    for (int t = 0; t < w; ++t) {
      if (j0 > 0) f = std::min(f, 1 << lvl(i0 + t, j0 - 1));
      if (j0 + w < n) f = std::min(f, 1 << lvl(i0 + t, j0 + w));
      if (i0 > 0) f = std::min(f, 1 << lvl(i0 - 1, j0 + t));
      if (i0 + w < n) f = std::min(f, 1 << lvl(i0 + w, j0 + t));
    }
    return f;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (!is_origin(i, j)) continue;
        const int k = lvl(i, j), w = 1 << k;
        if (k > 0 && finest_across(i, j, w) < w / 2) {
          for (int q = 0; q < 4; ++q) set_leaf(i + (q & 1) * (w / 2), j + (q >> 1) * (w / 2), k - 1);
          changed = true;
        }
      }
  }
  // Emit: vertices on demand, shared by grid point; a leaf with no finer neighbour is the two
  // triangles of the full grid's quad (same diagonal, same winding), one next to a finer leaf is a
  // fan around its centre through the midpoints the finer side has.
  std::unordered_map<uint64_t, uint32_t> index_of;
  auto vid = [&](int i, int j) {
    const uint64_t key = uint64_t(uint32_t(j)) * uint64_t(n + 1) + uint64_t(uint32_t(i));
    auto [it, fresh] = index_of.try_emplace(key, uint32_t(m.vertices.size()));
    if (fresh) m.vertices.push_back(height_field_vertex(s, h_grad, i, j));
    return it->second;
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (!is_origin(i, j)) continue;
      const int w = 1 << lvl(i, j), h = w / 2;
      // Is the neighbour across each edge finer? (It then covers the edge with two leaves of width h.)
      const bool bottom = j > 0 && (1 << lvl(i, j - 1)) < w, top_ = j + w < n && (1 << lvl(i, j + w)) < w;
      const bool left = i > 0 && (1 << lvl(i - 1, j)) < w, right = i + w < n && (1 << lvl(i + w, j)) < w;
      const uint32_t p00 = vid(i, j), p10 = vid(i + w, j), p11 = vid(i + w, j + w), p01 = vid(i, j + w);
      if (!(bottom || top_ || left || right)) {
        m.indices.insert(m.indices.end(), {p00, p11, p10, p00, p01, p11});
        continue;
      }
      // Boundary counter-clockwise in (i, j); each triangle (centre, b, a) for consecutive a, b winds
      // as the full grid's do (facing +Y).
      std::vector<uint32_t> ring = {p00};
      if (bottom) ring.push_back(vid(i + h, j));
      ring.push_back(p10);
      if (right) ring.push_back(vid(i + w, j + h));
      ring.push_back(p11);
      if (top_) ring.push_back(vid(i + h, j + w));
      ring.push_back(p01);
      if (left) ring.push_back(vid(i, j + h));
      const uint32_t c = vid(i + h, j + h);
      for (size_t a = 0; a < ring.size(); ++a) m.indices.insert(m.indices.end(), {c, ring[(a + 1) % ring.size()], ring[a]});
    }
}

void sphere_shell(Mesh& m, float r, int slices) {
  const int stacks = std::max(2, slices / 2);
  const uint32_t base = uint32_t(m.vertices.size());
  for (int j = 0; j <= stacks; ++j)
    for (int i = 0; i <= slices; ++i) {
      glm::vec2 uv(float(i) / float(slices), float(j) / float(stacks));
      // Same angles as the environment's lat-long map: theta from +Y, phi from +X towards +Z.
      float theta = kPi * uv.y, phi = kTwoPi * uv.x;
      float st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
      if (j == 0) st = 0.0f, ct = 1.0f;  // exact poles
      if (j == stacks) st = 0.0f, ct = -1.0f;
      if (i == slices) sp = 0.0f, cp = 1.0f;  // exact seam
      glm::vec3 n(st * cp, ct, st * sp);
      glm::vec3 dpdu(-sp, 0.0f, cp);             // direction of dP/dphi (defined at the poles too)
      glm::vec3 dpdv(ct * cp, -st, ct * sp);     // direction of dP/dtheta
      m.vertices.push_back(make_vertex(r * n, n, dpdu, dpdv, uv));
    }
  // cross(dP/dphi, dP/dtheta) points outwards: no flip.
  grid_indices(m, base, slices, stacks, /*flip=*/false, true, true);
}

}  // namespace

float height_field(const MeshSpec& s, float x, float z) {
  if (s.type == "plane") return 0.0f;
  if (s.type == "wavy") return s.amplitude * std::sin(kTwoPi * x / s.wavelength);
  if (s.type == "dunes") return ridged_dunes(s, x, z);
  throw std::invalid_argument("height_field: mesh type \"" + s.type + "\" is not a height field");
}

Mesh build_mesh(const MeshSpec& s, const std::vector<MeshView>& views) {
  validate(s);
  if (s.max_edge_px > 0.0f && views.empty())
    throw std::invalid_argument("mesh \"" + s.type + "\": max_edge_px needs the camera's views");
  Mesh m;
  // A height field, with the range of its heights (what bounds the adaptive grid's cells).
  auto field = [&](const HeightGrad& h_grad, double h_lo, double h_hi) {
    if (s.max_edge_px > 0.0f)
      adaptive_height_field_mesh(m, s, h_grad, views, h_lo, h_hi);
    else
      height_field_mesh(m, s, h_grad);
  };
  if (s.type == "plane") {
    field([](float, float) { return glm::vec3(0.0f); }, 0.0, 0.0);
  } else if (s.type == "wavy") {
    // Kajs sec. 2.2 "wavy plane": y = A sin(2π x / λ), analytic derivative.
    const float k = kTwoPi / s.wavelength;
    const double a = std::abs(double(s.amplitude));
    field([&](float x, float) {
      return glm::vec3(s.amplitude * std::sin(k * x), s.amplitude * k * std::cos(k * x), 0.0f);
    }, -a, a);
  } else if (s.type == "dunes") {
    // Normals from central differences of the height with the grid spacing as step, i.e. the slope
    // the triangles themselves have.
    const float d = s.size / float(s.tessellation);
    field([&](float x, float z) {
      float hx = (ridged_dunes(s, x + d, z) - ridged_dunes(s, x - d, z)) / (2.0f * d);
      float hz = (ridged_dunes(s, x, z + d) - ridged_dunes(s, x, z - d)) / (2.0f * d);
      return glm::vec3(ridged_dunes(s, x, z), hx, hz);
    }, std::min(0.0, double(s.amplitude)), std::max(0.0, double(s.amplitude)));
  } else {  // sphere
    const float r = 0.5f * s.size;
    for (int k = 0; k < s.layers; ++k) sphere_shell(m, r * (1.0f - float(k) * s.layer_spacing), s.tessellation);
  }
  chunk_mesh(m);
  return m;
}

MeshChunk whole_mesh_chunk(const Mesh& m) {
  MeshChunk c;
  c.index_count = uint32_t(m.indices.size());
  c.lo = glm::vec3(std::numeric_limits<float>::max());
  c.hi = glm::vec3(std::numeric_limits<float>::lowest());
  for (const Vertex& v : m.vertices) {
    c.lo = glm::min(c.lo, v.position);
    c.hi = glm::max(c.hi, v.position);
  }
  return c;
}

void chunk_mesh(Mesh& m, int per_axis) {
  if (per_axis < 1) throw std::invalid_argument("chunk_mesh: per_axis must be >= 1");
  if (m.indices.size() % 3 != 0) throw std::invalid_argument("chunk_mesh: the index count is not a multiple of 3");
  const MeshChunk all = whole_mesh_chunk(m);
  m.bounds_min = all.lo;
  m.bounds_max = all.hi;
  m.chunks.clear();
  const size_t n_tri = m.indices.size() / 3;
  if (n_tri == 0) return;
  const glm::dvec3 lo(m.bounds_min), extent = glm::dvec3(m.bounds_max) - lo;
  const double longest = std::max({extent.x, extent.y, extent.z});
  // Cells along each axis: the longest gets per_axis, the others as many of the same width as fit
  // (at least one). Cell coordinates come from a clamped double, never an out-of-range conversion.
  glm::ivec3 cells(1);
  for (int a = 0; a < 3; ++a)
    if (longest > 0.0)
      cells[a] = std::clamp(int(std::lround(double(per_axis) * extent[a] / longest)), 1, per_axis);
  auto cell_of = [&](uint32_t t) {
    glm::dvec3 c(0.0);
    for (int k = 0; k < 3; ++k) c += glm::dvec3(m.vertices.at(m.indices[3 * t + k]).position);
    c /= 3.0;
    glm::ivec3 q(0);
    for (int a = 0; a < 3; ++a)
      if (extent[a] > 0.0)
        q[a] = int(std::clamp(std::floor((c[a] - lo[a]) / extent[a] * cells[a]), 0.0, double(cells[a] - 1)));
    return uint32_t((q.y * cells.z + q.z) * cells.x + q.x);
  };
  std::vector<uint32_t> cell(n_tri), order(n_tri);
  for (uint32_t t = 0; t < n_tri; ++t) cell[t] = cell_of(t), order[t] = t;
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return cell[a] < cell[b]; });
  std::vector<uint32_t> sorted(m.indices.size());
  for (size_t i = 0; i < n_tri; ++i) {
    const uint32_t t = order[i];
    for (int k = 0; k < 3; ++k) sorted[3 * i + k] = m.indices[3 * t + k];
    if (i == 0 || cell[t] != cell[order[i - 1]]) {
      MeshChunk c;
      c.first_index = uint32_t(3 * i);
      c.lo = glm::vec3(std::numeric_limits<float>::max());
      c.hi = glm::vec3(std::numeric_limits<float>::lowest());
      m.chunks.push_back(c);
    }
    MeshChunk& c = m.chunks.back();
    c.index_count += 3;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3& p = m.vertices[sorted[3 * i + k]].position;
      c.lo = glm::min(c.lo, p);
      c.hi = glm::max(c.hi, p);
    }
  }
  m.indices = std::move(sorted);
}

MeshSpec MeshSpec::from_json(JsonReader& r) {
  MeshSpec s;
  s.type = r.get_enum("type", {"plane", "wavy", "sphere", "dunes"});
  s.size = float(r.get_number("size", 10.0, 1e-3, 1e5));
  s.tessellation = r.get_int("tessellation", 128, s.type == "sphere" ? 3 : 1, 4096);
  if (s.type == "wavy") {
    s.amplitude = float(r.get_number("amplitude", 1.0, -1e4, 1e4));
    s.wavelength = float(r.get_number("wavelength", s.size, 1e-3, 1e5));
  } else if (s.type == "dunes") {
    s.amplitude = float(r.get_number("amplitude", 1.5, 0.0, 1e4));
    s.wavelength = float(r.get_number("wavelength", 8.0, 1e-3, 1e5));
    s.octaves = r.get_int("octaves", 4, 1, 16);
    s.lacunarity = float(r.get_number("lacunarity", 2.0, 1.0, 8.0));
    s.gain = float(r.get_number("gain", 0.5, 0.0, 1.0));
    s.seed = uint32_t(r.get_int("seed", 1, 0, 2147483647));
  } else if (s.type == "sphere") {
    s.layers = r.get_int("layers", 1, 1, 64);
    s.layer_spacing = float(r.get_number("layer_spacing", 0.1, 0.0, 1.0));
    if (float(s.layers - 1) * s.layer_spacing >= 1.0f)
      r.fail("layer_spacing", "(layers - 1) * layer_spacing must be < 1 so that every shell has a positive radius");
  }
  if (s.type != "sphere") {
    s.max_edge_px = float(r.get_number("max_edge_px", 0.0, 0.0, 1e4));
    s.max_error_px = float(r.get_number("max_error_px", 0.0, 0.0, 1e4));
    if (s.max_error_px > 0.0f && !(s.max_edge_px > 0.0f))
      r.fail("max_error_px", "relaxes max_edge_px where the surface is flat: set max_edge_px > 0 as well");
  }
  if (auto m = r.optional_child("motion")) s.motion = ObjectMotion::from_json(*m);
  r.finish();
  return s;
}

}  // namespace glintlab::core
