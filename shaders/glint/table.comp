#version 450
// A glint model's data table (glint/query.glsl, "glint_table size=N"):
// entry i = glint_table_entry(i) of the model's file, for i < count. The
// model's defines build the file in as a render does (core::glint_table).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Inputs { float inputs[]; };  // unused
layout(push_constant) uniform Push { uint count; };

#define GLINT_TABLE_BINDING 1
#define GLINT_TABLE_ACCESS
#include "sand/glint_models.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < count) glint_table[i] = glint_table_entry(i);
}
