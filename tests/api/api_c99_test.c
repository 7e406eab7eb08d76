/* The nephele C API from a C99 host (issue 7): every call, every misuse case (null, forged and
 * destroyed handles, wrong thread, wrong or no GL context, wrong order, bad arguments), the
 * effect of render (clouds over the host's framebuffer, host depth occluding them, stats of DLM
 * reuse) and, after dirtying the host's GL state everywhere, that no call changes any of it.
 *
 * usage: nephele_api_c99_test DATASET   (a wrfout / ICON / .nph file with >= 2 timesteps)
 * The host context is OSMesa (4.5 core, llvmpipe), GL functions are libOSMesa's exports. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>  // first: it includes GL/gl.h, which glext.h needs

#include <GL/glext.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_state_snapshot.h"
#include "nephele/nephele.h"

/* GL 4.5 entry points libOSMesa does not export: loaded through OSMesaGetProcAddress. */
/* Hand-aligned: clang-format reflows this X-macro differently on every run. */
// clang-format off
#define GL45_FUNCTIONS(X)                                                                        \
  X(PFNGLCLIPCONTROLPROC, glClipControl) X(PFNGLCREATEBUFFERSPROC, glCreateBuffers)              \
  X(PFNGLCREATEFRAMEBUFFERSPROC, glCreateFramebuffers) X(PFNGLCREATESAMPLERSPROC, glCreateSamplers) \
  X(PFNGLCREATETEXTURESPROC, glCreateTextures) X(PFNGLCREATEVERTEXARRAYSPROC, glCreateVertexArrays) \
  X(PFNGLNAMEDBUFFERDATAPROC, glNamedBufferData)                                                 \
  X(PFNGLNAMEDFRAMEBUFFERTEXTUREPROC, glNamedFramebufferTexture)                                 \
  X(PFNGLTEXTURESTORAGE2DPROC, glTextureStorage2D) X(PFNGLTEXTURESTORAGE3DPROC, glTextureStorage3D)   \
  X(PFNGLGETTEXTUREIMAGEPROC, glGetTextureImage) X(PFNGLGETOBJECTLABELPROC, glGetObjectLabel)
// clang-format on
#define DECLARE(type, name) static type p_##name;
GL45_FUNCTIONS(DECLARE)
#undef DECLARE
#define glClipControl p_glClipControl
#define glCreateBuffers p_glCreateBuffers
#define glCreateFramebuffers p_glCreateFramebuffers
#define glCreateSamplers p_glCreateSamplers
#define glCreateTextures p_glCreateTextures
#define glCreateVertexArrays p_glCreateVertexArrays
#define glNamedBufferData p_glNamedBufferData
#define glNamedFramebufferTexture p_glNamedFramebufferTexture
#define glTextureStorage2D p_glTextureStorage2D
#define glTextureStorage3D p_glTextureStorage3D
#define glGetTextureImage p_glGetTextureImage
#define glGetObjectLabel p_glGetObjectLabel

static void load_gl45(void) {
#define LOAD(type, name)                                                \
  p_##name = (type)OSMesaGetProcAddress(#name);                         \
  if (p_##name == NULL) {                                               \
    fprintf(stderr, "OSMesaGetProcAddress(%s) returned NULL\n", #name); \
    exit(2);                                                            \
  }
  GL45_FUNCTIONS(LOAD)
#undef LOAD
}

/* Live GL object names of each kind, probed by name (glIs*): a renderer that is destroyed must
 * leave the counts as they were before it was created (issue 18: one program was left alive). */
enum { LIVE_KINDS = 7, LIVE_NAME_RANGE = 16384 };
static const char* const live_kind_names[LIVE_KINDS] = {"program",     "shader",       "texture", "buffer",
                                                        "framebuffer", "vertex array", "sampler"};
static void count_live_objects(int counts[LIVE_KINDS]) {
  for (int k = 0; k < LIVE_KINDS; ++k) counts[k] = 0;
  for (GLuint n = 1; n <= LIVE_NAME_RANGE; ++n) {
    counts[0] += glIsProgram(n) == GL_TRUE;
    counts[1] += glIsShader(n) == GL_TRUE;
    counts[2] += glIsTexture(n) == GL_TRUE;
    counts[3] += glIsBuffer(n) == GL_TRUE;
    counts[4] += glIsFramebuffer(n) == GL_TRUE;
    counts[5] += glIsVertexArray(n) == GL_TRUE;
    counts[6] += glIsSampler(n) == GL_TRUE;
  }
}

/* Live programs that carry a label: nephele labels every program it links ("render/clouds.comp"),
 * the host's are unlabelled. Printed, and counted. */
static int count_labelled_programs(void) {
  int labelled = 0;
  for (GLuint n = 1; n <= LIVE_NAME_RANGE; ++n) {
    char label[256] = {0};
    GLsizei length = 0;
    if (glIsProgram(n) != GL_TRUE) continue;
    glGetObjectLabel(GL_PROGRAM, n, (GLsizei)sizeof label, &length, label);
    if (length > 0) {
      fprintf(stderr, "program %u (%s) is still alive\n", n, label);
      ++labelled;
    }
  }
  return labelled;
}

/* Counts the kinds whose live objects differ from `before`, naming them. */
static int compare_live_objects(const int before[LIVE_KINDS], const char* when) {
  int after[LIVE_KINDS], differ = 0;
  count_live_objects(after);
  printf("live GL objects %s:", when);
  for (int k = 0; k < LIVE_KINDS; ++k) printf(" %s %d/%d", live_kind_names[k], before[k], after[k]);
  printf("\n");
  for (int k = 0; k < LIVE_KINDS; ++k) {
    if (after[k] != before[k]) {
      fprintf(stderr, "%s: %d %s(s) before, %d after\n", when, before[k], live_kind_names[k], after[k]);
      ++differ;
    }
  }
  return differ;
}

#define W 96
#define H 64

static const nph_api_v1* api;
static const nph_api_v2* api2; /* version 2: the same calls, plus the compositing passes */
static int failures = 0;

#define CHECK(cond)                                                            \
  do {                                                                         \
    if (!(cond)) {                                                             \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                              \
    }                                                                          \
  } while (0)

/* `call` must return `want`; on a failure, the handle's (or thread's) last error is non-empty. */
#define EXPECT(want, handle, call) expect_status((want), (call), (const void*)(handle), #call, __LINE__)
static void expect_status(nph_status want, nph_status got, const void* handle, const char* text, int line) {
  const char* message = api->last_error(handle);
  if (got != want) {
    fprintf(stderr, "line %d: %s returned %s, expected %s (last error: %s)\n", line, text, api->status_name(got),
            api->status_name(want), message);
    ++failures;
  } else if (want != NPH_OK && (message == NULL || message[0] == '\0')) {
    fprintf(stderr, "line %d: %s failed as expected but left no message\n", line, text);
    ++failures;
  }
}

static nph_get_proc_address_fn osmesa_proc(void) { return (nph_get_proc_address_fn)OSMesaGetProcAddress; }

static OSMesaContext create_context(void) {
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         4,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         5,
                         0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
  if (ctx == NULL) {
    fprintf(stderr, "OSMesaCreateContextAttribs(4.5 core) failed\n");
    exit(2);
  }
  return ctx;
}

static unsigned char g_buffer[W * H * 4], g_other_buffer[W * H * 4];

/* ---- wrong thread ---------------------------------------------------------------------------- */
static void* other_thread(void* arg) {
  nph_renderer* r = (nph_renderer*)arg;
  static nph_status got[5];
  got[0] = api->set_time(r, 0.0);
  got[1] = api->render(r);
  got[2] = api->renderer_destroy(r);
  got[3] = api->set_parameter(r, "jitter", 0.0);
  /* datasets are any-thread: nothing to test here beyond not crashing */
  got[4] = api->get_stats(r, NULL);
  return got;
}

/* ---- host-side GL helpers --------------------------------------------------------------------- */
static GLuint make_texture(GLenum format, int w, int h) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &t);
  glTextureStorage2D(t, 1, format, w, h);
  return t;
}

static GLuint make_program(void) {
  const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }\n";
  const char* fs = "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";
  GLuint p = glCreateProgram();
  GLuint s[2] = {glCreateShader(GL_VERTEX_SHADER), glCreateShader(GL_FRAGMENT_SHADER)};
  glShaderSource(s[0], 1, &vs, NULL);
  glShaderSource(s[1], 1, &fs, NULL);
  for (int i = 0; i < 2; ++i) {
    glCompileShader(s[i]);
    glAttachShader(p, s[i]);
  }
  glLinkProgram(p);
  return p;
}

/* Counts pixels of the RGBA8 framebuffer `fb` (W x H) that differ from `rgba`. */
static int pixels_differing(GLuint fb, const unsigned char rgba[4]) {
  static unsigned char px[W * H * 4];
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
  glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, px);
  int n = 0;
  for (int i = 0; i < W * H; ++i) n += memcmp(px + 4 * i, rgba, 4) != 0;
  return n;
}

/* Everything a host might have set, none of it at its default value. */
static void dirty_host_state(GLuint program, GLuint fb) {
  GLuint vao, buffers[4], samplers[2], tex2d[4], tex3d, texarray;
  glCreateVertexArrays(1, &vao);
  glCreateBuffers(4, buffers);
  for (int i = 0; i < 4; ++i) glNamedBufferData(buffers[i], 1024, NULL, GL_DYNAMIC_DRAW);
  glCreateSamplers(2, samplers);
  for (int i = 0; i < 4; ++i) tex2d[i] = make_texture(GL_RGBA8, 4, 4);
  glCreateTextures(GL_TEXTURE_3D, 1, &tex3d);
  glTextureStorage3D(tex3d, 1, GL_R8, 4, 4, 4);
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &texarray);
  glTextureStorage3D(texarray, 1, GL_RGBA8, 4, 4, 2);
  glUseProgram(program);
  glBindVertexArray(vao);
  glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
  for (int u = 0; u < 8; ++u) {
    glActiveTexture((GLenum)(GL_TEXTURE0 + u));
    glBindTexture(GL_TEXTURE_2D, tex2d[u % 4]);
    if (u % 2 == 0) glBindTexture(GL_TEXTURE_3D, tex3d);
    if (u % 3 == 0) glBindTexture(GL_TEXTURE_2D_ARRAY, texarray);
    glBindSampler((GLuint)u, samplers[u % 2]);
  }
  glActiveTexture(GL_TEXTURE5);
  glBindImageTexture(0, tex2d[1], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA8);
  glBindImageTexture(1, texarray, 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA8);
  glBindImageTexture(2, tex3d, 0, GL_FALSE, 2, GL_WRITE_ONLY, GL_R8);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 3, buffers[1], 256, 512);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[2]);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[3]);
  glBindBufferBase(GL_UNIFORM_BUFFER, 1, buffers[3]);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, buffers[1]);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffers[2]);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffers[0]); /* the DLM's overflow retries bind one */
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, buffers[1]);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 8);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 7);
  glPixelStorei(GL_UNPACK_SKIP_ROWS, 1);
  glPixelStorei(GL_PACK_ALIGNMENT, 2);
  glPixelStorei(GL_PACK_ROW_LENGTH, 5);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 1);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fb);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glViewport(3, 2, W - 5, H - 4);
  glScissor(1, 1, W - 2, H - 2);
  glEnable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GEQUAL);
  glDepthMask(GL_FALSE);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT);
  glFrontFace(GL_CW);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_NOTEQUAL, 3, 0xff);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE, GL_DST_COLOR, GL_ZERO);
  glBlendEquationSeparate(GL_FUNC_SUBTRACT, GL_MAX);
  glBlendFunci(1, GL_ONE, GL_ONE);
  glBlendColor(0.1f, 0.2f, 0.3f, 0.4f);
  glColorMaski(0, GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
  glDisable(GL_DITHER);
  glEnable(GL_PRIMITIVE_RESTART);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glEnable(GL_DEPTH_CLAMP);
  glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
  glClearColor(0.5f, 0.25f, 0.125f, 1.0f);
  glLineWidth(1.0f);
  glProvokingVertex(GL_FIRST_VERTEX_CONVENTION);
  glEnable(GL_FRAMEBUFFER_SRGB);
  glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
}

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s DATASET\n", argv[0]);
    return 2;
  }
  const char* path = argv[1];

  /* ---- the table ---- */
  CHECK(nph_get_api(0) == NULL);
  CHECK(nph_get_api(NPH_API_VERSION + 1) == NULL);
  api = (const nph_api_v1*)nph_get_api(1);
  api2 = (const nph_api_v2*)nph_get_api(NPH_API_VERSION);
  if (api == NULL || api2 == NULL) {
    fprintf(stderr, "nph_get_api(1 or %u) returned NULL\n", NPH_API_VERSION);
    return 1;
  }
  CHECK(api->version == 1u && api->struct_size == sizeof(nph_api_v1));
  CHECK(api2->version == 2u && api2->struct_size == sizeof(nph_api_v2));
  /* version 2 begins with version 1: a host holding a v1 pointer to the v2 table calls the same code */
  CHECK(((const nph_api_v1*)api2)->render == api->render && api2->get_stats == api->get_stats);
  CHECK(strlen(api->library_version()) > 0);
  CHECK(strcmp(api->status_name(NPH_OK), "NPH_OK") == 0);
  CHECK(strcmp(api->status_name(NPH_ERROR_WRONG_THREAD), "NPH_ERROR_WRONG_THREAD") == 0);
  CHECK(strcmp(api->status_name(12345), "NPH_UNKNOWN_STATUS") == 0);
  CHECK(api->last_error(NULL) != NULL);

  /* ---- datasets ---- */
  nph_dataset* ds = NULL;
  int32_t count = 0;
  const char* when = NULL;
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, NULL, api->dataset_open(NULL, &ds));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, NULL, api->dataset_open(path, NULL));
  EXPECT(NPH_ERROR_INPUT, NULL, api->dataset_open("/nonexistent/storm.nph", &ds));
  CHECK(ds == NULL);
  CHECK(strstr(api->last_error(NULL), "/nonexistent/storm.nph") != NULL);
  EXPECT(NPH_OK, NULL, api->dataset_open(path, &ds));
  CHECK(ds != NULL);
  EXPECT(NPH_ERROR_INVALID_HANDLE, NULL, api->dataset_timestep_count(NULL, &count));
  EXPECT(NPH_ERROR_INVALID_HANDLE, NULL, api->dataset_timestep_count((const nph_dataset*)(uintptr_t)0x1234, &count));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->dataset_timestep_count(ds, NULL));
  EXPECT(NPH_OK, ds, api->dataset_timestep_count(ds, &count));
  CHECK(count >= 2);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->dataset_timestep_utc(ds, -1, &when));
  CHECK(strstr(api->last_error(ds), "out of range") != NULL);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->dataset_timestep_utc(ds, count, &when));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->dataset_timestep_utc(ds, 0, NULL));
  EXPECT(NPH_OK, ds, api->dataset_timestep_utc(ds, count - 1, &when));
  CHECK(when != NULL && strlen(when) >= 10);

  /* ---- renderer creation: arguments and context ---- */
  nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
  nph_renderer* r = NULL;
  desc.get_proc_address = osmesa_proc();
  EXPECT(NPH_ERROR_WRONG_CONTEXT, ds, api->renderer_create(ds, &desc, &r)); /* nothing current yet */
  OSMesaContext ctx = create_context(), other = create_context();
  if (!OSMesaMakeCurrent(ctx, g_buffer, GL_UNSIGNED_BYTE, W, H)) return 2;
  load_gl45();
  EXPECT(NPH_ERROR_INVALID_HANDLE, NULL, api->renderer_create(NULL, &desc, &r));
  EXPECT(NPH_ERROR_INVALID_HANDLE, NULL, api->renderer_create((nph_dataset*)(uintptr_t)0x4242, &desc, &r));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->renderer_create(ds, NULL, &r));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->renderer_create(ds, &desc, NULL));
  desc.struct_size = 4;
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->renderer_create(ds, &desc, &r));
  desc.struct_size = sizeof desc;
  desc.get_proc_address = NULL;
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->renderer_create(ds, &desc, &r));
  desc.get_proc_address = osmesa_proc();
  desc.quality_preset = "ultra";
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->renderer_create(ds, &desc, &r));
  desc.quality_preset = "draft";
  desc.height_exaggeration = 0.5;
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, ds, api->renderer_create(ds, &desc, &r));
  desc.height_exaggeration = 0.0;
  CHECK(r == NULL);
  EXPECT(NPH_OK, ds, api->renderer_create(ds, &desc, &r));
  CHECK(r != NULL);
  EXPECT(NPH_ERROR_INVALID_HANDLE, NULL, api->dataset_timestep_count((const nph_dataset*)r, &count));
  EXPECT(NPH_ERROR_INVALID_HANDLE, NULL, api->set_time((nph_renderer*)ds, 0.0));

  /* ---- wrong order ---- */
  nph_stats stats;
  memset(&stats, 0, sizeof stats);
  stats.struct_size = sizeof stats;
  float view[16], proj[16];
  EXPECT(NPH_ERROR_WRONG_ORDER, r, api->render(r));
  EXPECT(NPH_ERROR_WRONG_ORDER, r, api->get_stats(r, &stats));
  EXPECT(NPH_ERROR_WRONG_ORDER, r, api->get_camera(r, view, proj));

  /* ---- setters ---- */
  double lo[3], hi[3], value = 0.0;
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->world_bounds(r, NULL, hi));
  EXPECT(NPH_OK, r, api->world_bounds(r, lo, hi));
  CHECK(lo[0] == 0.0 && lo[1] == 0.0 && hi[0] > 1e4 && hi[1] > 1e4 && hi[2] > lo[2]);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_camera_preset(r, "fisheye", W, H));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_camera_preset(r, NULL, W, H));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_camera_preset(r, "overview", 0, H));
  EXPECT(NPH_OK, r, api->set_camera_preset(r, "overview", W, H));
  EXPECT(NPH_OK, r, api->get_camera(r, view, proj));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_camera(r, NULL, proj, W, H));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_camera(r, view, proj, W, -1));
  float bad[16];
  memcpy(bad, view, sizeof bad);
  bad[5] = NAN;
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_camera(r, bad, proj, W, H));
  memset(bad, 0, sizeof bad);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_camera(r, view, bad, W, H));
  EXPECT(NPH_OK, r, api->set_camera(r, view, proj, W, H));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_sun(r, 90.0, 120.0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_sun(r, INFINITY, 30.0));
  EXPECT(NPH_OK, r, api->set_sun(r, 120.0, 35.0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_quality_preset(r, "ultra"));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_quality_preset(r, NULL));
  EXPECT(NPH_OK, r, api->set_quality_preset(r, "draft"));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "no_such_knob", 1.0));
  CHECK(strstr(api->last_error(r), "dlm_resolution") != NULL); /* the message lists the known names */
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, NULL, 1.0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "dlm_resolution", 100.5));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "step_voxels", 0.0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "g_ice", NAN));
  EXPECT(NPH_OK, r, api->set_parameter(r, "dlm_resolution", 64));
  EXPECT(NPH_OK, r, api->get_parameter(r, "dlm_resolution", &value));
  CHECK(value == 64.0);
  EXPECT(NPH_OK, r, api->set_parameter(r, "exposure_ev", 0.5));
  EXPECT(NPH_OK, r, api->get_parameter(r, "exposure_ev", &value));
  CHECK(value == 0.5);
  EXPECT(NPH_OK, r, api->set_parameter(r, "exposure_ev", 0.0));
  EXPECT(NPH_OK, r, api->get_parameter(r, "time_interpolation", &value));
  CHECK(value == 1.0); /* motion-compensated by default, as scene files */
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "time_interpolation", 2));
  EXPECT(NPH_OK, r, api->set_parameter(r, "time_interpolation", 0));
  EXPECT(NPH_OK, r, api->get_parameter(r, "time_interpolation", &value));
  CHECK(value == 0.0);
  EXPECT(NPH_OK, r, api->set_parameter(r, "time_interpolation", 1));
  /* temporal accumulation for interactive hosts: off by default, kept across a preset change */
  EXPECT(NPH_OK, r, api->get_parameter(r, "temporal_history", &value));
  CHECK(value == 0.0);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "temporal_history", 65));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "temporal_history", 2.5));
  EXPECT(NPH_OK, r, api->set_parameter(r, "temporal_history", 4));
  EXPECT(NPH_OK, r, api->set_quality_preset(r, "draft"));
  EXPECT(NPH_OK, r, api->get_parameter(r, "temporal_history", &value));
  CHECK(value == 4.0);
  EXPECT(NPH_OK, r, api->set_quality_preset(r, "broadcast"));
  EXPECT(NPH_OK, r, api->set_parameter(r, "temporal_history", 0));
  /* the camera's white balance (scene/white_balance.h): 6504 K is neutral, 2500-25000 K accepted */
  EXPECT(NPH_OK, r, api->get_parameter(r, "white_balance_k", &value));
  CHECK(value == 6504.0);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "white_balance_k", 2000.0));
  CHECK(strstr(api->last_error(r), "white_balance_k") != NULL);
  EXPECT(NPH_OK, r, api->set_parameter(r, "white_balance_k", 8000.0));
  EXPECT(NPH_OK, r, api->get_parameter(r, "white_balance_k", &value));
  CHECK(value == 8000.0);
  EXPECT(NPH_OK, r, api->set_parameter(r, "white_balance_k", 6504.0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_parameter(r, "white_balance_duv", -0.05));
  EXPECT(NPH_OK, r, api->set_parameter(r, "white_balance_duv", -0.005));
  EXPECT(NPH_OK, r, api->get_parameter(r, "white_balance_duv", &value));
  CHECK(value == -0.005);
  EXPECT(NPH_OK, r, api->set_parameter(r, "white_balance_duv", 0.0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->get_parameter(r, "jitter", NULL));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->get_parameter(r, "nope", &value));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->set_time(r, NAN));
  EXPECT(NPH_OK, r, api->set_time(r, 0.0));

  /* ---- render into the default framebuffer: clouds over an opaque host colour ---- */
  const unsigned char blue[4] = {0, 0, 255, 255};
  glViewport(0, 0, W, H);
  glClearColor(0.0f, 0.0f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  EXPECT(NPH_OK, r, api->render(r));
  const int cloudy = pixels_differing(0, blue);
  printf("render: %d of %d pixels carry clouds\n", cloudy, W * H);
  CHECK(cloudy > W * H / 20);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->get_stats(r, NULL));
  stats.struct_size = 8;
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->get_stats(r, &stats));
  stats.struct_size = sizeof stats;
  EXPECT(NPH_OK, r, api->get_stats(r, &stats));
  CHECK(stats.frames == 1 && stats.dlm_rebuilt == 1 && stats.volume_changed == 1 && stats.dlm_builds == 1);
  printf("first frame: load %.1f ms, upload %.1f ms, DLM %.1f ms, ray cast %.1f ms, composite %.1f ms, total %.1f ms\n",
         stats.load_ms, stats.upload_ms, stats.dlm_ms, stats.raycast_ms, stats.composite_ms, stats.total_ms);
  EXPECT(NPH_OK, r, api->render(r)); /* nothing changed: the DLM is reused */
  EXPECT(NPH_OK, r, api->get_stats(r, &stats));
  CHECK(stats.frames == 2 && stats.dlm_rebuilt == 0 && stats.volume_changed == 0 && stats.dlm_reuses >= 1);
  EXPECT(NPH_OK, r, api->set_sun(r, 200.0, 40.0)); /* a sun change rebuilds the DLM only */
  EXPECT(NPH_OK, r, api->render(r));
  EXPECT(NPH_OK, r, api->get_stats(r, &stats));
  CHECK(stats.dlm_rebuilt == 1 && stats.volume_changed == 0);
  EXPECT(NPH_OK, r, api->set_time(r, 0.5)); /* a time change blends, uploads and rebuilds */
  EXPECT(NPH_OK, r, api->render(r));
  EXPECT(NPH_OK, r, api->get_stats(r, &stats));
  CHECK(stats.volume_changed == 1 && stats.dlm_rebuilt == 1 && stats.time_index == 0.5);

  /* ---- host depth: a depth buffer at the near plane hides every cloud ---- */
  GLuint depth = make_texture(GL_DEPTH_COMPONENT32F, W, H), small_depth = make_texture(GL_DEPTH_COMPONENT32F, W / 2, H);
  const float zero = 0.0f;
  glClearTexImage(depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, &zero);
  EXPECT(NPH_OK, r, api->set_host_depth(r, depth));
  glClear(GL_COLOR_BUFFER_BIT);
  EXPECT(NPH_OK, r, api->render(r));
  CHECK(pixels_differing(0, blue) == 0);
  EXPECT(NPH_OK, r, api->set_host_depth(r, small_depth));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->render(r));
  EXPECT(NPH_OK, r, api->set_host_depth(r, 987654));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->render(r));
  EXPECT(NPH_OK, r, api->set_host_depth(r, 0));

  /* ---- render into a host texture ---- */
  GLuint target = make_texture(GL_RGBA8, W, H), target_fb = 0;
  glCreateFramebuffers(1, &target_fb);
  glNamedFramebufferTexture(target_fb, GL_COLOR_ATTACHMENT0, target, 0);
  const unsigned char clear[4] = {0, 0, 0, 0};
  glClearTexImage(target, 0, GL_RGBA, GL_UNSIGNED_BYTE, clear);
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->render_to_texture(r, 0, 0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->render_to_texture(r, 424242, 0));
  EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api->render_to_texture(r, target, 3));
  EXPECT(NPH_OK, r, api->render_to_texture(r, target, 0));
  CHECK(pixels_differing(target_fb, clear) > W * H / 20);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);

  /* ---- compositing passes into host textures (version 2; docs/passes.md) ---- */
  {
    static float px[6][W * H * 4];
    const char* names[6] = {"beauty", "cloud", "ground", "sky", "shadow", "depth"};
    GLuint pass_tex = make_texture(GL_RGBA32F, W, H);
    EXPECT(NPH_ERROR_WRONG_ORDER, r, api2->pass_to_texture(r, "cloud", pass_tex, 0)); /* no passes yet */
    EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api2->set_passes(r, 7));
    EXPECT(NPH_OK, r, api2->set_passes(r, 1));
    EXPECT(NPH_OK, r, api2->render(r));
    EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api2->pass_to_texture(r, "albedo", pass_tex, 0));
    CHECK(strstr(api->last_error(r), "shadow") != NULL); /* the message lists the pass names */
    EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api2->pass_to_texture(r, NULL, pass_tex, 0));
    EXPECT(NPH_ERROR_INVALID_ARGUMENT, r, api2->pass_to_texture(r, "sky", 0, 0));
    for (int k = 0; k < 6; ++k) {
      EXPECT(NPH_OK, r, api2->pass_to_texture(r, names[k], pass_tex, 0));
      glGetTextureImage(pass_tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)sizeof(px[k]), px[k]);
    }
    /* beauty = cloud + (1 - cloud.a)(ground + sky), exactly up to float rounding; the matte in
     * [0, 1] with some shadow in view; Z finite under clouds, 1e10 m where there is none */
    double max_err = 0.0;
    int shadowed = 0, clouds = 0, bad_depth = 0;
    for (int i = 0; i < W * H; ++i) {
      const float a = px[1][4 * i + 3];
      for (int c = 0; c < 3; ++c) {
        const float rebuilt = px[1][4 * i + c] + (1.0f - a) * (px[2][4 * i + c] + px[3][4 * i + c]);
        const double err = fabs((double)rebuilt - (double)px[0][4 * i + c]) / (1e-3 + fabs((double)px[0][4 * i + c]));
        if (err > max_err) max_err = err;
      }
      if (px[4][4 * i] < 0.9f) ++shadowed;
      if (px[4][4 * i] < 0.0f || px[4][4 * i] > 1.0f || px[4][4 * i + 3] != 1.0f) ++bad_depth;
      if (a > 0.0f) {
        ++clouds;
        if (!(px[5][4 * i] > 0.0f && px[5][4 * i] < 1e9f)) ++bad_depth;
      } else if (px[5][4 * i] != 1e10f) {
        ++bad_depth;
      }
    }
    CHECK(max_err < 1e-5);
    CHECK(clouds > W * H / 20);
    CHECK(shadowed > 0);
    CHECK(bad_depth == 0);
    EXPECT(NPH_OK, r, api2->set_passes(r, 0));
    EXPECT(NPH_OK, r, api2->render(r));
    EXPECT(NPH_ERROR_WRONG_ORDER, r, api2->pass_to_texture(r, "cloud", pass_tex, 0));
    glDeleteTextures(1, &pass_tex);
  }

  /* ---- wrong thread ---- */
  pthread_t thread;
  void* result = NULL;
  CHECK(pthread_create(&thread, NULL, other_thread, r) == 0);
  CHECK(pthread_join(thread, &result) == 0);
  for (int i = 0; i < 5; ++i) {
    if (((nph_status*)result)[i] != NPH_ERROR_WRONG_THREAD) {
      fprintf(stderr, "other thread call %d: %s, expected NPH_ERROR_WRONG_THREAD\n", i,
              api->status_name(((nph_status*)result)[i]));
      ++failures;
    }
  }
  CHECK(strstr(api->last_error(r), "thread") != NULL);

  /* ---- wrong context, no context ---- */
  OSMesaMakeCurrent(other, g_other_buffer, GL_UNSIGNED_BYTE, W, H);
  EXPECT(NPH_ERROR_WRONG_CONTEXT, r, api->render(r));
  EXPECT(NPH_ERROR_WRONG_CONTEXT, r, api->renderer_destroy(r)); /* refused: the handle stays valid */
  OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
  EXPECT(NPH_ERROR_WRONG_CONTEXT, r, api->render(r));
  CHECK(strstr(api->last_error(r), "no GL context") != NULL);
  OSMesaMakeCurrent(ctx, g_buffer, GL_UNSIGNED_BYTE, W, H);
  EXPECT(NPH_OK, r, api->render(r));

  /* ---- every call leaves the host's GL state as it found it ---- */
  GLuint host_fb = 0, host_colour = make_texture(GL_RGBA8, W, H), program = make_program();
  glCreateFramebuffers(1, &host_fb);
  glNamedFramebufferTexture(host_fb, GL_COLOR_ATTACHMENT0, host_colour, 0);
  dirty_host_state(program, host_fb);
  gl_state_snapshot before, after;
  gl_state_take(&before);
  printf("GL state snapshot: %zu values, compared around each call below\n", before.count);
#define STATE_KEPT(want, handle, call)                    \
  do {                                                    \
    EXPECT(want, handle, call);                           \
    gl_state_take(&after);                                \
    failures += gl_state_compare(&before, &after, #call); \
  } while (0)
  nph_renderer* r2 = NULL;
  nph_dataset* ds2 = NULL;
  int live_before[LIVE_KINDS];
  count_live_objects(live_before);
  STATE_KEPT(NPH_OK, NULL, api->dataset_open(path, &ds2));
  STATE_KEPT(NPH_OK, ds2, api->renderer_create(ds2, &desc, &r2));
  STATE_KEPT(NPH_OK, ds2, api->dataset_close(ds2)); /* the renderer keeps its data */
  STATE_KEPT(NPH_OK, r2, api->set_camera_preset(r2, "oblique", W - 5, H - 4));
  STATE_KEPT(NPH_OK, r2, api->get_camera(r2, view, proj));
  STATE_KEPT(NPH_OK, r2, api->set_camera(r2, view, proj, W - 5, H - 4));
  STATE_KEPT(NPH_OK, r2, api->set_time(r2, 1.25));
  STATE_KEPT(NPH_OK, r2, api->set_sun(r2, 45.0, 60.0));
  STATE_KEPT(NPH_OK, r2, api->set_quality_preset(r2, "draft"));
  STATE_KEPT(NPH_OK, r2, api->set_parameter(r2, "dlm_resolution", 48));
  STATE_KEPT(NPH_OK, r2, api->get_parameter(r2, "dlm_resolution", &value));
  STATE_KEPT(NPH_OK, r2, api->world_bounds(r2, lo, hi));
  STATE_KEPT(NPH_OK, r2, api->render(r2));
  STATE_KEPT(NPH_OK, r2, api->get_stats(r2, &stats));
  STATE_KEPT(NPH_OK, r2, api->set_parameter(r2, "ground", 1));
  STATE_KEPT(NPH_OK, r2, api->set_parameter(r2, "display_transform", 1));
  STATE_KEPT(NPH_OK, r2, api->render(r2));
  STATE_KEPT(NPH_OK, r2, api->render_to_texture(r2, target, 0));
  STATE_KEPT(NPH_OK, r2, api2->set_passes(r2, 1));
  STATE_KEPT(NPH_OK, r2, api2->render_to_texture(r2, target, 0));
  STATE_KEPT(NPH_OK, r2, api2->pass_to_texture(r2, "shadow", target, 0));
  STATE_KEPT(NPH_ERROR_INVALID_ARGUMENT, r2, api2->pass_to_texture(r2, "nope", target, 0));
  GLuint depth2 = make_texture(GL_DEPTH_COMPONENT32F, W - 5, H - 4);
  gl_state_take(&before); /* make_texture created a name; bindings are unchanged */
  STATE_KEPT(NPH_OK, r2, api->set_host_depth(r2, depth2));
  STATE_KEPT(NPH_OK, r2, api->render(r2));
  STATE_KEPT(NPH_ERROR_INVALID_ARGUMENT, r2, api->render_to_texture(r2, 424242, 0));
  STATE_KEPT(NPH_OK, r, api->render(r)); /* a second renderer in the same context */
  STATE_KEPT(NPH_OK, r2, api->renderer_destroy(r2));
  STATE_KEPT(NPH_ERROR_INVALID_HANDLE, r2, api->render(r2));
  glDeleteTextures(1, &depth2); /* the host's own */
  failures += compare_live_objects(live_before, "before create / after destroy of a second renderer");

  /* ---- destroyed handles ---- */
  EXPECT(NPH_OK, r, api->renderer_destroy(r));
  EXPECT(NPH_ERROR_INVALID_HANDLE, r, api->renderer_destroy(r));
  EXPECT(NPH_ERROR_INVALID_HANDLE, r, api->render(r));
  EXPECT(NPH_ERROR_INVALID_HANDLE, r, api->set_time(r, 0.0));
  EXPECT(NPH_ERROR_INVALID_HANDLE, r, api->get_stats(r, &stats));
  CHECK(strstr(api->last_error(r), "not a live handle") != NULL); /* the thread's message */

  /* ---- the only renderer of a context leaves nothing behind (issue 18) ---- */
  count_live_objects(live_before);
  EXPECT(NPH_OK, ds, api->renderer_create(ds, &desc, &r));
  EXPECT(NPH_OK, r, api->set_camera_preset(r, "oblique", W, H));
  EXPECT(NPH_OK, r, api->set_parameter(r, "ground", 1));
  EXPECT(NPH_OK, r, api->render(r));
  EXPECT(NPH_OK, r, api2->set_passes(r, 1));
  EXPECT(NPH_OK, r, api->render(r));
  EXPECT(NPH_OK, r, api->renderer_destroy(r));
  failures += compare_live_objects(live_before, "before create / after destroy of the only renderer");
  CHECK(count_labelled_programs() == 0); /* Mesa kept the composite program referenced */

  /* a renderer whose context is already gone: destroy with no context current frees the rest */
  EXPECT(NPH_OK, ds, api->renderer_create(ds, &desc, &r));
  OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
  OSMesaDestroyContext(other);
  EXPECT(NPH_OK, r, api->renderer_destroy(r));

  EXPECT(NPH_OK, ds, api->dataset_close(ds));
  EXPECT(NPH_ERROR_INVALID_HANDLE, ds, api->dataset_close(ds));
  EXPECT(NPH_ERROR_INVALID_HANDLE, ds, api->dataset_timestep_count(ds, &count));
  OSMesaDestroyContext(ctx);

  if (failures != 0) {
    fprintf(stderr, "%d failure(s)\n", failures);
    return 1;
  }
  printf("all C API checks passed\n");
  return 0;
}
