#version 450
// The sand material as a surface pass: gathers the macro surface, the sun and
// the sky's hemisphere term (Kajs eq. 4.2, from SH irradiance) and calls
// sand_shade(). Writes the weighted sample for accumulation; alpha = coverage;
// with SURFACE_MOTION, also the motion vector of the surface point.
#include "common/frame.glsl"
#include "sand/sand_params.glsl"
layout(set = 0, binding = 1, std140) uniform MaterialUBO { SandParams sand_params; };
layout(set = 0, binding = 2) uniform sampler2D env_map;
#include "common/environment.glsl"
#include "sand/sand.glsl"

#ifndef COLOR_HALF
#define COLOR_HALF 0  // the surface pass sets it when the colour target is RGBA16F
#endif
#include "common/surface_interface.glsl"
#include "common/motion.glsl"

layout(location = 0) out vec4 out_color;
#if SURFACE_MOTION
layout(location = 1) out vec4 out_motion;  // common/motion.glsl
#endif

void main() {
  vec3 to_eye = frame_camera_pos.xyz - v_x;
  float dist = length(to_eye);
  vec3 wo = dist > 0.0 ? to_eye / dist : vec3(0.0, 1.0, 0.0);
  // Interpolated normals can shrink; a degenerate one falls back to the
  // direction of the viewer. Seen from behind, the surface's other side faces us.
  float nl = length(v_n);
  vec3 n = nl > 1e-20 ? v_n / nl : wo;
  if (!gl_FrontFacing) n = -n;

  // A sample of a supersampled frame stands for 1/N of the pixel (N = 1/weight
  // stratified samples): its footprint is the pixel's uv extent times 1/sqrt(N),
  // so a filtered glint model integrates its own stratum, not the whole pixel.
  float footprint = sqrt(sample_jitter_weight.z);
  SandSurface s = sand_surface(v_x_obj, v_x, n, wo, dist, v_t, v_uv, dFdx(v_uv) * footprint, dFdy(v_uv) * footprint);
  SandLight l = SandLight(frame_sun_dir.xyz, frame_sun_L.rgb, env_irradiance(n), frame_sun_dir.w);
  // Not clamped: every frame is scanned for NaN/Inf/negative values, and a
  // clamp here would hide a defect of the material.
  vec3 L = sand_shade(sand_params, s, l);
  float w = sample_jitter_weight.z;
  out_color = vec4(L * w, w);
#if COLOR_HALF
  // An RGBA16F target holds at most 65504: what lies above is written as the
  // largest half (Vulkan leaves the conversion of larger values to the driver:
  // lavapipe saturates, others may write inf). NaN stays NaN, so a defect of
  // the material is still seen.
  out_color.rgb = mix(min(out_color.rgb, vec3(65504.0)), out_color.rgb, isnan(out_color.rgb));
#endif
#if SURFACE_MOTION
  out_motion = surface_motion(v_x, v_prev_x);
#endif
}
