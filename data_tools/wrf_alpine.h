#pragma once
// Issues 13/14: a 3 km convective storm over a generated mountain range (`nephele-gen wrf --case
// alpine-storm`, make demo's terrain shot). The terrain is the model's own HGT: a range along the
// domain's west–east axis cut by valleys that drain (connected lines whose floors fall
// monotonically from their heads to the foreland), and the clouds follow it (Muth 2026 §3.2: the
// convective and stratiform regimes a renderer must tell apart): orographic towers over the crests
// and slopes rising to 9.5–12.5 km with anvils downwind, a stratiform deck in the range's lee,
// shallow cumulus over the slopes and fog with a flat top in the lower valleys. Everything is a
// function of the grid and the seed (no library RNG): same seed, same bytes.
#include <cstddef>
#include <vector>

#include "atmosphere.h"

namespace nph::datagen {

/// A drainage line in grid kilometres from mass point (0, 0): the floor falls from `head_m` at the
/// first point to `mouth_m` at the last, monotonically along the arc length.
struct AlpineValley {
  std::vector<double> x_km, y_km;
  double head_m = 0.0, mouth_m = 0.0;
  double floor_half_width_km = 3.0;  ///< flat floor either side of the line
  double wall_width_km = 8.0;        ///< the walls rise to the crest envelope over this distance
  bool fog = false;                  ///< fog with a flat top lies on its floor where it is low
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;  ///< the line's bounding box [km]
};

struct AlpineTerrain {
  int nx = 0, ny = 0;
  double dx_km = 3.0;
  std::vector<double> height_m;    ///< HGT, nx*ny (j * nx + i)
  std::vector<double> envelope_m;  ///< the crest envelope the valleys are cut into
  std::vector<double> floor_m;     ///< floor height of the valley that shapes the column
  std::vector<double> wall;        ///< 0 on a valley floor, 1 on the envelope
  std::vector<signed char> fog;    ///< the column's valley carries fog
  std::vector<AlpineValley> valleys;
  double axisYkm(double x_km) const;  ///< the range's main divide
};

/// The generated range on an nx × ny grid of dx_m.
AlpineTerrain alpineTerrain(int nx, int ny, double dx_m, const ValueNoise& noise);

/// The range's continuous height function at (x, y) [grid km from mass point (0, 0)], its ridged
/// relief summed over `octaves` (the model's HGT: 4, down to 2 km; its finer DEM: 6, to 0.5 km).
/// HGT is this at the mass points, then conditioned so that every column drains.
struct AlpineSample {
  double height_m = 0.0, envelope_m = 0.0, floor_m = 0.0, wall = 1.0;
  signed char fog = 0;
};
AlpineSample sampleAlpineTerrain(const AlpineTerrain& t, const ValueNoise& noise, double x_km, double y_km,
                                 int octaves);

/// Per-column structure of the storm; each point follows from it, the height and the temperature.
struct AlpineColumns {
  std::vector<float> tower, tower_top_km, tower_base_km, tower_depth;  ///< convective cells and cumulus
  std::vector<float> anvil, anvil_top_km, anvil_base_km;
  std::vector<float> deck, deck_top_km, deck_base_km;
  std::vector<float> fog_top_m;  ///< absolute [m]; 0: no fog
};

/// Issue 14, eighteenth session: the storm's life cycle over a file of several hourly timesteps
/// (`nephele-gen wrf --case alpine-storm --times N`). Step 1 is the mature storm of the single
/// timestep (N = 1 writes it alone, byte for byte as before); step 0 is an hour younger (towering
/// cumulus, no anvils yet), later steps are older (the anvils longer downwind), and the last of
/// three or more decays (the towers collapse, the anvils thin). Every cell moves as one with the
/// steering wind (alpineSteeringWind), the lee deck with the wind at its mid level, the fog stays
/// in its valley; the wind written in the towers and the fog says so (alpineCloudWind).
struct AlpineStage {
  double shift_x_km = 0.0, shift_y_km = 0.0;            ///< the cells' displacement from their mature places
  double deck_shift_x_km = 0.0, deck_shift_y_km = 0.0;  ///< the lee deck's
  double growth = 1.0;                                  ///< 0: the young towers of step 0, 1: mature
  double anvil_age_h = 0.0;  ///< hours the anvils have spread downwind beyond their mature extent
  double decay = 0.0;        ///< 1: the towers collapse (the last step of three or more)
  bool life_cycle = false;   ///< several timesteps: the wind in the towers and the fog follows the clouds
};
AlpineStage alpineStage(int t, int ntimes);

AlpineColumns alpineColumns(const AlpineTerrain& terrain, const ValueNoise& noise, const AlpineStage& stage = {});

struct AlpinePoint {
  double q_cloud = 0, q_rain = 0, q_ice = 0, q_snow = 0, q_graupel = 0, w_m_per_s = 0, tke_m2_per_s2 = 0;
};
AlpinePoint alpinePoint(const AlpineColumns& col, std::size_t c, double z_m, double terrain_m, double temperature_k);

/// The ambient wind of the case [m/s] at height z: west-south-westerly, 6 m/s at the ground to
/// 24 m/s at 12 km (the shear that carries the anvils east-north-east).
void alpineWind(double z_m, double& u, double& v);

/// The storm's motion [m/s]: the 0–6 km mean of alpineWind (Bunkers et al. 2000's steering wind),
/// 10.5 m/s towards 20° north of east — 37.8 km, 12.6 columns, an hour.
void alpineSteeringWind(double& u, double& v);

/// The wind written at height z over column c in a life cycle (stage.life_cycle): in a tower
/// (base to top) the cell's own motion, the steering wind — the updraft carries the air it lifts
/// through the column, and a wind that says how the cloud moves is what a motion-compensated
/// blend between the timesteps needs; in the valley fog calm (a cold pool under its inversion);
/// elsewhere alpineWind. `u`, `v` hold alpineWind(z) on entry.
void alpineCloudWind(const AlpineColumns& col, std::size_t c, double z_m, double& u, double& v);

}  // namespace nph::datagen
