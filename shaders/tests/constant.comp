#version 450
// Evaluates one compile-time constant of the shader tree: outputs[0] =
// float(CONSTANT), e.g. CONSTANT=SAND_GLINT_KAJS. Lets tests check that C++
// tables and GLSL constants agree (an undefined name fails to compile).
#include "sand/sand_params.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };
void main() {
  if (gl_GlobalInvocationID.x == 0u) outputs[0] = float(CONSTANT);
}
