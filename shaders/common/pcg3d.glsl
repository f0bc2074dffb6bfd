// PCG3D hash, Jarzynski & Olano 2020 "Hash Functions for GPU Rendering"
// (Kajs 2022 Listing 4.1). The one implementation in the shader tree.
#ifndef GLINTLAB_COMMON_PCG3D_GLSL
#define GLINTLAB_COMMON_PCG3D_GLSL

uvec3 pcg3d(uvec3 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  v ^= v >> 16u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  return v;
}

// Uniform in [0, 1) from the top 24 bits: exactly representable in fp32.
vec3 pcg3d_unit(uvec3 h) { return vec3(h >> 8u) * (1.0 / 16777216.0); }

#endif  // GLINTLAB_COMMON_PCG3D_GLSL
