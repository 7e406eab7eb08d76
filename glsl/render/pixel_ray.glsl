// The eye ray through a pixel position (pixel units, row 0 at the top; centres at i + ½): the same
// ray as scene::Camera::rayDirection. One definition for the eye pass (clouds.comp) and the
// temporal accumulation's reprojection (temporal.comp), which must agree on it to the bit.
// The including shader declares u_size (the image size), u_view_from_clip (the inverse
// projection) and u_world_from_view (the view's axes in world), as render/raycast/cloud_renderer.h
// ViewRays fills them.
vec3 pixelRay(vec2 pixel) {
  vec2 ndc = vec2(2.0 * pixel.x / float(u_size.x) - 1.0, 1.0 - 2.0 * pixel.y / float(u_size.y));
  vec4 viewPoint = u_view_from_clip * vec4(ndc, 0.0, 1.0);
  return normalize(u_world_from_view * normalize(viewPoint.xyz / viewPoint.w));
}
