// Environment light lookups: sky radiance from the lat-long map and the Kajs eq. 4.2 sky term
// L_sky^Ω from l <= 2 irradiance spherical harmonics. Mirrors core/scene/environment.h and
// core/scene/spherical_harmonics.h exactly.
//
// REQUIREMENTS on the including shader, declared BEFORE `#include "common/environment.glsl"`:
//   - `vec4 env_sh[9]`  (e.g. a member of its uniform block; .rgb = irradiance coefficients
//     E_lm = Â_l L_lm in the working colour space, as computed by core::compute_sh_irradiance;
//     .a unused);
//   - `sampler2D env_map` (the lat-long sky with its mip chain from core::build_mips; sampler with
//     linear filtering, linear mipmaps, address mode U = REPEAT, V = CLAMP_TO_EDGE).
// Define ENV_NO_MAP before including to leave out env_radiance (and the need for env_map).
//
// Lat-long mapping: d = (sin θ cos φ, cos θ, sin θ sin φ), θ from +Y (zenith), φ from +X towards
// +Z; u = φ / 2π in [0, 1), v = θ / π; v = 0 (texture row 0) is the zenith.
#ifndef GLINTLAB_ENVIRONMENT_GLSL
#define GLINTLAB_ENVIRONMENT_GLSL

#include "common/math.glsl"

// dir need not be unit; a zero dir reads the zenith. The poles (x = z = 0) give u = 0
// (atan(0, 0) is undefined in GLSL).
vec2 env_latlong_uv(vec3 dir) {
  vec3 d = safe_normalize(dir, vec3(0.0, 1.0, 0.0));
  float u = (d.x != 0.0 || d.z != 0.0) ? atan(d.z, d.x) * (0.5 * INV_PI) : 0.0;
  if (u < 0.0) u += 1.0;
  if (u >= 1.0) u = 0.0;
  float v = acos(clamp(d.y, -1.0, 1.0)) * INV_PI;
  return vec2(u, v);
}

#ifndef ENV_NO_MAP
// Sky radiance towards `dir` at mip level `lod` (explicit LOD: no derivatives across the u seam).
vec3 env_radiance(vec3 dir, float lod) {
  return max(textureLod(env_map, env_latlong_uv(dir), lod).rgb, vec3(0.0));
}
#endif

// Irradiance E(n) = Σ E_lm Y_lm(n) (Ramamoorthi & Hanrahan 2001 eq. 7), basis order of
// core/scene/spherical_harmonics.h, clamped to >= 0.
vec3 env_sh_irradiance(vec3 n) {
  vec3 d = safe_normalize(n, vec3(0.0, 1.0, 0.0));  // a zero normal reads the zenith
  float x = d.x, y = d.y, z = d.z;
  vec3 E = env_sh[0].rgb * 0.282094791773878
         + env_sh[1].rgb * (0.488602511902920 * y)
         + env_sh[2].rgb * (0.488602511902920 * z)
         + env_sh[3].rgb * (0.488602511902920 * x)
         + env_sh[4].rgb * (1.092548430592079 * x * y)
         + env_sh[5].rgb * (1.092548430592079 * y * z)
         + env_sh[6].rgb * (0.315391565252520 * (3.0 * z * z - 1.0))
         + env_sh[7].rgb * (1.092548430592079 * x * z)
         + env_sh[8].rgb * (0.546274215296040 * (x * x - y * y));
  return max(E, vec3(0.0));
}

// Kajs eq. 4.2: L_sky^Ω(x, Ω), the cosine-weighted hemisphere average of sky radiance around the
// normal n, = E(n) / π.
vec3 env_irradiance(vec3 n) {
  return env_sh_irradiance(n) * INV_PI;
}

#endif  // GLINTLAB_ENVIRONMENT_GLSL
