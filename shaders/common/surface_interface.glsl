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
#if SURFACE_MOTION  // common/motion.glsl's surface_motion() of the point
layout(location = 5) in vec3 v_pix;             // homogeneous pixel position, this frame
layout(location = 6) in vec3 v_prev_pix;        // the same point's in the previous frame
layout(location = 7) in vec3 v_eye_offset;      // world position - eye, this frame
layout(location = 8) in vec3 v_prev_eye_offset; // the same in the previous frame
#endif

#endif
