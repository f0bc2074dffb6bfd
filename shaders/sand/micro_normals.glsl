// Micro normals: per-grain random numbers from pcg3d seeded by the object
// position (Kajs 2022 sec. 4.1), a uniform random rotation (eq. 4.1), the
// Frisvad basis of that rotation and the cube face most aligned with w_o.
#ifndef GLINTLAB_SAND_MICRO_NORMALS_GLSL
#define GLINTLAB_SAND_MICRO_NORMALS_GLSL

#include "common/math.glsl"
#include "common/pcg3d.glsl"
#include "common/frisvad.glsl"
#include "sand/sand_params.glsl"

// Integer key of the grain cell containing x_obj. The cell coordinate is
// floor(x_obj * noise_scale) in fp32 and the key is its bit pattern, so no
// float -> int conversion ever happens (Appendix A's int3(x * scale) is
// undefined for |x * scale| >= 2^31 and truncates, which doubles the cells
// around 0). -0.0 is mapped to +0.0 so both zeros are one cell.
uvec3 grain_cell_key(vec3 x_obj, float noise_scale) {
  vec3 c = floor(x_obj * noise_scale);
  uvec3 k = floatBitsToUint(c);
  return uvec3(c.x == 0.0 ? 0u : k.x, c.y == 0.0 ? 0u : k.y, c.z == 0.0 ? 0u : k.z);
}

// Per-grain random numbers xi in [0, 1]^3 and xi_pm = 2 xi - 1 in [-1, 1]^3.
struct GrainRandom { vec3 xi; vec3 xi_pm; };

GrainRandom grain_random(uvec3 key, uint appendix_compat) {
  uvec3 h = pcg3d(key);
  GrainRandom r;
  if ((appendix_compat & SAND_COMPAT_RAND_NORMALIZED) != 0u) {
    // Appendix A: rand = normalize(int3 hash), components in [-1, 1]; a zero
    // hash vector is guarded (Appendix A normalises it).
    r.xi_pm = safe_normalize(vec3(ivec3(h)), vec3(0.0, 0.0, 1.0));
    r.xi = r.xi_pm * 0.5 + 0.5;
  } else {
    r.xi = pcg3d_unit(h);  // exact multiples of 2^-24
    r.xi_pm = r.xi * 2.0 - 1.0;  // exact in fp32
  }
  return r;
}

// Kajs eq. 4.1 (Dutre): uniform direction on the unit sphere from xi_1, xi_2 in [0, 1].
vec3 sphere_direction(vec2 xi) {
  float phi = TWO_PI * xi.x;
  float r = 2.0 * sqrt(max(xi.y * (1.0 - xi.y), 0.0));
  return vec3(r * cos(phi), r * sin(phi), 1.0 - 2.0 * xi.y);
}

// Kajs sec. 4.1: the cube of the grain has face normals +-b1, +-b2, +-q in
// world space (q from eq. 4.1, b1, b2 its Frisvad basis). w_o is taken to
// the cube frame with the transposed basis and the face with the largest
// dot is chosen (first maximum in the order +x,+y,+z,-x,-y,-z as in
// Appendix A). The same basis rotates the face back, so m maximises m.w_o.
vec3 micro_normal(vec2 xi, vec3 wo, out uint face) {
  vec3 q = sphere_direction(xi);
  vec3 b1, b2;
  frisvad_basis(q, b1, b2);
  vec3 v = vec3(dot(b1, wo), dot(b2, wo), dot(q, wo));
  float d[6] = float[6](v.x, v.y, v.z, -v.x, -v.y, -v.z);
  face = 0u;
  float best = d[0];
  for (uint k = 1u; k < 6u; ++k) {
    if (d[k] > best) { best = d[k]; face = k; }
  }
  vec3 axis = (face % 3u) == 0u ? b1 : ((face % 3u) == 1u ? b2 : q);
  return face < 3u ? axis : -axis;
}

#endif  // GLINTLAB_SAND_MICRO_NORMALS_GLSL
