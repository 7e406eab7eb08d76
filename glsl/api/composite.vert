#version 450 core
// Plugin API composite pass: one triangle covering the host's viewport (no vertex buffer).
// v_uv is (0, 0) at the viewport's bottom-left and (1, 1) at its top-right.
#include "common/fullscreen.glsl"
out vec2 v_uv;
void main() { gl_Position = fullscreenTriangle(gl_VertexID, v_uv); }
