/*
 * nephele/nephele.h — the nephele render-plugin C API (C99, C++ compatible).
 *
 * A broadcast graphics host that owns an OpenGL 4.5 core context loads libnephele (link it, or
 * dlopen("libnephele.so.0")), asks for a function table with nph_get_api(NPH_API_VERSION) and
 * renders volumetric clouds of a WRF/ICON dataset into its own framebuffer:
 *
 *   const nph_api_v1* api = (const nph_api_v1*)nph_get_api(NPH_API_VERSION);
 *   nph_dataset* ds;  api->dataset_open("storm.nph", &ds);
 *   nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
 *   desc.get_proc_address = (nph_get_proc_address_fn)glfwGetProcAddress;
 *   nph_renderer* r;  api->renderer_create(ds, &desc, &r);      (host context current)
 *   per frame: api->set_time(r, t); api->set_camera(r, view, proj, w, h); api->render(r);
 *   api->renderer_destroy(r); api->dataset_close(ds);
 *
 * Everything is documented in docs/plugin-api.md: every call, status code, threading rule, the
 * world frame and the versioning policy.
 *
 * ABI rules: handles are opaque; every call returns an nph_status (0 = NPH_OK) and never throws,
 * aborts or crashes on a null, destroyed or foreign handle; the message of the last failure is
 * kept per handle (last_error). Structs the caller fills carry struct_size first so they can grow.
 * Version 1 of the table is frozen: a new version is a new table type (nph_api_v2) returned for
 * nph_get_api(2), and nph_get_api(1) keeps returning this one.
 */
#ifndef NEPHELE_NEPHELE_H
#define NEPHELE_NEPHELE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The newest table version this header describes. nph_api_v2 begins with every member of
 * nph_api_v1 in the same order, so a host written for version 1 may keep its nph_api_v1 pointer. */
#define NPH_API_VERSION 2u

#if defined(__GNUC__)
#define NPH_EXPORT __attribute__((visibility("default")))
#else
#define NPH_EXPORT
#endif

/** Opaque handles. Never dereferenced by the library before it has checked them. */
typedef struct nph_dataset nph_dataset;
typedef struct nph_renderer nph_renderer;

/** Status codes: every call returns one. New codes may be added in later versions. */
typedef int32_t nph_status;
#define NPH_OK 0
#define NPH_ERROR_INVALID_HANDLE 1   /* null, destroyed, or a handle of another type */
#define NPH_ERROR_INVALID_ARGUMENT 2 /* null pointer, NaN, out of range, unknown name */
#define NPH_ERROR_WRONG_THREAD 3     /* a renderer call from a thread other than its own */
#define NPH_ERROR_WRONG_CONTEXT 4    /* no GL context current, or not the renderer's context */
#define NPH_ERROR_WRONG_ORDER 5      /* e.g. render before any camera was set */
#define NPH_ERROR_INPUT 6            /* a dataset that is missing, unreadable or malformed */
#define NPH_ERROR_GL 7               /* GL 4.5 core missing, shader or GL call failed */
#define NPH_ERROR_OUT_OF_MEMORY 8
#define NPH_ERROR_INTERNAL 9 /* a bug in nephele: please report with the message */

/** What the host's GetProcAddress returns (eglGetProcAddress, glfwGetProcAddress, ...). */
typedef void (*nph_gl_proc)(void);
typedef nph_gl_proc (*nph_get_proc_address_fn)(const char* name);

/** Renderer creation parameters. Initialise with NPH_RENDERER_DESC_INIT, then set fields. */
typedef struct nph_renderer_desc {
  uint32_t struct_size;                     /* sizeof(nph_renderer_desc) */
  nph_get_proc_address_fn get_proc_address; /* required: GL entry points of the host context */
  const char* quality_preset;               /* "draft" | "broadcast" | "reference"; NULL = broadcast */
  double time_index;                        /* initial fractional timestep index */
  double height_exaggeration;               /* vertical scale of the world frame; 0 = 1 (true scale) */
} nph_renderer_desc;
#define NPH_RENDERER_DESC_INIT \
  { sizeof(nph_renderer_desc), NULL, NULL, 0.0, 1.0 }

/** Per-frame and per-renderer figures (get_stats). Set struct_size before the call. */
typedef struct nph_stats {
  uint32_t struct_size;   /* sizeof(nph_stats) */
  int32_t volume_changed; /* 1: the last render uploaded a new (possibly blended) volume */
  int32_t dlm_rebuilt;    /* 1: the last render rebuilt the deep light map; 0: reused it */
  int32_t reserved;
  double time_index;   /* fractional timestep index of the last render */
  double load_ms;      /* decoding / blending timesteps (0 when cached) */
  double upload_ms;    /* volume upload */
  double dlm_ms;       /* deep light map build (0 when reused) */
  double raycast_ms;   /* ray cast submission */
  double composite_ms; /* the composite pass into the host framebuffer */
  double total_ms;     /* the whole render call, incl. state save and restore */
  uint64_t frames;     /* render calls that succeeded */
  uint64_t dlm_builds, dlm_reuses, volume_uploads;
} nph_stats;

/**
 * Version 1 of the function table. Functions on a renderer must be called from the thread that
 * created it; those marked [GL] also need the renderer's GL context current on that thread.
 */
typedef struct nph_api_v1 {
  uint32_t version;     /* 1 */
  uint32_t struct_size; /* sizeof(nph_api_v1) */

  /* "0.1.0" (the library's version; the table version is `version`). */
  const char* (*library_version)(void);
  /* "NPH_OK", "NPH_ERROR_INVALID_HANDLE", ...; "NPH_UNKNOWN_STATUS" for others. */
  const char* (*status_name)(nph_status status);
  /* The message of the last failed call on `handle` (a nph_dataset* or nph_renderer*), "" if
   * none. With NULL, or a handle that is not valid: the last failure on the calling thread of a
   * call that had no valid handle. Valid until the next call on that handle (or thread). */
  const char* (*last_error)(const void* handle);

  /* ---- datasets: no GL; any thread ---- */
  /* Opens a .nph extinction cache or a WRF wrfout / ICON NetCDF file. */
  nph_status (*dataset_open)(const char* path, nph_dataset** out);
  /* Closes the handle. Renderers created from it keep the data they need and stay usable. */
  nph_status (*dataset_close)(nph_dataset* dataset);
  nph_status (*dataset_timestep_count)(const nph_dataset* dataset, int32_t* count);
  /* ISO 8601 time of timestep `index`; the string lives as long as the dataset handle. */
  nph_status (*dataset_timestep_utc)(const nph_dataset* dataset, int32_t index, const char** time_utc);

  /* ---- renderers: one per host GL context, bound to the creating thread ---- */
  /* [GL] Creates GL resources in the current context and loads timestep desc->time_index. */
  nph_status (*renderer_create)(nph_dataset* dataset, const nph_renderer_desc* desc, nph_renderer** out);
  /* [GL] Deletes the GL resources. With no context current (the host destroyed it already) it
   * frees the rest and returns NPH_OK; with another context current: NPH_ERROR_WRONG_CONTEXT. */
  nph_status (*renderer_destroy)(nph_renderer* renderer);
  /* The volume's box in the world frame [m]: x east, y north from the grid's outer corner, z up
   * above mean sea level (times the height exaggeration). */
  nph_status (*world_bounds)(const nph_renderer* renderer, double min_m[3], double max_m[3]);

  /* Fractional timestep index in [0, count-1] (clamped): a blend of the two neighbours, carried
   * along their winds where both have U, V (parameter time_interpolation: 1, the default), or a
   * cross-fade (0). */
  nph_status (*set_time)(nph_renderer* renderer, double time_index);
  /* The host's camera: column-major 4x4 matrices as glUniformMatrix4fv takes them (world -> eye,
   * rigid; eye -> clip, OpenGL perspective) and the size of the image rendered (usually the
   * viewport; the cloud layer is ray cast at this size and stretched over the viewport). */
  nph_status (*set_camera)(nph_renderer* renderer, const float view_from_world[16], const float clip_from_view[16],
                           int32_t width, int32_t height);
  /* A camera framing the volume: "overview" | "oblique" | "top" (as in scene files). */
  nph_status (*set_camera_preset)(nph_renderer* renderer, const char* preset, int32_t width, int32_t height);
  /* The current camera's matrices (column-major), e.g. to draw host geometry under a preset. */
  nph_status (*get_camera)(const nph_renderer* renderer, float view_from_world[16], float clip_from_view[16]);
  /* Sun direction in the world frame: azimuth clockwise from grid north, elevation above the
   * horizon [deg]. Changing it rebuilds the deep light map at the next render. */
  nph_status (*set_sun)(nph_renderer* renderer, double azimuth_deg, double elevation_deg);
  /* "draft" | "broadcast" | "reference": resets every quality parameter to the preset. */
  nph_status (*set_quality_preset)(nph_renderer* renderer, const char* preset);
  /* One named parameter (docs/plugin-api.md has the list, ranges and defaults). */
  nph_status (*set_parameter)(nph_renderer* renderer, const char* name, double value);
  nph_status (*get_parameter)(const nph_renderer* renderer, const char* name, double* value);
  /* A host depth texture (GL_DEPTH_COMPONENT* or R32F, camera size, window depth in [0, 1] of the
   * same projection) that stops rays at host geometry; 0 = none. Read during render only. */
  nph_status (*set_host_depth)(nph_renderer* renderer, uint32_t gl_texture);

  /* [GL] Brings volume and light up to date, ray casts and composites the clouds into the
   * currently bound draw framebuffer over the current viewport (premultiplied alpha "over",
   * scissor and sRGB conversion as the host set them). Restores all GL state it touches. */
  nph_status (*render)(nph_renderer* renderer);
  /* [GL] The same into level `level` of a host GL_TEXTURE_2D (RGBA8, RGBA16F, RGBA32F, ...),
   * composited over its content across the whole level. */
  nph_status (*render_to_texture)(nph_renderer* renderer, uint32_t gl_texture, int32_t level);
  /* Figures of the last render. NPH_ERROR_WRONG_ORDER before the first. */
  nph_status (*get_stats)(const nph_renderer* renderer, nph_stats* stats);
} nph_api_v1;

/**
 * Version 2 (issue 15): version 1's members unchanged and in the same order, then the compositing
 * passes (docs/passes.md) as extra host textures. nph_get_api(2) returns it; nph_get_api(1) keeps
 * returning the version-1 table.
 */
typedef struct nph_api_v2 {
  uint32_t version;     /* 2 */
  uint32_t struct_size; /* sizeof(nph_api_v2) */
  const char* (*library_version)(void);
  const char* (*status_name)(nph_status status);
  const char* (*last_error)(const void* handle);
  nph_status (*dataset_open)(const char* path, nph_dataset** out);
  nph_status (*dataset_close)(nph_dataset* dataset);
  nph_status (*dataset_timestep_count)(const nph_dataset* dataset, int32_t* count);
  nph_status (*dataset_timestep_utc)(const nph_dataset* dataset, int32_t index, const char** time_utc);
  nph_status (*renderer_create)(nph_dataset* dataset, const nph_renderer_desc* desc, nph_renderer** out);
  nph_status (*renderer_destroy)(nph_renderer* renderer);
  nph_status (*world_bounds)(const nph_renderer* renderer, double min_m[3], double max_m[3]);
  nph_status (*set_time)(nph_renderer* renderer, double time_index);
  nph_status (*set_camera)(nph_renderer* renderer, const float view_from_world[16], const float clip_from_view[16],
                           int32_t width, int32_t height);
  nph_status (*set_camera_preset)(nph_renderer* renderer, const char* preset, int32_t width, int32_t height);
  nph_status (*get_camera)(const nph_renderer* renderer, float view_from_world[16], float clip_from_view[16]);
  nph_status (*set_sun)(nph_renderer* renderer, double azimuth_deg, double elevation_deg);
  nph_status (*set_quality_preset)(nph_renderer* renderer, const char* preset);
  nph_status (*set_parameter)(nph_renderer* renderer, const char* name, double value);
  nph_status (*get_parameter)(const nph_renderer* renderer, const char* name, double* value);
  nph_status (*set_host_depth)(nph_renderer* renderer, uint32_t gl_texture);
  nph_status (*render)(nph_renderer* renderer);
  nph_status (*render_to_texture)(nph_renderer* renderer, uint32_t gl_texture, int32_t level);
  nph_status (*get_stats)(const nph_renderer* renderer, nph_stats* stats);

  /* ---- version 2: compositing passes ---- */
  /* Whether the next renders also produce the compositing passes (off by default: they cost two
   * image stores per pixel and two RGBA32F textures of the camera's size). */
  nph_status (*set_passes)(nph_renderer* renderer, int32_t enabled);
  /* [GL] Copies one pass of the last render into level `level` of a host GL_TEXTURE_2D (use
   * RGBA16F or RGBA32F: the values are linear and "depth" is in metres), replacing its content,
   * stretched over the level as render_to_texture does. `pass`: "beauty" (the clouds over
   * nephele's own ground), "cloud" (premultiplied RGBA), "ground", "sky" (RGB, alpha 1),
   * "shadow" (the cloud-shadow matte m in RGB, 1 = no shadow, alpha 1), "depth" (Z in RGB, alpha
   * 1). Radiance passes carry the renderer's exposure (parameter exposure_ev); shadow and depth
   * do not. NPH_ERROR_WRONG_ORDER when the last render had no passes. Restores the GL state. */
  nph_status (*pass_to_texture)(nph_renderer* renderer, const char* pass, uint32_t gl_texture, int32_t level);
} nph_api_v2;

/**
 * The only exported symbol. Returns the function table of `version` (cast it to nph_api_v<N>*),
 * or NULL if this library does not have that version (it is older than the header).
 */
NPH_EXPORT const void* nph_get_api(uint32_t version);
typedef const void* (*nph_get_api_fn)(uint32_t version);

#ifdef __cplusplus
}
#endif

#endif /* NEPHELE_NEPHELE_H */
