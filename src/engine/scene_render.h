#pragma once
// One frame of a scene file, rendered and written: what `nephele render` does after it has a scene
// and a dataset, shared with the Python module (issue #16 item 3) so both produce the same pixels
// and the same files from the same scene keys (docs/scene-file.md).
#include <memory>
#include <optional>
#include <string>

#include "engine/dataset.h"
#include "engine/session.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/output_image.h"
#include "scene/scene_file.h"

namespace nph::engine {

struct SceneFrame {
  render::RenderOutput out;  ///< frame, premultiplied cloud layer, passes (when the scene wants them)
  /// The frame with Z or the pass layers (outputFrame) when the scene asks for them; none when
  /// output.paths receive out.frame as it is (no second copy of the output, issue 19).
  std::optional<scene::RgbaImage> image;
  scene::ImageOutputOptions options;  ///< how they are written: output.image, exposure resolved for the sun

  /// What output.paths receive: image, else out.frame.
  const scene::RgbaImage& written() const { return image ? *image : out.frame; }
};

/// Renders `scene` of `dataset` once (Session: its timestep, camera, sun, quality), logging the
/// deep light map's and the ray cast's figures as `nephele render` does. Needs a current GL 4.5
/// context on the calling thread.
/// `read_back`: what the frame copies to host memory (`nephele render` skips the cloud layer when
/// no file takes it).
SceneFrame renderSceneFrame(std::shared_ptr<const Dataset> dataset, const scene::SceneDescription& scene,
                            const render::ReadBack& read_back = {});
/// The same with a session already made for `scene` (its time and sun set; only what changed
/// since its last frame is rebuilt, session.h), ray casting `camera`: the Python module's
/// persistent Renderer, whose frames thereby equal renderSceneFrame's.
SceneFrame renderSceneFrame(Session& session, const scene::SceneDescription& scene, const scene::Camera& camera,
                            const render::ReadBack& read_back = {});

/// Writes `frame` to the scene's output.paths and output.pass_files (folders created), and the
/// premultiplied cloud layer to `layer_path` unless it is empty. IoError when a file cannot be written.
void writeSceneOutputs(const scene::SceneDescription& scene, const SceneFrame& frame,
                       const std::string& layer_path = "");

}  // namespace nph::engine
