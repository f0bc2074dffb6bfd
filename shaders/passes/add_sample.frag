#version 450
// A surface pass's summed samples (core/render/surface_pass.h): writes one
// opaque sample's pixel, which the pipeline's blending adds to the colour
// target (or, for the first sample, writes).
layout(set = 0, binding = 0) uniform sampler2D sample_image;
layout(location = 0) out vec4 out_color;

void main() { out_color = texelFetch(sample_image, ivec2(gl_FragCoord.xy), 0); }
