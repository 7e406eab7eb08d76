#version 450 core
// Plugin API composite pass: one triangle covering the host's viewport (no vertex buffer).
// v_uv is (0, 0) at the viewport's bottom-left and (1, 1) at its top-right.
out vec2 v_uv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  v_uv = p;
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
