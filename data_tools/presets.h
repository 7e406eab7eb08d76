#pragma once
// Named sizes for the sample data: `tiny` for tests (well under a second each), `realistic`
// for benchmarks (generated on demand, never committed).
#include "icon_scene.h"
#include "wrf_hurricane.h"

namespace nph::datagen {

enum class SampleSize { Tiny, Realistic };

inline WrfHurricaneSpec wrfPreset(SampleSize size) {
  WrfHurricaneSpec s;
  if (size == SampleSize::Realistic) {
    s.nx = 500;
    s.ny = 500;
    s.nz = 60;
    s.dx_m = 3000.0;  // 1500 km domain at convection-permitting resolution
    s.format = NcFormat::Netcdf4Deflate;
  }
  return s;
}

inline IconSceneSpec iconPreset(SampleSize size, bool native) {
  IconSceneSpec s;
  if (size == SampleSize::Realistic) {
    s.nlon = 500;
    s.nlat = 500;
    s.nz = 60;
    s.dlon_deg = 0.02;  // ICON-D2 regular-lat-lon spacing
    s.dlat_deg = 0.02;
    s.model_top_m = 22000.0;
    s.format = NcFormat::Netcdf4Deflate;
  }
  if (native) {
    // R3B7 (~18 km) for tiny, R19B7 (~2.9 km edge, ICON-D2's R19B07 parent) for realistic.
    s.native_divisions = size == SampleSize::Realistic ? 19 * 128 : 3 * 128;
  }
  return s;
}

}  // namespace nph::datagen
