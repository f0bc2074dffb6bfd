#version 450
// A spatial upscale (core/render/upscale_pass.h): the output pixel's centre, mapped into the render
// image, interpolated bilinearly between the render texel centres around it (edges clamped).
layout(set = 0, binding = 0) uniform sampler2D src;
layout(location = 0) out vec4 out_color;
layout(push_constant) uniform Push {
  vec4 sizes;  // output width, height; render width, height
};

void main() {
  ivec2 n = ivec2(sizes.zw);
  vec2 q = (gl_FragCoord.xy) * (sizes.zw / sizes.xy) - 0.5;  // render texel coordinates, centres at integers
  vec2 i0 = floor(q), f = q - i0;
  ivec2 a = clamp(ivec2(i0), ivec2(0), n - 1), b = clamp(ivec2(i0) + 1, ivec2(0), n - 1);
  vec4 c00 = texelFetch(src, a, 0), c10 = texelFetch(src, ivec2(b.x, a.y), 0);
  vec4 c01 = texelFetch(src, ivec2(a.x, b.y), 0), c11 = texelFetch(src, b, 0);
  out_color = mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
}
