#version 450
// Temporal accumulation of the eye pass's jitter for the interactive path (issue 19 item 4; Muth
// 2026 §3.4.9: the clouds are marched with a new jitter every frame and the frames accumulate;
// Karis 2014, "High quality temporal supersampling", for the reprojection and the neighbourhood
// clamp). render/raycast/temporal_accumulation.{h,cpp} drives it after each dispatch of
// clouds.comp with RenderSettings::temporal_history > 0.
//
// The frame is resolved as its two layers, each with its own history and its own depth: the
// premultiplied cloud layer, reprojected at the cloud's mean depth, and the background behind it
// (ground and sky), reprojected at the ground's distance (the sky at infinity); the frame is then
// recomposed, cloud + (1 − α)·background. One depth per pixel for the composite would move a
// half-transparent cloud edge with the ground behind it — the trails the first version of this
// pass left along every silhouette. Per layer and pixel:
//   n = min(n_prev + 1, N),   out = hist + (cur − hist) / n,
// so a still pixel becomes the running mean of its last N samples (the cloud layer exactly the
// mean samples_per_pixel gives while n < N), and a pixel whose history lies off screen starts
// afresh (n = 1). When the view moved, the history is taken from where the surface was (Catmull–
// Rom) and clamped into the range of the current layer's 3 × 3 neighbourhood, so a disoccluded
// pixel or a cloud seen anew cannot drag an old colour along (ghosting traded for a little noise).
// Two roles (u_role): 0 resolve into the new histories, 1 write the recomposed frame (alpha 1) and
// the cloud layer back into the renderer's images, the textures hosts and the viewer read.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = UNIT_TEMPORAL_CLOUD) uniform sampler2D u_cloud;            // this frame's premultiplied layer
layout(binding = UNIT_TEMPORAL_DEPTH) uniform sampler2D u_depth;            // its mean depth [m], 0 = no cloud
layout(binding = UNIT_TEMPORAL_BACKGROUND) uniform sampler2D u_background;  // (ground + sky, its depth [m]; 0 = far)
layout(binding = UNIT_TEMPORAL_HISTORY_BACKGROUND) uniform sampler2D u_history_background;  // (RGB, n), bilinear
layout(binding = UNIT_TEMPORAL_HISTORY_CLOUD) uniform sampler2D u_history_cloud;       // premultiplied RGBA
layout(binding = UNIT_TEMPORAL_HISTORY_COUNT) uniform sampler2D u_history_count;       // the cloud layer's n
layout(rgba32f, binding = IMAGE_TEMPORAL_BACKGROUND_OUT) uniform writeonly image2D u_background_out;
layout(rgba32f, binding = IMAGE_TEMPORAL_CLOUD_OUT) uniform writeonly image2D u_cloud_out;
layout(r32f, binding = IMAGE_TEMPORAL_COUNT_OUT) uniform writeonly image2D u_count_out;
layout(rgba32f, binding = IMAGE_FRAME) uniform writeonly image2D u_frame_target;        // role 1: the renderer's frame
layout(rgba32f, binding = IMAGE_CLOUD_LAYER) uniform writeonly image2D u_cloud_target;  // role 1: its cloud layer

uniform int u_role;
uniform ivec2 u_size;
uniform mat4 u_view_from_clip;        // this frame's inverse projection (RaycastBlock's)
uniform mat3 u_world_from_view;       // this frame's view axes in world
uniform vec3 u_cam_delta_m;           // this frame's eye − the previous frame's eye (world or ECEF, in double on the host)
uniform mat3 u_prev_view_from_world;  // the previous frame's rotation, world → view
uniform mat4 u_prev_clip_from_view;   // the previous frame's projection
uniform bool u_history_valid;         // false: the first frame after a reset (n = 1 everywhere)
uniform bool u_view_moved;            // false: the same view as the previous frame: no reprojection, no clamp
uniform float u_max_history;          // N

#include "render/pixel_ray.glsl"

// Where the surface this pixel shows lay in the previous frame, in pixels (row 0 at the top);
// (−1, −1) when behind the previous eye. The point relative to the previous eye is
// (eye − eye_prev) + d·t, t the motion depth; t = 0 (nothing hit: the sky) reprojects the
// direction alone (a point at infinity).
vec2 previousPixel(ivec2 px, float depth_m) {
  vec3 dir = pixelRay(vec2(px) + 0.5);
  vec4 relative = depth_m > 0.0 ? vec4(u_cam_delta_m + dir * depth_m, 1.0) : vec4(dir, 0.0);
  vec4 clip = u_prev_clip_from_view * vec4(u_prev_view_from_world * relative.xyz, relative.w);
  if (clip.w <= 0.0) return vec2(-1.0);
  vec2 ndc = clip.xy / clip.w;
  return vec2((ndc.x + 1.0) * 0.5 * float(u_size.x), (1.0 - ndc.y) * 0.5 * float(u_size.y));
}

// The history at a fractional position: the Catmull–Rom spline through the 4 × 4 texels around
// it, from 9 bilinear fetches (the middle two weights of each axis merged into one fetch; after
// Jimenez 2016, "Filmic SMAA", and Karis 2014). Bilinear resampling blurs the history anew every
// frame the view moves — over N frames a blur of ≈ √(N/8) pixels — where Catmull–Rom keeps it
// sharp; its overshoot is taken back by the neighbourhood clamp.
vec4 catmullRom(sampler2D history, vec2 at) {
  vec2 size = vec2(textureSize(history, 0));
  vec2 centre1 = floor(at - 0.5) + 0.5;  // the texel centre at or left of/above `at`
  vec2 f = at - centre1;
  vec2 w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
  vec2 w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
  vec2 w2 = f * (0.5 + f * (2.0 - 1.5 * f));
  vec2 w3 = f * f * (-0.5 + 0.5 * f);
  vec2 w12 = w1 + w2;
  vec2 c0 = (centre1 - 1.0) / size, c12 = (centre1 + w2 / w12) / size, c3 = (centre1 + 2.0) / size;
  vec4 r = vec4(0.0);
  r += textureLod(history, vec2(c0.x, c0.y), 0.0) * w0.x * w0.y;
  r += textureLod(history, vec2(c12.x, c0.y), 0.0) * w12.x * w0.y;
  r += textureLod(history, vec2(c3.x, c0.y), 0.0) * w3.x * w0.y;
  r += textureLod(history, vec2(c0.x, c12.y), 0.0) * w0.x * w12.y;
  r += textureLod(history, vec2(c12.x, c12.y), 0.0) * w12.x * w12.y;
  r += textureLod(history, vec2(c3.x, c12.y), 0.0) * w3.x * w12.y;
  r += textureLod(history, vec2(c0.x, c3.y), 0.0) * w0.x * w3.y;
  r += textureLod(history, vec2(c12.x, c3.y), 0.0) * w12.x * w3.y;
  r += textureLod(history, vec2(c3.x, c3.y), 0.0) * w3.x * w3.y;
  return r;
}

struct Layer {
  vec4 value;  // the resolved value
  float n;     // frames in its history
};

// One layer of one pixel: `current` this frame's value, `depth_m` where its surface lies along the
// ray, `n_previous` from the count the caller reads (`history`'s alpha or a count texture).
Layer resolveLayer(ivec2 px, vec4 current, float depth_m, sampler2D history, sampler2D current_layer,
                   sampler2D count, int count_channel, bool rgb_only) {
  Layer l;
  l.value = current;
  l.n = 1.0;
  if (!u_history_valid) return l;
  vec4 h;
  float n;
  if (!u_view_moved) {  // the same pixel: exact, no filtering
    h = texelFetch(history, px, 0);
    n = texelFetch(count, px, 0)[count_channel];
    if (rgb_only) h.a = current.a;
  } else {
    vec2 previous = previousPixel(px, depth_m);
    if (any(lessThan(previous, vec2(0.0))) || any(greaterThanEqual(previous, vec2(u_size)))) return l;
    h = catmullRom(history, previous);
    n = textureLod(count, previous / vec2(u_size), 0.0)[count_channel];
    // The neighbourhood clamp: the history into the range of this frame's 3 × 3 pixels.
    vec4 low = current, high = current;
    for (int j = -1; j <= 1; ++j) {
      for (int i = -1; i <= 1; ++i) {
        vec4 c = texelFetch(current_layer, clamp(px + ivec2(i, j), ivec2(0), u_size - 1), 0);
        if (rgb_only) c.a = current.a;
        low = min(low, c);
        high = max(high, c);
      }
    }
    if (rgb_only) h.a = current.a;
    vec4 clamped = clamp(h, low, high);
    // A history the clamp had to move by more than a tenth of the neighbourhood's range shows
    // another surface or another light (a disocclusion, a cloud seen from elsewhere): it counts
    // as one frame, so the current frame takes half the weight instead of 1/N and the old
    // picture fades within a few frames instead of N.
    vec4 moved = abs(clamped - h) / max(high - low, vec4(1e-6));
    if (max(max(moved.r, moved.g), max(moved.b, moved.a)) > 0.1) n = 1.0;
    h = clamped;
  }
  l.n = clamp(floor(n + 0.5) + 1.0, 1.0, u_max_history);
  l.value = h + (current - h) / l.n;
  return l;
}

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(px, u_size))) return;
  if (u_role == 1) {
    vec4 cloud = texelFetch(u_history_cloud, px, 0);
    vec3 background = texelFetch(u_history_background, px, 0).rgb;
    imageStore(u_frame_target, px, vec4(cloud.rgb + (1.0 - cloud.a) * background, 1.0));
    imageStore(u_cloud_target, px, cloud);
    return;
  }
  vec4 background = texelFetch(u_background, px, 0);
  vec4 cloud = texelFetch(u_cloud, px, 0);
  float cloudDepth = texelFetch(u_depth, px, 0).r;
  // The background's alpha is its depth: compare and blend its colour only (alpha 0 below).
  Layer b = resolveLayer(px, vec4(background.rgb, 0.0), background.a, u_history_background, u_background,
                         u_history_background, 3, true);
  // A pixel without cloud now reprojects with the background's depth: the clamp to its cloudless
  // neighbourhood then decides what of an old cloud may stay.
  Layer c = resolveLayer(px, cloud, cloudDepth > 0.0 ? cloudDepth : background.a, u_history_cloud, u_cloud,
                         u_history_count, 0, false);
  imageStore(u_background_out, px, vec4(b.value.rgb, b.n));
  imageStore(u_cloud_out, px, c.value);
  imageStore(u_count_out, px, vec4(c.n));
}
