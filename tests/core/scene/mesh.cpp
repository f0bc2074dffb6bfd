// Procedural meshes: vertex layout, frame invariants, winding, analytic surfaces, convergence.
#include "core/util/json_check.h"
#include "core/scene/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

using namespace glintlab;
using namespace glintlab::core;

namespace {

MeshSpec spec_of(const std::string& type, int tess, float size = 10.0f) {
  MeshSpec s;
  s.type = type;
  s.tessellation = tess;
  s.size = size;
  if (type == "wavy") s.amplitude = 1.0f, s.wavelength = 6.0f;
  if (type == "dunes") s.amplitude = 1.5f, s.wavelength = 8.0f;
  if (type == "sphere") s.layers = 2, s.layer_spacing = 0.2f;
  return s;
}

// Invariants every mesh must satisfy. Normals are compared with the finite-difference geometric
// normal of the surface at each vertex: the area-weighted mean of the normals of the triangles
// around it (vertices with a full ring of >= 6 triangles; border and seam rings are one-sided).
// `min_dot` bounds the angle between the two; every triangle must also face the side its vertex
// normals point to (CCW winding seen from outside).
void check_invariants(const Mesh& m, double min_dot) {
  ASSERT_FALSE(m.vertices.empty());
  ASSERT_EQ(m.indices.size() % 3, 0u);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const Vertex& v : m.vertices) {
    EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(v.normal, glm::vec3(v.tangent)), 0.0f, 1e-5f);
    EXPECT_TRUE(v.tangent.w == 1.0f || v.tangent.w == -1.0f);
    EXPECT_GE(v.uv.x, 0.0f);
    EXPECT_LE(v.uv.x, 1.0f);
    EXPECT_GE(v.uv.y, 0.0f);
    EXPECT_LE(v.uv.y, 1.0f);
    lo = glm::min(lo, v.position);
    hi = glm::max(hi, v.position);
  }
  EXPECT_EQ(m.bounds_min, lo);
  EXPECT_EQ(m.bounds_max, hi);

  std::vector<glm::dvec3> ring(m.vertices.size(), glm::dvec3(0.0));
  std::vector<glm::dvec3> ring_dpdu(m.vertices.size(), glm::dvec3(0.0));
  std::vector<int> ring_count(m.vertices.size(), 0);
  int back_facing = 0, bad_sign = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    uint32_t id[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
    for (uint32_t i : id) ASSERT_LT(i, m.vertices.size());
    const Vertex &a = m.vertices[id[0]], &b = m.vertices[id[1]], &c = m.vertices[id[2]];
    glm::dvec3 e1 = glm::dvec3(b.position - a.position), e2 = glm::dvec3(c.position - a.position);
    glm::dvec3 g = glm::cross(e1, e2);  // CCW -> along the outward normal, length = 2 area
    ASSERT_GT(glm::length(g), 0.0) << "degenerate triangle " << t / 3;
    // d(position)/du and /dv of the triangle (finite differences in uv).
    glm::dvec2 d1 = glm::dvec2(b.uv - a.uv), d2 = glm::dvec2(c.uv - a.uv);
    double det = d1.x * d2.y - d2.x * d1.y;
    glm::dvec3 dpdu = (e1 * d2.y - e2 * d1.y) / det, dpdv = (e2 * d1.x - e1 * d2.x) / det;
    for (uint32_t i : id) ring[i] += g, ring_dpdu[i] += dpdu * glm::length(g), ring_count[i]++;
    for (const Vertex* v : {&a, &b, &c}) {
      glm::dvec3 n(v->normal), tg(v->tangent);
      if (glm::dot(n, g) <= 0.0) ++back_facing;
      if (glm::dot(double(v->tangent.w) * glm::cross(n, tg), dpdv) <= 0.0) ++bad_sign;
    }
  }
  double worst = 1.0, worst_t = 1.0;
  int full_rings = 0;
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    if (ring_count[i] < 6) continue;
    ++full_rings;
    glm::dvec3 n(m.vertices[i].normal), du = ring_dpdu[i] - n * glm::dot(n, ring_dpdu[i]);
    worst = std::min(worst, glm::dot(glm::normalize(ring[i]), n));
    worst_t = std::min(worst_t, glm::dot(glm::normalize(du), glm::dvec3(m.vertices[i].tangent)));
  }
  EXPECT_GT(full_rings, 0);
  EXPECT_GE(worst, min_dot) << "vertex normals disagree with the geometric normals of the triangles";
  EXPECT_GE(worst_t, min_dot) << "tangents are not along d(position)/du";
  EXPECT_EQ(back_facing, 0) << "triangles wound against their vertex normals";
  EXPECT_EQ(bad_sign, 0) << "tangent.w does not give the bitangent along d(position)/dv";
}

}  // namespace

TEST(Mesh, VertexLayoutIsTheVertexBufferLayout) {
  EXPECT_EQ(sizeof(Vertex), 48u);
  EXPECT_EQ(offsetof(Vertex, position), 0u);
  EXPECT_EQ(offsetof(Vertex, normal), 12u);
  EXPECT_EQ(offsetof(Vertex, tangent), 24u);
  EXPECT_EQ(offsetof(Vertex, uv), 40u);
}

TEST(Mesh, PlaneIsAnUpFacingSquare) {
  Mesh m = build_mesh(spec_of("plane", 4, 6.0f));
  check_invariants(m, 0.9999f);
  EXPECT_EQ(m.vertices.size(), 25u);
  EXPECT_EQ(m.indices.size(), 4u * 4u * 6u);
  EXPECT_EQ(m.bounds_min, glm::vec3(-3.0f, 0.0f, -3.0f));
  EXPECT_EQ(m.bounds_max, glm::vec3(3.0f, 0.0f, 3.0f));
  for (const Vertex& v : m.vertices) EXPECT_EQ(v.normal, glm::vec3(0, 1, 0));
}

TEST(Mesh, WavyFramesAndWindingAgreeWithGeometry) { check_invariants(build_mesh(spec_of("wavy", 96)), 0.995f); }
TEST(Mesh, SphereFramesAndWindingAgreeWithGeometry) { check_invariants(build_mesh(spec_of("sphere", 64)), 0.99f); }
// Ridged noise has sharp crests, so the ring of triangles bends more there than on the wave.
TEST(Mesh, DunesFramesAndWindingAgreeWithGeometry) { check_invariants(build_mesh(spec_of("dunes", 128, 20.0f)), 0.95); }

TEST(Mesh, WavySurfaceSatisfiesTheAnalyticHeightAndNormal) {
  MeshSpec s = spec_of("wavy", 64);
  Mesh m = build_mesh(s);
  const double k = 2.0 * M_PI / s.wavelength;
  for (const Vertex& v : m.vertices) {
    double x = v.position.x;
    EXPECT_NEAR(v.position.y, s.amplitude * std::sin(k * x), 1e-5);
    glm::dvec3 n = glm::normalize(glm::dvec3(-s.amplitude * k * std::cos(k * x), 1.0, 0.0));
    EXPECT_GT(glm::dot(n, glm::dvec3(v.normal)), 1.0 - 1e-6);
  }
  EXPECT_NEAR(m.bounds_max.y, s.amplitude, 0.01);
  EXPECT_NEAR(m.bounds_min.y, -s.amplitude, 0.01);
}

TEST(Mesh, SphereAreaConvergesTo4PiR2AtSecondOrder) {
  auto rel_error = [](int tess) {
    MeshSpec s = spec_of("sphere", tess, 3.0f);
    s.layers = 1;
    Mesh m = build_mesh(s);
    double area = 0.0;
    for (size_t t = 0; t < m.indices.size(); t += 3) {
      glm::dvec3 a(m.vertices[m.indices[t]].position), b(m.vertices[m.indices[t + 1]].position),
          c(m.vertices[m.indices[t + 2]].position);
      area += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    return std::fabs(area - 4.0 * M_PI * 1.5 * 1.5) / (4.0 * M_PI * 1.5 * 1.5);
  };
  double e32 = rel_error(32), e64 = rel_error(64), e128 = rel_error(128);
  EXPECT_LT(e128, 1e-3);
  EXPECT_GT(e32 / e64, 3.0);  // O(h²): halving the edge length divides the error by ~4
  EXPECT_LT(e32 / e64, 5.0);
  EXPECT_GT(e64 / e128, 3.0);
}

TEST(Mesh, LayeredSphereHasConcentricShells) {
  MeshSpec s = spec_of("sphere", 16, 4.0f);
  s.layers = 3;
  s.layer_spacing = 0.25f;
  Mesh m = build_mesh(s);
  const size_t per_shell = m.vertices.size() / 3;
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(glm::length(m.vertices[k * per_shell + 5].position), 2.0 * (1.0 - 0.25 * k), 1e-5);
}

TEST(Mesh, DunesAreDeterministicPerSeedAndBounded) {
  MeshSpec s = spec_of("dunes", 32, 20.0f);
  Mesh a = build_mesh(s), b = build_mesh(s);
  s.seed = 2;
  Mesh c = build_mesh(s);
  ASSERT_EQ(a.vertices.size(), c.vertices.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    EXPECT_EQ(a.vertices[i].position, b.vertices[i].position);
    EXPECT_GE(a.vertices[i].position.y, 0.0f);
    EXPECT_LE(a.vertices[i].position.y, s.amplitude);
    differ += a.vertices[i].position.y != c.vertices[i].position.y;
  }
  EXPECT_GT(differ, a.vertices.size() / 2);
  EXPECT_GT(a.bounds_max.y - a.bounds_min.y, 0.2f * s.amplitude);  // not flat
}

TEST(Mesh, SpecFromJsonValidatesPerType) {
  nlohmann::json ok = {{"type", "dunes"}, {"size", 40}, {"tessellation", 64}, {"seed", 7}};
  JsonReader r(ok, "scene.json", "mesh");
  MeshSpec s = MeshSpec::from_json(r);
  EXPECT_EQ(s.type, "dunes");
  EXPECT_EQ(s.size, 40.0f);
  EXPECT_EQ(s.seed, 7u);

  nlohmann::json bad = {{"type", "sphere"}, {"amplitude", 2}};  // amplitude is not a sphere key
  JsonReader rb(bad, "scene.json", "mesh");
  try {
    MeshSpec::from_json(rb);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.amplitude"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos) << e.what();
  }
  nlohmann::json bad_type = {{"type", "torus"}};
  JsonReader rt(bad_type, "scene.json", "mesh");
  EXPECT_THROW(MeshSpec::from_json(rt), ConfigError);
  EXPECT_THROW(build_mesh(spec_of("torus", 4)), std::invalid_argument);
}

// chunk_mesh: the chunks partition the index list in order, each box is the
// tight box of its triangles' vertices, the triangles (with their winding)
// are the same whatever the grid, and the grid has the cells it says.
TEST(Mesh, ChunksPartitionTheTrianglesIntoTightBoxes) {
  auto triangles = [](const Mesh& m) {  // each triangle rotated to start at its smallest index (winding kept)
    std::vector<std::array<uint32_t, 3>> t;
    for (size_t i = 0; i < m.indices.size(); i += 3) {
      std::array<uint32_t, 3> a = {m.indices[i], m.indices[i + 1], m.indices[i + 2]};
      while (a[0] > a[1] || a[0] > a[2]) a = {a[1], a[2], a[0]};
      t.push_back(a);
    }
    std::sort(t.begin(), t.end());
    return t;
  };
  auto check = [](const Mesh& m) {
    uint32_t next = 0;
    for (const MeshChunk& c : m.chunks) {
      ASSERT_EQ(c.first_index, next);
      ASSERT_GT(c.index_count, 0u);
      ASSERT_EQ(c.index_count % 3, 0u);
      glm::vec3 lo(1e30f), hi(-1e30f);
      for (uint32_t i = c.first_index; i < c.first_index + c.index_count; ++i)
        lo = glm::min(lo, m.vertices[m.indices[i]].position), hi = glm::max(hi, m.vertices[m.indices[i]].position);
      EXPECT_EQ(c.lo, lo);
      EXPECT_EQ(c.hi, hi);
      next += c.index_count;
    }
    EXPECT_EQ(next, m.indices.size());
  };
  for (const char* name : {"plane", "wavy", "dunes", "sphere"}) {
    const std::string type = name;
    SCOPED_TRACE(type);
    const Mesh m = build_mesh(spec_of(type, 32));
    check(m);
    // A flat plane: 8 x 8 cells of 4 x 4 quads; the others at least that many, a 2-layer sphere up to 8^3.
    if (type == "plane") {
      EXPECT_EQ(m.chunks.size(), 64u);
    }
    EXPECT_GE(m.chunks.size(), 64u);
    EXPECT_LE(m.chunks.size(), 512u);
    Mesh coarse = m;
    chunk_mesh(coarse, 3);
    check(coarse);
    EXPECT_LT(coarse.chunks.size(), m.chunks.size());
    EXPECT_EQ(triangles(coarse), triangles(m));
    Mesh one = m;
    chunk_mesh(one, 1);
    ASSERT_EQ(one.chunks.size(), 1u);
    EXPECT_EQ(one.indices, m.indices) << "one cell keeps the order";
    EXPECT_EQ(one.chunks[0].lo, m.bounds_min);
    EXPECT_EQ(one.chunks[0].hi, m.bounds_max);
  }
  Mesh bad = build_mesh(spec_of("plane", 2));
  EXPECT_THROW(chunk_mesh(bad, 0), std::invalid_argument);
}

namespace {

// Triangles as vertex-position triples (winding kept, rotated to a canonical start), sorted:
// meshes with other vertex numbering compare equal when they have the same triangles.
std::vector<std::array<float, 9>> position_triangles(const Mesh& m) {
  std::vector<std::array<float, 9>> out;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    std::array<std::array<float, 3>, 3> v;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = m.vertices[m.indices[t + size_t(k)]].position;
      v[size_t(k)] = {p.x, p.y, p.z};
    }
    while (v[0] > v[1] || v[0] > v[2]) v = {v[1], v[2], v[0]};
    std::array<float, 9> a;
    for (int k = 0; k < 9; ++k) a[size_t(k)] = v[size_t(k / 3)][size_t(k % 3)];
    out.push_back(a);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// An adapted grid of the n x n, `size`-wide square: every vertex is the full grid's vertex at its uv,
// attribute for attribute; every directed edge has its reverse once, except on the border of the
// square; all triangles face up; together they cover the square once (projected area).
void expect_full_grid_vertices_and_watertight(const Mesh& m, const Mesh& full, int n, double size) {
  const double half = 0.5 * size;
  ASSERT_EQ(full.vertices.size(), size_t(n + 1) * size_t(n + 1));
  for (const Vertex& v : m.vertices) {
    const int i = int(std::lround(v.uv.x * float(n))), j = int(std::lround(v.uv.y * float(n)));
    ASSERT_EQ(std::memcmp(&v, &full.vertices[size_t(j) * size_t(n + 1) + size_t(i)], sizeof(Vertex)), 0) << i << "," << j;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  double area = 0.0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const uint32_t id[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
    for (int k = 0; k < 3; ++k) ++edges[{id[k], id[(k + 1) % 3]}];
    const glm::dvec3 a(m.vertices[id[0]].position), b(m.vertices[id[1]].position), c(m.vertices[id[2]].position);
    const double ny = glm::cross(b - a, c - a).y;
    EXPECT_GT(ny, 0.0) << "triangle " << t / 3 << " faces down";
    area += 0.5 * ny;
  }
  EXPECT_NEAR(area, size * size, 1e-6 * size * size);
  auto on_border = [&](uint32_t a, uint32_t b) {
    const glm::dvec3 p(m.vertices[a].position), q(m.vertices[b].position);
    auto at = [&](double v) { return std::abs(std::abs(v) - half) < 1e-6; };
    return (at(p.x) && at(q.x) && p.x == q.x) || (at(p.z) && at(q.z) && p.z == q.z);
  };
  int open = 0;
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1) << "edge drawn twice in one direction";
    const auto rev = edges.find({e.second, e.first});
    if (rev == edges.end() && !on_border(e.first, e.second)) ++open;
  }
  EXPECT_EQ(open, 0) << "edges without a neighbour inside the square (a crack or T-junction)";
}

}  // namespace

TEST(Mesh, AdaptiveGridIsTheFullGridWhereEveryCellIsSeenClose) {
  for (const char* type : {"plane", "wavy", "dunes"}) {
    SCOPED_TRACE(type);
    MeshSpec s = spec_of(type, 32);
    const Mesh full = build_mesh(s);
    s.max_edge_px = 4.0f;
    const Mesh adaptive = build_mesh(s, {MeshView{{0.0f, 3.0f, 0.0f}, 1e5f}});
    EXPECT_EQ(position_triangles(adaptive), position_triangles(full));
  }
}

// Dunes 40 units wide, 128 x 128 cells, seen from beyond one edge and from above its centre; and a
// plane seen by a view of so few pixels per unit (focal_px / max_edge_px < 1) that cells two
// levels apart would meet without the 2:1 restriction.
class AdaptiveGrid : public ::testing::TestWithParam<int> {};

TEST_P(AdaptiveGrid, IsWatertightAndCoarseOnlyWhereCellsLookSmall) {
  MeshSpec s = spec_of(GetParam() == 0 ? "dunes" : "plane", 128, 40.0f);
  const Mesh full = build_mesh(s);
  s.max_edge_px = 4.0f;
  const std::vector<MeshView> views =
      GetParam() == 0 ? std::vector<MeshView>{{{-26.0f, 4.0f, 3.0f}, 150.0f}, {{0.0f, 60.0f, 0.0f}, 150.0f}}
                      : std::vector<MeshView>{{{0.75f, 0.0f, 1.0f}, 1.0f}};
  const Mesh m = build_mesh(s, views);
  const double unit = 40.0 / 128.0;

  expect_full_grid_vertices_and_watertight(m, full, 128, 40.0);

  // Coarser than the full grid, and no triangle wider on screen than allowed, unless it is one of
  // the full grid's: the cell's edge (its longest side seen from above, the cell's diagonal, over
  // sqrt(2)) against the distance to the triangle's own box.
  EXPECT_LT(m.indices.size(), full.indices.size() * 6 / 10);
  int coarse = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = glm::dvec3(m.vertices[m.indices[t + size_t(k)]].position);
    double longest = 0.0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, glm::length(glm::dvec2(p[k].x - p[(k + 1) % 3].x, p[k].z - p[(k + 1) % 3].z)));
    const glm::dvec3 lo = glm::min(p[0], glm::min(p[1], p[2])), hi = glm::max(p[0], glm::max(p[1], p[2]));
    if (longest <= std::sqrt(2.0) * unit * 1.0001) continue;  // a cell of the full grid
    ++coarse;
    for (const MeshView& v : views) {
      const glm::dvec3 e(v.eye), d = e - glm::clamp(e, lo, hi);
      EXPECT_LE(longest / std::sqrt(2.0) * v.focal_px, 4.0 * glm::length(d) * 1.0001) << "triangle " << t / 3;
    }
  }
  EXPECT_GT(coarse, 100);
}
INSTANTIATE_TEST_SUITE_P(Mesh, AdaptiveGrid, ::testing::Values(0, 1));

// max_error_px: the dunes above, 2 px edges allowed, 0.5 px of error. Every point of the full grid
// (its grid points and its quads' centres) lies, on the adapted mesh, within 0.5 px (vertically, over
// its distance from each eye) of where the full grid has it, wherever the triangle that holds it is
// wider on screen than 2 px, and somewhere nearly 0.5 px (the error is exact, not a loose bound); the
// mesh is watertight and smaller than the edge rule alone makes it; a plane collapses to two triangles.
TEST(Mesh, ErrorBoundedGridStaysWithinItsPixelsOfTheFullGrid) {
  MeshSpec s = spec_of("dunes", 128, 40.0f);
  const Mesh full = build_mesh(s);
  s.max_edge_px = 2.0f;
  const std::vector<MeshView> views = {{{-26.0f, 4.0f, 3.0f}, 150.0f}, {{0.0f, 60.0f, 0.0f}, 150.0f}};
  const Mesh edge_only = build_mesh(s, views);
  s.max_error_px = 0.5f;
  const Mesh m = build_mesh(s, views);
  expect_full_grid_vertices_and_watertight(m, full, 128, 40.0);
  EXPECT_LT(m.indices.size(), edge_only.indices.size() * 95 / 100);

  // Each full-grid point and each centre of a full-grid quad (where the full grid has the mean of its
  // diagonal's ends, and where an edge of the adapted mesh may cross the full grid's), located in the
  // adapted triangle above it (xz barycentrics), with that triangle's height there. Between these
  // points both surfaces are linear, so this is the largest error there is. Doubled coordinates:
  // (2i, 2j) is grid point (i, j), (2i + 1, 2j + 1) the centre of quad (i, j).
  const int n = 128, n2 = 2 * n;
  const double unit = 40.0 / n, half = 20.0;
  std::vector<double> adapted(size_t(n2 + 1) * size_t(n2 + 1), std::nan(""));
  std::vector<size_t> holder(adapted.size(), 0);
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    glm::dvec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = glm::dvec3(m.vertices[m.indices[t + size_t(k)]].position);
    const double det = (p[1].x - p[0].x) * (p[2].z - p[0].z) - (p[2].x - p[0].x) * (p[1].z - p[0].z);
    const double u2 = unit / 2;
    const int i_lo = int(std::floor((std::min({p[0].x, p[1].x, p[2].x}) + half) / u2 + 1e-9));
    const int i_hi = int(std::ceil((std::max({p[0].x, p[1].x, p[2].x}) + half) / u2 - 1e-9));
    const int j_lo = int(std::floor((std::min({p[0].z, p[1].z, p[2].z}) + half) / u2 + 1e-9));
    const int j_hi = int(std::ceil((std::max({p[0].z, p[1].z, p[2].z}) + half) / u2 - 1e-9));
    for (int j = j_lo; j <= j_hi; ++j)
      for (int i = i_lo; i <= i_hi; ++i) {
        if ((i + j) % 2 != 0) continue;  // a point on a grid line between two grid points
        const double x = -half + i * u2, z = -half + j * u2;
        const double b1 = ((x - p[0].x) * (p[2].z - p[0].z) - (p[2].x - p[0].x) * (z - p[0].z)) / det;
        const double b2 = ((p[1].x - p[0].x) * (z - p[0].z) - (x - p[0].x) * (p[1].z - p[0].z)) / det;
        if (b1 < -1e-9 || b2 < -1e-9 || b1 + b2 > 1.0 + 1e-9) continue;
        adapted[size_t(j) * size_t(n2 + 1) + size_t(i)] = p[0].y + b1 * (p[1].y - p[0].y) + b2 * (p[2].y - p[0].y);
        holder[size_t(j) * size_t(n2 + 1) + size_t(i)] = t;
      }
  }
  auto full_y = [&](int i, int j) { return double(full.vertices[size_t(j) * size_t(n + 1) + size_t(i)].position.y); };
  int checked = 0, centres = 0;
  double worst = 0.0;  // the largest error seen, in units of max_error_px
  for (int j = 0; j <= n2; ++j)
    for (int i = 0; i <= n2; ++i) {
      if ((i + j) % 2 != 0) continue;
      const size_t at = size_t(j) * size_t(n2 + 1) + size_t(i);
      ASSERT_FALSE(std::isnan(adapted[at])) << "point " << i << "," << j << " (doubled) is under no triangle";
      const bool centre = i % 2 != 0;
      const double y = centre ? 0.5 * (full_y(i / 2, j / 2) + full_y(i / 2 + 1, j / 2 + 1)) : full_y(i / 2, j / 2);
      const glm::dvec3 q(-half + i * unit / 2, y, -half + j * unit / 2);
      const double err = std::abs(adapted[at] - q.y);
      // The holding triangle's width as the edge rule measures it (longest side / sqrt 2).
      double longest = 0.0;
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 a(m.vertices[m.indices[holder[at] + size_t(k)]].position);
        const glm::dvec3 b(m.vertices[m.indices[holder[at] + size_t(k + 1) % 3]].position);
        longest = std::max(longest, glm::length(glm::dvec2(a.x - b.x, a.z - b.z)));
      }
      for (const MeshView& v : views) {
        const double dist = glm::length(glm::dvec3(v.eye) - q);
        if (longest / std::sqrt(2.0) * v.focal_px <= 2.0 * dist) continue;  // narrow: the edge rule holds
        ++checked;
        centres += centre;
        worst = std::max(worst, err * v.focal_px / (0.5 * dist));
        EXPECT_LE(err * v.focal_px, 0.5 * dist * (1.0 + 1e-6)) << "point " << i << "," << j << " (doubled)";
      }
    }
  EXPECT_GT(checked, 1000) << "too few points rely on the error bound for the test to say anything";
  EXPECT_GT(centres, 100) << "too few quad centres rely on the error bound";
  // The leaves' errors are exact: some leaf is kept with nearly all the error it is allowed.
  EXPECT_GT(worst, 0.9) << "the error bound is never approached: it is looser than the mesh's error";
  std::printf("  %zu triangles (edge rule alone %zu); %d point-views rely on the bound (%d at quad centres), "
              "worst %.3f of it\n",
              m.indices.size() / 3, edge_only.indices.size() / 3, checked, centres, worst);
  if (::testing::Test::HasFailure()) return;

  MeshSpec plane = spec_of("plane", 128, 40.0f);
  plane.max_edge_px = 2.0f;
  plane.max_error_px = 0.5f;
  EXPECT_EQ(build_mesh(plane, views).indices.size(), 6u) << "a flat square is one cell";
}

TEST(Mesh, AdaptiveGridKeysAndMisuse) {
  nlohmann::json ok = {{"type", "wavy"}, {"max_edge_px", 3}};
  JsonReader r(ok, "scene.json", "mesh");
  EXPECT_EQ(MeshSpec::from_json(r).max_edge_px, 3.0f);
  for (const auto& [bad, key] : std::vector<std::pair<nlohmann::json, std::string>>{
           {{{"type", "sphere"}, {"max_edge_px", 3}}, "mesh.max_edge_px"},
           {{{"type", "dunes"}, {"max_edge_px", -1}}, "mesh.max_edge_px"},
           {{{"type", "dunes"}, {"max_edge_px", 2}, {"max_error_px", -0.5}}, "mesh.max_error_px"},
           {{{"type", "wavy"}, {"max_error_px", 0.5}}, "mesh.max_error_px"}}) {
    JsonReader rb(bad, "scene.json", "mesh");
    try {
      MeshSpec::from_json(rb);
      ADD_FAILURE() << "expected ConfigError for " << bad.dump();
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  nlohmann::json with_error = {{"type", "dunes"}, {"max_edge_px", 2}, {"max_error_px", 0.5}};
  JsonReader re(with_error, "scene.json", "mesh");
  EXPECT_EQ(MeshSpec::from_json(re).max_error_px, 0.5f);
  MeshSpec s = spec_of("plane", 8);
  s.max_edge_px = 2.0f;
  EXPECT_THROW(build_mesh(s), std::invalid_argument) << "an adaptive grid needs the camera's views";
  // A tessellation with no factor 2 has nothing to merge: the full grid.
  s.tessellation = 9;
  EXPECT_EQ(build_mesh(s, {MeshView{{1000.0f, 1.0f, 0.0f}, 1.0f}}).indices.size(), 2u * 9u * 9u * 3u);
}
