// Units of the sand's terms (shaders/sand/DIFFERENCES.md "Units"). The thesis
// model is reproduced faithfully by default; `energy_consistent` corrects the
// factors that keep it from being a radiometrically consistent BRDF, so that
// the kajs glints can be compared with grains/zirr/beckmann in one unit.
//
// The sun is a directional light: L_i (frame_sun_L) is its normal
// irradiance E_sun = integral of its radiance over its solid angle, which is
// what the thesis' diffuse rho/pi L_i max(0, n.w_i) (Kajs eq. 4.11) assumes.
// L_sky^Omega (Kajs eq. 4.2, env_irradiance) is the cosine-weighted mean sky
// radiance E_sky / pi.
#ifndef GLINTLAB_SAND_ENERGY_GLSL
#define GLINTLAB_SAND_ENERGY_GLSL

#include "common/math.glsl"

// Factor on L_sky^Omega in the diffuse terms (Kajs eq. 4.11, 4.35). The
// thesis applies rho/pi to L_sky^Omega = E_sky/pi (rho E_sky / pi^2, where a
// Lambertian surface reflects rho E_sky / pi); consistent: pi.
float sky_diffuse_scale(uint energy_consistent) { return energy_consistent != 0u ? PI : 1.0; }

// Factor on the sun's Fresnel, transmission and kajs glint terms (Kajs
// eq. 4.16, 4.32, 4.19-4.20). The thesis multiplies L_i by a dimensionless
// weight f, t or g: a BRDF of value f sr^-1 with albedo up to pi f. Divided
// by pi they become the normalised lobes f/pi (albedo f: the Fresnel share
// that the diffuse loses as 1 - f), rho_n t/pi and g/pi (max(0, w_o.r_m) / pi
// integrates to 1 over w_o). The sky part of eq. 4.16, f L_sky^Omega, is
// already f/pi times E_sky and is unchanged.
float sun_lobe_scale(uint energy_consistent) { return energy_consistent != 0u ? INV_PI : 1.0; }

#endif  // GLINTLAB_SAND_ENERGY_GLSL
