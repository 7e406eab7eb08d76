// 01-embed-glfw: a host application that owns its window and OpenGL context, draws its own scene
// (a map plane under the storm and a few opaque towers, with depth) and composites nephele's
// clouds into its frame through the plugin C API, loaded at run time with dlopen + nph_get_api —
// the way a broadcast graphics framework loads a renderer plugin (Nes 2008 §7.2).
//
//   embed_glfw DATASET [--plugin libnephele.so.0] [--size WxH] [--time T] [--exaggeration 6]
//              [--frames N --screenshot out.ppm]     (render N frames, save the last, quit)
//
// Interaction: drag with the left mouse button to orbit, scroll to zoom, [ and ] step the time,
// S moves the sun, Q toggles draft/broadcast quality, Escape quits.
//
// Per frame the host (1) draws its scene into its own framebuffer (colour + depth texture),
// (2) hands nephele the same view and projection matrices and the depth texture, so its towers
// cut the clouds where they stand in front of them, (3) calls render(), which ray casts and
// blends the premultiplied clouds over the bound framebuffer and puts back every piece of GL
// state it touched, and (4) blits the result to the window.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "nephele/nephele.h"

namespace {

struct Options {
  std::string dataset, plugin = "libnephele.so.0", screenshot;
  int width = 960, height = 540, frames = 0;
  double time = 0.0, exaggeration = 6.0;
};

const nph_api_v1* g_api = nullptr;

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "embed_glfw: %s\n", message.c_str());
  std::exit(1);
}

void check(nph_status s, const void* handle, const char* what) {
  if (s != NPH_OK) die(std::string(what) + ": " + g_api->status_name(s) + ": " + g_api->last_error(handle));
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : (die(a + " needs a value"), std::string()); };
    if (a == "--plugin") o.plugin = next();
    else if (a == "--size") {
      if (std::sscanf(next().c_str(), "%dx%d", &o.width, &o.height) != 2) die("--size WxH");
    } else if (a == "--time") o.time = std::atof(next().c_str());
    else if (a == "--exaggeration") o.exaggeration = std::atof(next().c_str());
    else if (a == "--frames") o.frames = std::atoi(next().c_str());
    else if (a == "--screenshot") o.screenshot = next();
    else if (!a.empty() && a[0] != '-' && o.dataset.empty()) o.dataset = a;
    else die("unknown argument " + a);
  }
  if (o.dataset.empty())
    die("usage: embed_glfw DATASET [--plugin PATH] [--size WxH] [--time T] [--exaggeration X] [--frames N --screenshot "
        "FILE.ppm]");
  return o;
}

// ---- the host's own scene: a shaded map plane and boxes, one program ---------------------------
const char* kVertex = R"(#version 450 core
layout(location = 0) in vec3 a_position_m;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_colour;
uniform mat4 u_clip_from_world;
out vec3 v_normal; out vec3 v_colour; out vec2 v_xy;
void main() {
  v_normal = a_normal; v_colour = a_colour; v_xy = a_position_m.xy;
  gl_Position = u_clip_from_world * vec4(a_position_m, 1.0);
})";
const char* kFragment = R"(#version 450 core
in vec3 v_normal; in vec3 v_colour; in vec2 v_xy;
uniform vec3 u_to_sun;
uniform float u_grid_m;
out vec4 o_colour;
void main() {
  vec2 cell = floor(v_xy / u_grid_m);
  float checker = mod(cell.x + cell.y, 2.0) * 0.08 + 0.92;  // a map grid, so motion reads
  float lambert = max(dot(normalize(v_normal), u_to_sun), 0.0);
  o_colour = vec4(v_colour * checker * (0.25 + 0.75 * lambert), 1.0);
})";

GLuint compile(GLenum type, const char* source) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    die(std::string("host shader: ") + log);
  }
  return s;
}

struct Vertex {
  glm::vec3 position, normal, colour;
};

void addQuad(std::vector<Vertex>& v, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 colour) {
  const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
  for (const glm::vec3& p : {a, b, c, a, c, d}) v.push_back({p, n, colour});
}

void addBox(std::vector<Vertex>& v, glm::vec3 lo, glm::vec3 hi, glm::vec3 colour) {
  const glm::vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                          {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  addQuad(v, p[4], p[5], p[6], p[7], colour);  // top
  addQuad(v, p[0], p[1], p[5], p[4], colour);  // south
  addQuad(v, p[1], p[2], p[6], p[5], colour);  // east
  addQuad(v, p[2], p[3], p[7], p[6], colour);  // north
  addQuad(v, p[3], p[0], p[4], p[7], colour);  // west
}

struct OrbitCamera {  // around the volume's centre, in nephele's world frame (z up)
  glm::dvec3 target{0.0};
  double azimuth_deg = 200.0, elevation_deg = 25.0, distance_m = 1.0;

  glm::dmat4 viewFromWorld() const {
    const double az = glm::radians(azimuth_deg), el = glm::radians(elevation_deg);
    const glm::dvec3 eye =
        target + distance_m * glm::dvec3(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
    return glm::lookAt(eye, target, glm::dvec3(0.0, 0.0, 1.0));
  }
};

bool g_dragging = false;
double g_last_x = 0.0, g_last_y = 0.0, g_scroll = 0.0;

void writePpm(const std::string& path, const std::vector<unsigned char>& rgba, int w, int h) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) die(path + ": cannot write");
  std::fprintf(f, "P6\n%d %d\n255\n", w, h);
  for (int y = h - 1; y >= 0; --y) {  // GL rows are bottom-first
    for (int x = 0; x < w; ++x) std::fwrite(&rgba[4 * (std::size_t(y) * std::size_t(w) + std::size_t(x))], 1, 3, f);
  }
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);

  // The plugin, loaded like any host loads its renderers.
  void* lib = dlopen(o.plugin.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (lib == nullptr) die(std::string("dlopen: ") + dlerror());
  auto get_api = reinterpret_cast<nph_get_api_fn>(dlsym(lib, "nph_get_api"));
  if (get_api == nullptr) die(o.plugin + " has no nph_get_api");
  g_api = static_cast<const nph_api_v1*>(get_api(NPH_API_VERSION));
  if (g_api == nullptr) die(o.plugin + " does not offer API version 1");

  if (!glfwInit()) die("glfwInit failed (no display?)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "nephele: clouds in a host scene", nullptr, nullptr);
  if (window == nullptr) die("no OpenGL 4.5 core window");
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
    if (button == GLFW_MOUSE_BUTTON_LEFT) g_dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &g_last_x, &g_last_y);
  });
  glfwSetScrollCallback(window, [](GLFWwindow*, double, double dy) { g_scroll += dy; });

  // ---- nephele in the host's context ----
  nph_dataset* ds = nullptr;
  nph_renderer* clouds = nullptr;
  int32_t timesteps = 0;
  check(g_api->dataset_open(o.dataset.c_str(), &ds), nullptr, "dataset_open");
  check(g_api->dataset_timestep_count(ds, &timesteps), ds, "dataset_timestep_count");
  nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
  desc.get_proc_address = reinterpret_cast<nph_get_proc_address_fn>(glfwGetProcAddress);
  desc.quality_preset = "draft";
  desc.time_index = o.time;
  desc.height_exaggeration = o.exaggeration;  // model domains are ~30x wider than tall
  check(g_api->renderer_create(ds, &desc, &clouds), ds, "renderer_create");
  double lo[3], hi[3];
  check(g_api->world_bounds(clouds, lo, hi), clouds, "world_bounds");
  const glm::dvec3 box_lo(lo[0], lo[1], lo[2]), box_hi(hi[0], hi[1], hi[2]);
  double sun_azimuth_deg = 135.0, time = o.time;
  const double sun_elevation_deg = 35.0;
  bool draft = true;
  check(g_api->set_sun(clouds, sun_azimuth_deg, sun_elevation_deg), clouds, "set_sun");
  // This host's framebuffer is display-referred 8-bit (its colours are sRGB values), so it asks
  // for display-referred clouds: tone-mapped, sRGB-encoded, premultiplied. A linear-light host
  // would keep the default (linear) and enable GL_FRAMEBUFFER_SRGB on an sRGB target instead.
  check(g_api->set_parameter(clouds, "display_transform", 1), clouds, "set_parameter");

  // ---- the host's scene: map plane (with a margin) and towers reaching into the clouds ----
  const glm::vec3 size = glm::vec3(box_hi - box_lo);
  const float margin = 0.15f * std::max(size.x, size.y);
  std::vector<Vertex> mesh;
  addQuad(mesh, {-margin, -margin, 0.0f}, {size.x + margin, -margin, 0.0f}, {size.x + margin, size.y + margin, 0.0f},
          {-margin, size.y + margin, 0.0f}, {0.22f, 0.42f, 0.25f});
  const float top_m = float(box_hi.z) * 0.9f, side = 0.04f * std::min(size.x, size.y);
  // Two in front of the storm (south of it: the camera looks from the south-south-west), one in
  // it, one beside it: the host depth must cut the clouds behind the first two.
  const glm::vec2 towers[] = {{0.25f, -0.07f}, {0.6f, -0.07f}, {0.5f, 0.5f}, {1.07f, 0.4f}};
  const glm::vec3 tower_colours[] = {{0.8f, 0.3f, 0.2f}, {0.9f, 0.8f, 0.3f}, {0.3f, 0.5f, 0.9f}, {0.8f, 0.8f, 0.8f}};
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 c(towers[i] * glm::vec2(size), 0.0f);
    addBox(mesh, c - glm::vec3(side, side, 0.0f), c + glm::vec3(side, side, top_m * (0.5f + 0.15f * float(i))),
           tower_colours[i]);
  }
  GLuint vbo = 0, vao = 0;
  glCreateBuffers(1, &vbo);
  glNamedBufferStorage(vbo, GLsizeiptr(mesh.size() * sizeof(Vertex)), mesh.data(), 0);
  glCreateVertexArrays(1, &vao);
  glVertexArrayVertexBuffer(vao, 0, vbo, 0, sizeof(Vertex));
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, GLuint(a * sizeof(glm::vec3)));
    glVertexArrayAttribBinding(vao, a, 0);
  }
  GLuint program = glCreateProgram();
  glAttachShader(program, compile(GL_VERTEX_SHADER, kVertex));
  glAttachShader(program, compile(GL_FRAGMENT_SHADER, kFragment));
  glLinkProgram(program);

  // The host's framebuffer: colour + a depth *texture* nephele can read.
  GLuint colour = 0, depth = 0, fbo = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &colour);
  glTextureStorage2D(colour, 1, GL_RGBA8, o.width, o.height);
  glCreateTextures(GL_TEXTURE_2D, 1, &depth);
  glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT32F, o.width, o.height);
  glCreateFramebuffers(1, &fbo);
  glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, colour, 0);
  glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depth, 0);
  check(g_api->set_host_depth(clouds, depth), clouds, "set_host_depth");

  OrbitCamera camera;
  camera.target = 0.5 * (box_lo + box_hi);
  camera.target.z = 0.0;
  camera.distance_m = 1.3 * double(std::max(size.x, size.y));
  const double near_m = 0.01 * camera.distance_m, far_m = 20.0 * camera.distance_m;

  for (int frame = 1; !glfwWindowShouldClose(window); ++frame) {
    glfwPollEvents();
    if (glfwGetKey(window, GLFW_KEY_ESCAPE) == GLFW_PRESS) glfwSetWindowShouldClose(window, GLFW_TRUE);
    if (g_dragging) {
      double x = 0.0, y = 0.0;
      glfwGetCursorPos(window, &x, &y);
      camera.azimuth_deg += 0.3 * (x - g_last_x);
      camera.elevation_deg = std::clamp(camera.elevation_deg + 0.3 * (y - g_last_y), 2.0, 89.0);
      g_last_x = x;
      g_last_y = y;
    }
    camera.distance_m *= std::pow(0.9, g_scroll);
    g_scroll = 0.0;
    auto pressed = [&](int key) {
      static bool down[512];
      bool now = glfwGetKey(window, key) == GLFW_PRESS, edge = now && !down[key];
      down[key] = now;
      return edge;
    };
    if (pressed(GLFW_KEY_RIGHT_BRACKET)) time = std::min(time + 0.25, double(timesteps - 1));
    if (pressed(GLFW_KEY_LEFT_BRACKET)) time = std::max(time - 0.25, 0.0);
    if (pressed(GLFW_KEY_S))
      check(g_api->set_sun(clouds, sun_azimuth_deg += 30.0, sun_elevation_deg), clouds, "set_sun");
    if (pressed(GLFW_KEY_Q))
      check(g_api->set_quality_preset(clouds, (draft = !draft) ? "draft" : "broadcast"), clouds, "quality");

    const glm::dmat4 view = camera.viewFromWorld();
    const glm::dmat4 proj = glm::perspective(glm::radians(40.0), double(o.width) / double(o.height), near_m, far_m);
    const glm::mat4 viewf(view), projf(proj);

    // (1) the host's scene, with depth
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, o.width, o.height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearColor(0.45f, 0.62f, 0.85f, 1.0f);  // sky
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "u_clip_from_world"), 1, GL_FALSE, glm::value_ptr(projf * viewf));
    const double az = glm::radians(sun_azimuth_deg), el = glm::radians(sun_elevation_deg);
    glUniform3f(glGetUniformLocation(program, "u_to_sun"), float(std::sin(az) * std::cos(el)),
                float(std::cos(az) * std::cos(el)), float(std::sin(el)));
    glUniform1f(glGetUniformLocation(program, "u_grid_m"), 0.1f * std::max(size.x, size.y));
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(mesh.size()));

    // (2)+(3) the clouds, cut by the host's depth, blended over its colour
    check(g_api->set_time(clouds, time), clouds, "set_time");
    check(g_api->set_camera(clouds, glm::value_ptr(viewf), glm::value_ptr(projf), o.width, o.height), clouds,
          "set_camera");
    check(g_api->render(clouds), clouds, "render");

    // (4) to the window
    glBlitNamedFramebuffer(fbo, 0, 0, 0, o.width, o.height, 0, 0, o.width, o.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    if (o.frames > 0 && frame == o.frames) {
      if (!o.screenshot.empty()) {
        std::vector<unsigned char> rgba(std::size_t(o.width) * std::size_t(o.height) * 4);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        writePpm(o.screenshot, rgba, o.width, o.height);
      }
      nph_stats st{};
      st.struct_size = sizeof st;
      check(g_api->get_stats(clouds, &st), clouds, "get_stats");
      std::printf("frame %d: DLM %s, ray cast %.1f ms, composite %.1f ms, render call %.1f ms\n", frame,
                  st.dlm_rebuilt ? "rebuilt" : "reused", st.raycast_ms, st.composite_ms, st.total_ms);
      glfwSetWindowShouldClose(window, GLFW_TRUE);
    }
    glfwSwapBuffers(window);
  }

  check(g_api->renderer_destroy(clouds), clouds, "renderer_destroy");  // context still current
  check(g_api->dataset_close(ds), ds, "dataset_close");
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}
