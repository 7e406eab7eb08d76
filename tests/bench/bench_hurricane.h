#pragma once
// Shared by the GL benchmarks: a hidden headless context on NEPHELE_GL's backend, and the
// realistic generated hurricane (data_tools presets, one timestep) as extinction volumes, written
// to a temporary NetCDF file named `scratch_name` and removed after loading.
#include <filesystem>
#include <memory>
#include <string>

#include "io/model_file.h"
#include "physics/volume_builder.h"
#include "presets.h"
#include "render/gl/context.h"

namespace nph::bench {

inline std::unique_ptr<gl::Context> hiddenContext() {
  gl::ContextOptions o;
  o.backend = gl::backendFromEnvironment();
  o.visible = false;
  return gl::createContext(o);
}

/// The volumes of timestep 0 of the generator's file for `spec`, written to a temporary NetCDF
/// file named `scratch_name` and removed after loading.
inline ExtinctionVolumes generatedVolumes(const datagen::WrfHurricaneSpec& spec, const std::string& scratch_name) {
  const auto path = (std::filesystem::temp_directory_path() / scratch_name).string();
  datagen::writeWrfHurricane(spec, path);
  const auto file = io::openModelFile(path);
  ExtinctionVolumes v =
      physics::buildExtinctionVolumes(file.load(0), physics::defaultOptics(), physics::VerticalGridOptions{});
  std::filesystem::remove(path);
  return v;
}

// Generated once per process (≈ 20 s of writing and converting a 228 MB wrfout): every benchmark of
// a binary that asks for it gets a copy of the same volumes.
inline ExtinctionVolumes realisticHurricane(const std::string& scratch_name) {
  static const ExtinctionVolumes once = [&] {
    datagen::WrfHurricaneSpec spec = datagen::wrfPreset(datagen::SampleSize::Realistic);
    spec.ntimes = 1;
    spec.format = datagen::NcFormat::Classic64;
    return generatedVolumes(spec, scratch_name);
  }();
  return once;
}

}  // namespace nph::bench
