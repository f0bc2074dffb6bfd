#version 450
// One triangle covering the screen at the far plane (depth 1); the fragment
// stage gets NDC xy.
layout(location = 0) out vec2 v_ndc;

void main() {
  vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  v_ndc = p * 2.0 - 1.0;
  gl_Position = vec4(v_ndc, 1.0, 1.0);
}
