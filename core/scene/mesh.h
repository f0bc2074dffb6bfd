// Procedural meshes of the scene: plane, wavy "dune" plane, (layered) sphere and a ridged-noise dune
// height field. CPU only; the renderer uploads `vertices`/`indices` as they are.
//
// Conventions shared by every mesh:
//  - object space, right-handed, +Y up; lengths in scene units;
//  - triangles are counter-clockwise seen from outside/above: for indices (a, b, c) the geometric
//    normal cross(p_b - p_a, p_c - p_a) points to the same side as the vertex normals. With the
//    Y-flipped projection of core/scene/camera.h this is VK_FRONT_FACE_COUNTER_CLOCKWISE;
//  - `normal` is unit; `tangent.xyz` is unit, orthogonal to `normal` and points along d(position)/du;
//    `tangent.w` = ±1 such that bitangent = tangent.w * cross(normal, tangent.xyz) points along
//    d(position)/dv (MikkTSpace convention);
//  - uv in [0, 1]^2.
#pragma once

#include "core/scene/object_motion.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace glintlab {
class JsonReader;
}

namespace glintlab::core {

// Vertex-buffer / std430 friendly: exactly these four members in this order, 48 bytes.
struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec4 tangent;
  glm::vec2 uv;
};
static_assert(sizeof(Vertex) == 48, "Vertex must stay 48 bytes (vertex buffer layout)");

// A run of triangles that lie close together, indices [first_index, first_index + index_count), and
// the box around their vertices (object space): the renderer skips the chunks a sample cannot see.
struct MeshChunk {
  uint32_t first_index = 0;
  uint32_t index_count = 0;
  glm::vec3 lo{0.0f}, hi{0.0f};
};

struct Mesh {
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;  // triangle list
  glm::vec3 bounds_min{0.0f};
  glm::vec3 bounds_max{0.0f};
  std::vector<MeshChunk> chunks;  // partition of `indices` (chunk_mesh); empty: one chunk, the whole mesh
};

// What to build. JSON keys (all but "type" optional; keys that do not apply to the type are errors):
//   "type": "plane" | "wavy" | "sphere" | "dunes"
//   "size": edge length of plane/wavy/dunes, diameter of the sphere   (default 10)
//   "tessellation": quads per edge (plane/wavy/dunes) or sphere slices (stacks = slices/2)  (default 128)
//   wavy:   "amplitude" A (default 1), "wavelength" λ (default = size): y = A sin(2π x / λ)
//   sphere: "layers" (default 1), "layer_spacing" (default 0.1): the thesis' layered sphere
//           (Kajs sec. 2.2) = `layers` concentric shells, shell k with radius r (1 - k·layer_spacing)
//   dunes:  "amplitude" (default 1.5), "wavelength" (base feature size, default 8), "octaves"
//           (default 4), "lacunarity" (default 2), "gain" (default 0.5), "seed" (default 1)
//   plane/wavy/dunes: "max_edge_px" (default 0 = off): a grid that adapts to the run's camera, fixed
//           for the whole run. The tessellation x tessellation grid is the finest level; cells are
//           merged in 2 x 2 blocks (as often as tessellation is divisible by 2) where, seen from every
//           camera position of the path, the merged cell's edge spans at most this many pixels at the
//           run's resolution. Neighbouring cells differ by at most one level and a cell next to a
//           finer one is a fan around its centre, so the mesh has no cracks; every vertex is one of
//           the full grid's, with the same attributes (build_mesh with `views`).
//   plane/wavy/dunes: "max_error_px" (default 0 = off; needs max_edge_px): a merged cell wider
//           than max_edge_px is kept where it is flat enough: where, from every camera position, its
//           largest vertical distance from the full grid (exact, over every triangulation it and the
//           cells inside it may get) spans at most this many pixels. Silhouettes and positions stay
//           within it of the full grid's.
//   any:    "motion": rigid motion of the mesh over time (core/scene/object_motion.h)
struct MeshSpec {
  std::string type = "plane";
  float size = 10.0f;
  int tessellation = 128;
  float amplitude = 1.0f;
  float wavelength = 10.0f;
  int layers = 1;
  float layer_spacing = 0.1f;
  int octaves = 4;
  float lacunarity = 2.0f;
  float gain = 0.5f;
  uint32_t seed = 1;
  float max_edge_px = 0.0f;  // > 0: the grid adapts to the camera (height fields; see above)
  float max_error_px = 0.0f; // > 0: ... and keeps wider cells where they are this flat on screen
  ObjectMotion motion;  // "motion": rigid motion over time (core/scene/object_motion.h); default none

  static MeshSpec from_json(JsonReader& r);  // validates; calls r.finish()
};

// A camera position the adaptive grid must serve: `eye` in the mesh's object space, `focal_px` the
// pixels per unit of length seen at unit distance (image height / (2 tan(fov_y / 2))).
struct MeshView {
  glm::vec3 eye{0.0f};
  float focal_px = 1.0f;
};

// Throws std::invalid_argument for an unknown type or out-of-range parameters, and for
// max_edge_px > 0 without views. The mesh comes chunked (chunk_mesh).
Mesh build_mesh(const MeshSpec& spec, const std::vector<MeshView>& views = {});

// Groups the triangles into the cells of a grid over the mesh's bounds, `per_axis` cells along its
// longest axis and as many cube-like cells along the others as fit (a flat plane: per_axis^2 cells,
// a sphere per_axis^3), by the centroid of each triangle: reorders `indices` so that every non-empty
// cell's triangles are one run (keeping their order), sets `chunks` (cells in x, then z, then y order)
// and `bounds_min/max`. Vertices are not touched; the triangles are the same, drawn in another order.
void chunk_mesh(Mesh& m, int per_axis = 8);

// The whole mesh as one chunk: every index, and the box of every vertex.
MeshChunk whole_mesh_chunk(const Mesh& m);

// Height y(x, z) of the surfaces that are height fields ("plane", "wavy", "dunes"); used by the
// mesh builder and by tests/camera placement. Throws std::invalid_argument for "sphere".
float height_field(const MeshSpec& spec, float x, float z);

}  // namespace glintlab::core
