// nph_dump FILE.nph T OUT: the decoded volumes of timestep T of a .nph cache, read with NphReader
// (not with the VDB exporter), as OUT.json (grid and georeference) plus OUT_ice.f32 and
// OUT_water.f32 (raw little-endian float32, x fastest, then y, then k). The round-trip test
// (vdb_roundtrip.py) compares these with what python3-openvdb reads from the exported files.
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cache/nph_cache.h"

namespace {
void writeFloats(const std::string& path, const std::vector<float>& v) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(float)));
  if (!out) throw std::runtime_error(path + ": cannot write");
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: nph_dump FILE.nph TIMESTEP OUT_PREFIX\n");
    return 2;
  }
  try {
    const nph::cache::NphReader reader(argv[1]);
    const std::size_t t = std::strtoull(argv[2], nullptr, 10);
    const nph::ExtinctionVolumes v = reader.read(t);
    nlohmann::json j;
    j["nx"] = v.nx;
    j["ny"] = v.ny;
    j["nz"] = v.nz;
    j["dz_m"] = v.dz_m;
    j["z_bottom_m"] = v.z_bottom_m;
    j["time_utc"] = nph::geo::isoOrEmpty(v.time_utc);
    j["max_ice_per_m"] = v.max_ice_per_m;
    j["max_water_per_m"] = v.max_water_per_m;
    j["proj_definition"] = v.georef.proj_definition;
    j["geographic"] = v.georef.geographic;
    j["x0"] = v.georef.x0;
    j["y0"] = v.georef.y0;
    j["dx"] = v.georef.dx_m;
    j["dy"] = v.georef.dy_m;
    const std::string out = argv[3];
    std::ofstream(out + ".json") << j.dump(1) << "\n";
    writeFloats(out + "_ice.f32", v.ice_per_m);
    writeFloats(out + "_water.f32", v.water_per_m);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nph_dump: %s\n", e.what());
    return 1;
  }
  return 0;
}
