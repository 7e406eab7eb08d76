#include "engine/scene_render.h"

#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "core/log.h"
#include "core/process_memory.h"
#include "engine/session.h"
#include "scene/passes.h"

namespace nph::engine {

SceneFrame renderSceneFrame(std::shared_ptr<const Dataset> dataset, const scene::SceneDescription& scene,
                            const render::ReadBack& read_back) {
  Session session(std::move(dataset), scene);
  session.setReleaseAfterUpload(true);  // one frame: the decoded volume is not read after its upload
  return renderSceneFrame(session, scene, session.prepared().camera, read_back);
}

SceneFrame renderSceneFrame(Session& session, const scene::SceneDescription& scene, const scene::Camera& camera,
                            const render::ReadBack& read_back) {
  if (session.sun().elevation_deg <= 0.0) {
    log::warn("the sun is {:.1f} deg below the horizon: the clouds are lit from below", -session.sun().elevation_deg);
  }
  SceneFrame f;
  f.out = session.render(camera, read_back);
  const auto& st = session.deepLightMap().stats();
  if (session.stats().dlm_rebuilt) {
    log::info("deep light map: {}x{} texels, {} steps, {:.1f} nodes/texel (max {}), {:.1f} MB, {:.0f}x smaller than "
              "the uncompressed light volume, passes {:.0f}+{:.0f}+{:.0f} ms{}",
              st.texels.x, st.texels.y, st.steps, st.mean_nodes, st.max_nodes_used, double(st.bytes) / 1e6,
              st.compression_ratio, st.pass1_ms, st.pass2_ms, st.pass3_ms,
              st.unbounded_texels ? fmt::format(", {} texels over budget", st.unbounded_texels) : "");
  }
  if (f.out.gpu_milliseconds > 0.01) {  // a real GPU's query (llvmpipe's answer ≈ 0)
    log::info("ray cast {}x{} in {:.0f} ms (GPU {:.2f} ms; set-up and submission {:.0f} ms, read-back {:.0f} ms)",
              f.out.frame.width, f.out.frame.height, f.out.milliseconds, f.out.gpu_milliseconds,
              f.out.submit_milliseconds, f.out.readback_milliseconds);
  } else {
    log::info("ray cast {}x{} in {:.0f} ms (read-back {:.0f} ms)", f.out.frame.width, f.out.frame.height,
              f.out.milliseconds, f.out.readback_milliseconds);
  }
  if (const std::uint64_t cut = session.renderer().raysCutShort()) {
    log::warn("{} rays were cut short by the GL driver's loop limit (Mesa llvmpipe ends a shader's loops after "
              "65 535 iterations): the clouds behind each cut are missing. Raise quality step_voxels, keep "
              "empty_space_skipping on, or render on a GPU (docs/rendering.md \"llvmpipe's loop limit\")",
              cut);
  }
  {  // issue 19's memory accounting: on llvmpipe GL storage is process memory
    const render::VolumeTextures& vt = session.volumeTextures();
    const glm::ivec3 n = vt.frame().voxels;
    const double voxels = double(n.x) * double(n.y) * double(n.z);
    log::info("GL textures: volume {:.1f} MB ({:.2f} bytes/voxel{}), deep light map {:.1f} MB, ray caster {:.1f} MB",
              double(vt.bytes()) / 1e6, double(vt.bytes()) / voxels, vt.hasSeparateTextures() ? ", separate" : "",
              double(session.deepLightMap().textureBytes()) / 1e6, double(session.renderer().textureBytes()) / 1e6);
  }
  const scene::FramePasses* passes = f.out.passes ? &*f.out.passes : nullptr;
  if (scene.output.wantsPasses() && !read_back.cloud_layer) {
    throw std::logic_error(
        "renderSceneFrame: the scene's passes are made from the cloud layer, which was not read back");
  }
  if (scene.output.wantsPasses()) f.image = scene::outputFrame(scene.output, f.out.frame, f.out.cloud_layer, passes);
  logMemoryPhase("output frame");
  f.options = scene::imageOptionsFor(scene.output, session.sun().elevation_deg);
  if (scene.output.exposure == scene::ExposureMode::Sun) {
    log::info("exposure follows the sun ({:.1f} deg): {:+.2f} EV ({:+.2f} over output.exposure_ev)",
              session.sun().elevation_deg, f.options.exposure_ev,
              f.options.exposure_ev - scene.output.image.exposure_ev);
  }
  return f;
}

void writeSceneOutputs(const scene::SceneDescription& s, const SceneFrame& f, const std::string& layer_path) {
  const auto prepare = [](const std::string& path) {
    if (auto dir = std::filesystem::path(path).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  };
  for (const auto& path : s.output.paths) {
    prepare(path);
    scene::writeImage(f.written(), path, f.options);
    log::info("wrote {}{}", path, f.written().layers.empty() ? "" : " (with the compositing passes)");
  }
  for (const auto& [pass, path] : s.output.pass_files) {
    prepare(path);
    scene::writeImage(scene::passImage(pass, f.out.frame, f.out.cloud_layer, *f.out.passes), path, f.options);
    log::info("wrote {} ({} pass)", path, scene::passName(pass));
  }
  if (!layer_path.empty()) {
    if (f.out.cloud_layer.rgba.empty()) throw std::logic_error("writeSceneOutputs: the cloud layer was not read back");
    scene::writeImage(f.out.cloud_layer, layer_path, f.options);
    log::info("wrote {} (premultiplied cloud layer)", layer_path);
  }
  logMemoryPhase("image writing");
}

}  // namespace nph::engine
