#version 450
// Harness self-test: outputs[i] = inputs[i] * SCALE + float(i).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { float outputs[]; };
layout(push_constant) uniform Push { uint count; };
#ifndef SCALE
#define SCALE 1.0
#endif
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  outputs[i] = inputs[i] * SCALE + float(i);
}
