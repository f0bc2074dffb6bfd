// The varyings from passes/surface.vert, declared once for every surface
// fragment shader (a fragment shader must declare all of them, used or not,
// so the interfaces match exactly).
#ifndef GLINTLAB_SURFACE_INTERFACE_GLSL
#define GLINTLAB_SURFACE_INTERFACE_GLSL

layout(location = 0) in vec3 v_x_obj;   // object-space position (seeds procedural detail)
layout(location = 1) in vec3 v_x;       // world position, this frame
layout(location = 2) in vec3 v_n;       // world macro normal (not normalised)
layout(location = 3) in vec4 v_t;       // world tangent, w = bitangent sign
layout(location = 4) in vec2 v_uv;      // surface uv
layout(location = 5) in vec3 v_prev_x;  // world position of the same surface point in the previous frame

#endif
