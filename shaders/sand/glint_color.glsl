// Coloured glints (Zirr & Kaplanyan 2016 sec. 4.5): each microdetail takes a
// random albedo from a colour wheel, and a cell holding N reflecting
// microdetails is tinted with the 1/sqrt(N) normalisation of the paper.
#ifndef GLINTLAB_SAND_GLINT_COLOR_GLSL
#define GLINTLAB_SAND_GLINT_COLOR_GLSL

#include "common/math.glsl"

// The wheel: c_k(hue) = 1 + s cos(2 pi (hue - k/3)) for k = 0, 1, 2 (r, g, b),
// saturation s in [0, 1]. Every channel averages to exactly 1 over a uniform
// hue (the glints stay white on average, so the models keep converging to
// beckmann) and lies in [1 - s, 1 + s] >= 0. A cell of N microdetails with
// independent hues has the mean colour 1 and a spread falling as 1/sqrt(N)
// ("normalized with a factor of 1/sqrt(N)"): tint = 1 + (c(hue) - 1)/sqrt(N).
// N < 1 (no reflecting microdetail) is read as 1.
vec3 glint_tint(float hue, float saturation, float N) {
  vec3 phase = TWO_PI * (vec3(hue) - vec3(0.0, 1.0 / 3.0, 2.0 / 3.0));
  return vec3(1.0) + (saturation * inversesqrt(max(N, 1.0))) * cos(phase);
}

#endif  // GLINTLAB_SAND_GLINT_COLOR_GLSL
