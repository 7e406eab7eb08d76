// One triangle covering the viewport, from gl_VertexID alone (no vertex buffer): vertices
// 0, 1, 2 → p = (0, 0), (2, 0), (0, 2), clip position 2p − 1, so the visible square [−1, 1]²
// is the triangle's corner. uv = p is (0, 0) at the bottom-left of the viewport, (1, 1) at its
// top-right. Draw with glDrawArrays(GL_TRIANGLES, 0, 3) and an empty vertex array.
vec4 fullscreenTriangle(int vertexId, out vec2 uv) {
  vec2 p = vec2((vertexId << 1) & 2, vertexId & 2);
  uv = p;
  return vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
