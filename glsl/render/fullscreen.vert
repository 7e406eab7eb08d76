#version 450 core
// A full-screen triangle (glsl/common/fullscreen.glsl): the viewer's present pass and the GL tests.
#include "common/fullscreen.glsl"
out vec2 v_uv;
void main() { gl_Position = fullscreenTriangle(gl_VertexID, v_uv); }
