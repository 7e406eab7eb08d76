/* See gl_state_snapshot.h. GL functions come from libOSMesa's exported symbols. */
#define GL_GLEXT_PROTOTYPES 1
#include "gl_state_snapshot.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>

#define UNITS 32 /* texture and sampler units checked: as many as the plugin saves (32) */
#define IMAGE_UNITS 8
#define SSBO_BINDINGS 12

typedef struct query {
  const char* name;
  GLenum pname;
  int count; /* values returned by glGetIntegerv */
} query;

#define Q(p, n) \
  { #p, p, n }
static const query kPlain[] = {
    Q(GL_CURRENT_PROGRAM, 1),
    Q(GL_VERTEX_ARRAY_BINDING, 1),
    Q(GL_ACTIVE_TEXTURE, 1),
    Q(GL_ARRAY_BUFFER_BINDING, 1),
    Q(GL_ELEMENT_ARRAY_BUFFER_BINDING, 1),
    Q(GL_SHADER_STORAGE_BUFFER_BINDING, 1),
    Q(GL_UNIFORM_BUFFER_BINDING, 1),
    Q(GL_PIXEL_PACK_BUFFER_BINDING, 1),
    Q(GL_PIXEL_UNPACK_BUFFER_BINDING, 1),
    Q(GL_DISPATCH_INDIRECT_BUFFER_BINDING, 1),
    Q(GL_DRAW_FRAMEBUFFER_BINDING, 1),
    Q(GL_READ_FRAMEBUFFER_BINDING, 1),
    Q(GL_RENDERBUFFER_BINDING, 1),
    Q(GL_VIEWPORT, 4),
    Q(GL_SCISSOR_BOX, 4),
    Q(GL_DEPTH_FUNC, 1),
    Q(GL_DEPTH_WRITEMASK, 1),
    Q(GL_CULL_FACE_MODE, 1),
    Q(GL_FRONT_FACE, 1),
    Q(GL_POLYGON_MODE, 2),
    Q(GL_CLIP_ORIGIN, 1),
    Q(GL_CLIP_DEPTH_MODE, 1),
    Q(GL_BLEND_COLOR, 4),
    Q(GL_STENCIL_FUNC, 1),
    Q(GL_STENCIL_REF, 1),
    Q(GL_STENCIL_WRITEMASK, 1),
    Q(GL_PACK_ALIGNMENT, 1),
    Q(GL_PACK_ROW_LENGTH, 1),
    Q(GL_PACK_SKIP_ROWS, 1),
    Q(GL_PACK_SKIP_PIXELS, 1),
    Q(GL_PACK_IMAGE_HEIGHT, 1),
    Q(GL_PACK_SKIP_IMAGES, 1),
    Q(GL_PACK_SWAP_BYTES, 1),
    Q(GL_UNPACK_ALIGNMENT, 1),
    Q(GL_UNPACK_ROW_LENGTH, 1),
    Q(GL_UNPACK_SKIP_ROWS, 1),
    Q(GL_UNPACK_SKIP_PIXELS, 1),
    Q(GL_UNPACK_IMAGE_HEIGHT, 1),
    Q(GL_UNPACK_SKIP_IMAGES, 1),
    Q(GL_UNPACK_SWAP_BYTES, 1),
    Q(GL_DRAW_BUFFER, 1),
    Q(GL_READ_BUFFER, 1),
    Q(GL_COLOR_CLEAR_VALUE, 4),
    Q(GL_DEPTH_CLEAR_VALUE, 1),
    Q(GL_LINE_WIDTH, 1),
    Q(GL_PROVOKING_VERTEX, 1),
    Q(GL_PATCH_VERTICES, 1),
};

static const query kEnables[] = {
    Q(GL_DEPTH_TEST, 1),
    Q(GL_STENCIL_TEST, 1),
    Q(GL_CULL_FACE, 1),
    Q(GL_SCISSOR_TEST, 1),
    Q(GL_DITHER, 1),
    Q(GL_RASTERIZER_DISCARD, 1),
    Q(GL_SAMPLE_ALPHA_TO_COVERAGE, 1),
    Q(GL_SAMPLE_COVERAGE, 1),
    Q(GL_COLOR_LOGIC_OP, 1),
    Q(GL_PRIMITIVE_RESTART, 1),
    Q(GL_FRAMEBUFFER_SRGB, 1),
    Q(GL_MULTISAMPLE, 1),
    Q(GL_POLYGON_OFFSET_FILL, 1),
    Q(GL_PROGRAM_POINT_SIZE, 1),
    Q(GL_DEPTH_CLAMP, 1),
    Q(GL_TEXTURE_CUBE_MAP_SEAMLESS, 1),
    Q(GL_CLIP_DISTANCE0, 1),
    Q(GL_DEBUG_OUTPUT, 1),
    Q(GL_DEBUG_OUTPUT_SYNCHRONOUS, 1),
};

/* Indexed (glGetIntegeri_v / glIsEnabledi) per draw buffer 0..3. */
static const query kPerDrawBuffer[] = {
    Q(GL_BLEND_SRC_RGB, 1),   Q(GL_BLEND_DST_RGB, 1),      Q(GL_BLEND_SRC_ALPHA, 1),
    Q(GL_BLEND_DST_ALPHA, 1), Q(GL_BLEND_EQUATION_RGB, 1), Q(GL_BLEND_EQUATION_ALPHA, 1),
};

static const query kPerUnit[] = {
    /* on the active texture unit */
    Q(GL_TEXTURE_BINDING_1D, 1),
    Q(GL_TEXTURE_BINDING_2D, 1),
    Q(GL_TEXTURE_BINDING_3D, 1),
    Q(GL_TEXTURE_BINDING_1D_ARRAY, 1),
    Q(GL_TEXTURE_BINDING_2D_ARRAY, 1),
    Q(GL_TEXTURE_BINDING_RECTANGLE, 1),
    Q(GL_TEXTURE_BINDING_CUBE_MAP, 1),
    Q(GL_TEXTURE_BINDING_CUBE_MAP_ARRAY, 1),
    Q(GL_TEXTURE_BINDING_BUFFER, 1),
    Q(GL_TEXTURE_BINDING_2D_MULTISAMPLE, 1),
    Q(GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY, 1),
};

static const query kPerImageUnit[] = {
    Q(GL_IMAGE_BINDING_NAME, 1),  Q(GL_IMAGE_BINDING_LEVEL, 1),  Q(GL_IMAGE_BINDING_LAYERED, 1),
    Q(GL_IMAGE_BINDING_LAYER, 1), Q(GL_IMAGE_BINDING_ACCESS, 1), Q(GL_IMAGE_BINDING_FORMAT, 1),
};
#undef Q

static void push(gl_state_snapshot* s, const char* name, int index, int64_t v) {
  if (s->count >= GL_STATE_MAX_VALUES) return;
  s->names[s->count] = name;
  s->indices[s->count] = index;
  s->values[s->count++] = v;
}

static void plain(gl_state_snapshot* s, const query* q, int index) {
  GLint v[4] = {0, 0, 0, 0};
  glGetIntegerv(q->pname, v);
  for (int i = 0; i < q->count; ++i) push(s, q->name, index, v[i]);
}

void gl_state_take(gl_state_snapshot* s) {
  s->count = 0;
  for (size_t i = 0; i < sizeof kPlain / sizeof kPlain[0]; ++i) plain(s, &kPlain[i], -1);
  for (size_t i = 0; i < sizeof kEnables / sizeof kEnables[0]; ++i)
    push(s, kEnables[i].name, -1, glIsEnabled(kEnables[i].pname));
  GLboolean mask[4];
  glGetBooleanv(GL_DEPTH_WRITEMASK, mask);
  push(s, "GL_DEPTH_WRITEMASK (boolean)", -1, mask[0]);
  for (int b = 0; b < 4; ++b) {
    push(s, "GL_BLEND (indexed)", b, glIsEnabledi(GL_BLEND, (GLuint)b));
    glGetBooleani_v(GL_COLOR_WRITEMASK, (GLuint)b, mask);
    for (int c = 0; c < 4; ++c) push(s, "GL_COLOR_WRITEMASK", b, mask[c]);
    for (size_t i = 0; i < sizeof kPerDrawBuffer / sizeof kPerDrawBuffer[0]; ++i) {
      GLint v = 0;
      glGetIntegeri_v(kPerDrawBuffer[i].pname, (GLuint)b, &v);
      push(s, kPerDrawBuffer[i].name, b, v);
    }
  }
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  for (int u = 0; u < UNITS; ++u) {
    glActiveTexture((GLenum)(GL_TEXTURE0 + u));
    for (size_t i = 0; i < sizeof kPerUnit / sizeof kPerUnit[0]; ++i) plain(s, &kPerUnit[i], u);
    GLint sampler = 0;
    glGetIntegeri_v(GL_SAMPLER_BINDING, (GLuint)u, &sampler);
    push(s, "GL_SAMPLER_BINDING", u, sampler);
  }
  glActiveTexture((GLenum)active);
  for (int u = 0; u < IMAGE_UNITS; ++u) {
    for (size_t i = 0; i < sizeof kPerImageUnit / sizeof kPerImageUnit[0]; ++i) {
      GLint v = 0;
      glGetIntegeri_v(kPerImageUnit[i].pname, (GLuint)u, &v);
      push(s, kPerImageUnit[i].name, u, v);
    }
  }
  for (int b = 0; b < SSBO_BINDINGS; ++b) {
    GLint name = 0;
    GLint64 start = 0, size = 0;
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, (GLuint)b, &name);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, (GLuint)b, &start);
    glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, (GLuint)b, &size);
    push(s, "GL_SHADER_STORAGE_BUFFER_BINDING (indexed)", b, name);
    push(s, "GL_SHADER_STORAGE_BUFFER_START", b, start);
    push(s, "GL_SHADER_STORAGE_BUFFER_SIZE", b, size);
    glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, (GLuint)b, &name);
    push(s, "GL_UNIFORM_BUFFER_BINDING (indexed)", b, name);
  }
  push(s, "glGetError", -1, (int64_t)glGetError());
}

int gl_state_compare(const gl_state_snapshot* a, const gl_state_snapshot* b, const char* what) {
  int diffs = 0;
  if (a->count != b->count) {
    fprintf(stderr, "GL state after %s: %zu values, before %zu\n", what, b->count, a->count);
    return 1;
  }
  for (size_t i = 0; i < a->count; ++i) {
    if (a->values[i] != b->values[i]) {
      fprintf(stderr, "GL state changed by %s: %s[%d] was %lld (0x%llx), now %lld (0x%llx)\n", what, a->names[i],
              a->indices[i], (long long)a->values[i], (long long)a->values[i], (long long)b->values[i],
              (long long)b->values[i]);
      ++diffs;
    }
  }
  return diffs;
}
