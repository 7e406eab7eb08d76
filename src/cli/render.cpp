// `nephele render`: one frame of a scene file, headless (EGL or OSMesa).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/output_options.h"
#include "cli/quick_look.h"
#include "core/error.h"
#include "engine/dataset.h"
#include "engine/scene_render.h"
#include "render/gl/context.h"
#include "scene/image_codec.h"
#include "scene/passes.h"
#include "scene/scene_file.h"

namespace nph::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::vector<std::string> outputs;
  std::string layer;
  std::vector<std::string> pass_files;  // NAME=FILE
  bool passes = false;
  bool depth = false;
  std::string display, view;
  std::string gl = "auto";
  int width = 0, height = 0;
  int timestep = -1;
  std::string basemap;
  std::string dem;
  bool print_scene = false;
};

int runRender(const RenderOptions& o) {
  std::shared_ptr<const engine::Dataset> dataset;
  scene::SceneDescription s;
  // A missing image codec (scene/image_codec.h) stops the command before any work, even before a
  // quick look converts the data to frame it; a scene file's own outputs are checked once read.
  if (!o.outputs.empty() || !o.layer.empty())
    scene::image_codec::modulePath(!o.outputs.empty() ? o.outputs.front() : o.layer);
  if (isDataFile(o.scene)) {
    // Quick look: a scene written for the data; --print-scene shows it for editing.
    QuickLook q = makeQuickLook({o.scene, o.outputs, o.width > 0 ? o.width : 1920, o.height > 0 ? o.height : 1080});
    if (o.print_scene) std::fputs(q.scene_json.c_str(), stdout);
    if (o.print_scene && o.outputs.empty() && o.layer.empty()) return kExitOk;
    s = std::move(q.scene);
    dataset = std::move(q.dataset);
  } else {
    if (o.print_scene) throw UsageError("--print-scene: " + o.scene + " is already a scene file");
    s = scene::loadSceneFile(o.scene);
    if (o.width > 0) s.output.width = o.width;
    if (o.height > 0) s.output.height = o.height;
    if (!o.outputs.empty()) s.output.paths = o.outputs;
  }
  if (o.timestep >= 0 && s.data) {
    s.data->timestep = o.timestep;
    s.data->time_utc.reset();
  }
  if (!o.basemap.empty()) {
    // Issue 14 item 3: any raster GDAL reads (scene/basemap.h), replacing the scene's or the quick
    // look's imagery; margin and resolution stay the scene's (or the defaults).
    if (!s.basemap) s.basemap.emplace();
    s.basemap->path = o.basemap;
  }
  if (!o.dem.empty()) s.terrain = scene::TerrainSpec{o.dem};  // issue 14 item 2 (scene/dem.h)
  if (o.passes) s.output.passes = true;
  applyColourOptions(o.display, o.view, s.output.image);
  if (o.depth) s.output.image.write_depth = true;
  for (const std::string& spec : o.pass_files) {
    const auto eq = spec.find('=');
    const auto pass = eq == std::string::npos ? std::nullopt : scene::passFromName(spec.substr(0, eq));
    if (!pass || eq + 1 >= spec.size()) {
      throw UsageError(fmt::format("--pass {}: expected NAME=FILE with NAME one of {}", spec, scene::passNames()));
    }
    s.output.pass_files.emplace_back(*pass, spec.substr(eq + 1));
  }
  if (!s.data) throw InputError(o.scene + ": no \"data\" section: which .nph or model file to render?");
  if (s.output.paths.empty() && o.layer.empty() && s.output.pass_files.empty()) {
    throw UsageError("no output: give -o FILE.png/.exr or output.paths in the scene");
  }
  // Before the render: a missing image codec module is an error now, not after the frame.
  scene::image_codec::modulePath(!s.output.paths.empty() ? s.output.paths.front()
                                 : !o.layer.empty()      ? o.layer
                                                         : s.output.pass_files.front().second);
  if (!dataset) dataset = engine::Dataset::open(s.data->path);

  auto ctx = gl::createHeadlessContext(o.gl);
  // The cloud layer is copied to host memory only when a file takes it (issue 19: on a GPU the
  // read-back is most of the frame's wall time, docs/benchmarks.md "Read-back").
  render::ReadBack read_back;
  read_back.cloud_layer = !o.layer.empty() || s.output.wantsPasses();
  engine::writeSceneOutputs(s, engine::renderSceneFrame(dataset, s, read_back), o.layer);
  return kExitOk;
}

}  // namespace

void addRenderCommand(CLI::App& app, Action& run) {
  auto opts = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render one frame of a scene file (JSON: data, camera, sun, basemap, quality, output; see "
                "docs/scene-file.md) headless through EGL or OSMesa. Writes the clouds composited over the "
                "basemap to every output path (.png: sRGB 8-bit; .exr: linear half) and, with --layer, the "
                "premultiplied cloud layer alone for a compositor; with --passes / --pass the compositing passes "
                "(cloud, ground, sky, shadow matte, depth).\n\nQuick look: give a wrfout, ICON or .nph "
                "file instead of a scene (`nephele render wrfout_d01.nc -o look.png`): the data is framed "
                "automatically (oblique camera, sun from the data's time, Blue Marble); --print-scene prints "
                "that scene as JSON to start editing from.");
  cmd->add_option("scene", opts->scene,
                  "scene file (JSON), or a wrfout / ICON (NetCDF, GRIB2 file or folder) / .nph file for a quick look")
      ->required()
      ->check(CLI::ExistingPath);  // a folder: GRIB2 quick look
  cmd->add_flag("--print-scene", opts->print_scene,
                "quick look: print the generated scene (JSON) to stdout; renders too when -o/--layer is given");
  cmd->add_option("-o,--output", opts->outputs, "output image(s) (.png/.exr); replaces output.paths");
  cmd->add_option("--layer", opts->layer, "also write the premultiplied cloud layer (.exr or .png)");
  cmd->add_flag("--passes", opts->passes,
                "write the compositing passes into every .exr output as layers: cloud.RGBA, ground.RGB, sky.RGB, "
                "shadow.Y and the cloud depth as Z (beauty = cloud + (1 - cloud.A)(ground + sky); docs/passes.md)");
  addColourOptions(*cmd, opts->display, opts->view);
  cmd->add_flag("--depth", opts->depth, "add the cloud depth Z (metres along the view axis) to .exr outputs");
  cmd->add_option("--pass", opts->pass_files,
                  "write one pass to a file of its own, NAME=FILE (repeatable); NAME: beauty, cloud, ground, sky, "
                  "shadow (a matte, 1 = no shadow; stored without tone curve), depth (.exr only)");
  cmd->add_option("--gl", opts->gl, "OpenGL backend: auto (EGL, then OSMesa), egl, osmesa")->capture_default_str();
  cmd->add_option("--width", opts->width, "image width (default: the scene's, 1920)");
  cmd->add_option("--height", opts->height, "image height (default: the scene's, 1080)");
  cmd->add_option("--timestep", opts->timestep, "timestep index (replaces data.timestep/time)");
  cmd->add_option("--basemap", opts->basemap,
                  "imagery under the clouds: any raster GDAL reads (GeoTIFF/COG, VRT, MBTiles, PNG/JPEG with a world "
                  "file, or a whole-Earth 2:1 image); replaces basemap.path");
  cmd->add_option("--dem", opts->dem,
                  "ground heights: a DEM GDAL reads (GeoTIFF/COG, VRT; one band of metres, with a CRS) replacing the "
                  "model's terrain where it has data and carrying the relief beyond the domain; replaces terrain.dem");
  cmd->callback([opts, &run] { run = [opts] { return runRender(*opts); }; });
}

}  // namespace nph::cli
