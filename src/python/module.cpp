// `nephele._nephele`: the compiled half of the Python module (issue #16 item 3; docs/interop.md
// "Python"). Thin by design: datasets are engine::Dataset (the loaders of `nephele render`),
// scenes are parsed by scene/scene_file (the JSON keys of docs/scene-file.md), frames are made and
// written by engine/scene_render (what `nephele render` runs), in a headless GL context of its own
// (render/gl/context.h: EGL or OSMesa). The pure-Python half (nephele/__init__.py) turns dicts into
// scene text and xarray Datasets into datasets.
//
// pybind11 over the engine rather than ctypes over the frozen C API (nephele.h): the C API renders
// into a GL context the *host* owns and opens datasets only from paths; a Python user has neither a
// context nor files for arrays, and the C API has no scene file. The reasoning is in docs/interop.md.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.h"
#include "engine/animation.h"
#include "engine/dataset.h"
#include "engine/quick_look.h"
#include "engine/scene_render.h"
#include "io/field_checks.h"
#include "io/model_fields.h"
#include "io/model_file.h"
#include "render/gl/context.h"
#include "scene/animation_spec.h"
#include "scene/georeference.h"
#include "scene/output_image.h"
#include "scene/scene_file.h"

namespace py = pybind11;

namespace nph::python {
namespace {

/// A dataset as Python holds it; shared with the sessions rendering it.
struct PyDataset {
  std::shared_ptr<const engine::Dataset> dataset;
};

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

/// float32 array (rows, cols, channels) of `values` (row 0 = top, as the renderer's images).
template <typename T>
py::array_t<T> imageArray(const std::vector<T>& values, int height, int width, int channels) {
  py::array_t<T> a({py::ssize_t(height), py::ssize_t(width), py::ssize_t(channels)});
  std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(T));
  return a;
}

/// One (nz, ny, nx) float32 array of a volume's layout (x fastest, then y, then z).
py::array_t<float> volumeArray(const std::vector<float>& values, int nz, int ny, int nx) {
  py::array_t<float> a({py::ssize_t(nz), py::ssize_t(ny), py::ssize_t(nx)});
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(float));
  return a;
}

/// Dimensions of `a`: (nt, nz, ny, nx) for a 4-D array, (1, nz, ny, nx) for a 3-D one.
std::array<py::ssize_t, 4> timestepShape(const FloatArray& a, const std::string& dataset, const char* name) {
  if (a.ndim() == 4) return {a.shape(0), a.shape(1), a.shape(2), a.shape(3)};
  if (a.ndim() == 3) return {1, a.shape(0), a.shape(1), a.shape(2)};
  throw InputError(
      fmt::format("{}: {} has {} dimensions, expected (z, y, x) or (time, z, y, x)", dataset, name, a.ndim()));
}

/// The horizontal georeference of from_extinction/from_arrays' keywords (geo/grid_georeference.h).
geo::GridGeoreference georeferenceOf(const std::string& proj, double dx, double dy, double x0, double y0,
                                     bool geographic) {
  geo::GridGeoreference g;
  g.proj_definition = proj;
  g.dx_m = dx;
  g.dy_m = dy;
  g.x0 = x0;
  g.y0 = y0;
  g.geographic = geographic;
  return g;
}

/// The same keywords in a dict (grid(), model_fields()): proj, dx, dy, x0, y0, geographic.
void putGeoreference(py::dict& d, const geo::GridGeoreference& g) {
  d["proj"] = g.proj_definition;
  d["dx"] = g.dx_m;
  d["dy"] = g.dy_m;
  d["x0"] = g.x0;
  d["y0"] = g.y0;
  d["geographic"] = g.geographic;
}

/// The grid of timestep t (loads it): sizes, spacings, the vertical extent, the projection and,
/// for georeferenced grids, the footprint's lon/lat corners (SW, SE, NE, NW).
py::dict gridOf(const PyDataset& d, std::size_t t) {
  ExtinctionVolumes v;
  {
    py::gil_scoped_release release;
    v = d.dataset->load(t);
  }
  py::dict g;
  g["nx"] = v.nx;
  g["ny"] = v.ny;
  g["nz"] = v.nz;
  putGeoreference(g, v.georef);
  g["dz_m"] = v.dz_m;
  g["z_bottom_m"] = v.z_bottom_m;
  g["z_top_m"] = v.z_bottom_m + v.nz * v.dz_m;
  g["time_utc"] = geo::isoOrEmpty(v.time_utc);
  g["max_ice_per_m"] = v.max_ice_per_m;
  g["max_water_per_m"] = v.max_water_per_m;
  const glm::dvec3 size = volume::frameOf(v).size_m();
  g["size_m"] = py::make_tuple(size.x, size.y, size.z);
  py::list corners;
  if (!v.georef.proj_definition.empty()) {
    const scene::SceneGeoreference geo(v, volume::frameOf(v));
    for (const scene::LonLat& c : geo.footprintCorners()) corners.append(py::make_tuple(c.lon_deg, c.lat_deg));
  }
  g["lonlat_corners"] = corners;
  return g;
}

/// Timestep t's volumes as numpy arrays: ice_per_m, water_per_m (nz, ny, nx) and
/// terrain_height_m (ny, nx; None when the data has none), the keywords of from_extinction.
py::dict extinctionOf(const PyDataset& d, std::size_t t) {
  ExtinctionVolumes v;
  {
    py::gil_scoped_release release;
    v = d.dataset->load(t);
  }
  py::dict out;
  out["ice_per_m"] = volumeArray(v.ice_per_m, v.nz, v.ny, v.nx);
  out["water_per_m"] = volumeArray(v.water_per_m, v.nz, v.ny, v.nx);
  out["terrain_height_m"] =
      v.terrain_height_m.empty()
          ? py::object(py::none())
          : py::object(volumeArray(v.terrain_height_m, 1, v.ny, v.nx).reshape({py::ssize_t(v.ny), py::ssize_t(v.nx)}));
  return out;
}

PyDataset fromExtinction(const FloatArray& ice, const FloatArray& water, double dx, double dy, double dz_m,
                         double z_bottom_m, const std::string& proj, double x0, double y0, bool geographic,
                         const std::vector<std::string>& times_utc, std::optional<FloatArray> terrain_height_m,
                         const std::string& name) {
  const auto shape = timestepShape(ice, name, "ice_per_m");
  if (timestepShape(water, name, "water_per_m") != shape) {
    throw InputError(
        fmt::format("{}: water_per_m has another shape than ice_per_m ({} dimensions)", name, water.ndim()));
  }
  const std::size_t nt = std::size_t(shape[0]);
  if (!times_utc.empty() && times_utc.size() != nt) {
    throw InputError(fmt::format("{}: {} times for {} timesteps", name, times_utc.size(), nt));
  }
  std::vector<float> terrain;
  if (terrain_height_m) {
    if (terrain_height_m->ndim() != 2 || terrain_height_m->shape(0) != shape[2] ||
        terrain_height_m->shape(1) != shape[3]) {
      throw InputError(
          fmt::format("{}: terrain_height_m must have the shape (ny, nx) = ({}, {})", name, shape[2], shape[3]));
    }
    terrain.assign(terrain_height_m->data(), terrain_height_m->data() + terrain_height_m->size());
  }
  const std::size_t voxels = std::size_t(shape[1] * shape[2] * shape[3]);
  std::vector<ExtinctionVolumes> volumes(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    ExtinctionVolumes& v = volumes[t];
    v.nx = int(shape[3]);
    v.ny = int(shape[2]);
    v.nz = int(shape[1]);
    v.dz_m = dz_m;
    v.z_bottom_m = z_bottom_m;
    v.georef = georeferenceOf(proj, dx, dy, x0, y0, geographic);
    if (!times_utc.empty() && !times_utc[t].empty()) v.time_utc = geo::UtcTime::parse(times_utc[t]);
    v.ice_per_m.assign(ice.data() + t * voxels, ice.data() + (t + 1) * voxels);
    v.water_per_m.assign(water.data() + t * voxels, water.data() + (t + 1) * voxels);
    v.terrain_height_m = terrain;
  }
  return {engine::Dataset::fromVolumes(name, std::move(volumes))};
}

/// The scene text of the CLI's quick look at `d` (engine/quick_look.h: `nephele render DATA`
/// with no scene file), `data_path` its file ("" for data in memory), output `width` x `height`.
std::string quickLookOf(const PyDataset& d, const std::string& data_path, int width, int height) {
  py::gil_scoped_release release;
  const ExtinctionVolumes v = d.dataset->load(0);
  return engine::quickLookSceneText({data_path, {}, width, height, d.dataset->path()}, v);
}

/// from_arrays' hydrometeor keywords in io::kAllHydrometeors order: WRF's Q* names in lower case.
constexpr std::array<const char*, io::kAllHydrometeors.size()> kMixingRatioArgs = {"qcloud", "qrain",    "qice",
                                                                                   "qsnow",  "qgraupel", "qhail"};
/// Their number concentrations [1/kg] (two-moment schemes: WRF's QN*, effective_radius.h).
constexpr std::array<const char*, io::kAllHydrometeors.size()> kNumberArgs = {"qncloud", "qnrain",    "qnice",
                                                                              "qnsnow",  "qngraupel", "qnhail"};

/// One 3-D field argument of from_arrays, split into timesteps: a numpy array of a floating-point
/// dtype, (z, y, x) or (time, z, y, x), of the same shape as the first field (`shape`, set by the
/// first call), with finite values. InputError naming `name`, the argument and what was expected.
std::vector<std::vector<float>> fieldArgument(const py::handle& value, const std::string& arg, const std::string& name,
                                              std::optional<std::array<py::ssize_t, 4>>& shape) {
  const py::array a = py::array::ensure(value);
  if (!a)
    throw InputError(
        fmt::format("{}: {} is not an array, expected a numpy array (z, y, x) or (time, z, y, x)", name, arg));
  if (a.dtype().kind() != 'f') {
    throw InputError(fmt::format("{}: {} has dtype {}, expected floating-point values (float32 or float64)", name, arg,
                                 std::string(py::str(a.dtype()))));
  }
  const FloatArray f = FloatArray::ensure(a);
  const std::array<py::ssize_t, 4> s = timestepShape(f, name, arg.c_str());
  const auto text = [](const std::array<py::ssize_t, 4>& d) {
    return fmt::format("(time {}, z {}, y {}, x {})", d[0], d[1], d[2], d[3]);
  };
  if (shape && *shape != s) {
    throw InputError(
        fmt::format("{}: {} has the shape {}, expected that of the first field, {}", name, arg, text(s), text(*shape)));
  }
  if (s[1] < 2 || s[2] < 1 || s[3] < 1) {
    throw InputError(
        fmt::format("{}: {} has the shape {}, expected at least 2 levels and one column", name, arg, text(s)));
  }
  shape = s;
  const std::size_t voxels = std::size_t(s[1] * s[2] * s[3]);
  std::vector<std::vector<float>> out(static_cast<std::size_t>(s[0]));
  for (std::size_t t = 0; t < out.size(); ++t) {
    out[t].assign(f.data() + t * voxels, f.data() + (t + 1) * voxels);
    io::requireFinite(name, out.size() > 1 ? fmt::format("{} (timestep {})", arg, t) : arg, out[t]);
  }
  return out;
}

/// InputError unless every value of mixing ratio `var` lies in [0, kMaxMixingRatio] (the loaders'
/// gate, io/field_checks.h). The file loaders clamp negative values (advection noise); arrays
/// are refused instead, so a sign error in the caller's arithmetic does not pass for clear air.
void requireMixingRatio(const std::string& name, const std::string& var, const std::vector<float>& q) {
  const auto negative = std::find_if(q.begin(), q.end(), [](float v) { return v < 0.0f; });
  if (negative != q.end()) {
    throw InputError(fmt::format("{}: {} is {} at element {}, expected a mixing ratio [kg/kg] >= 0 (clip advection "
                                 "noise first: numpy.clip({}, 0, None), as the file loaders do)",
                                 name, var, *negative, negative - q.begin(), var));
  }
  io::requireAtMost(name, var, q, io::kMaxMixingRatio_kg_per_kg, "a mixing ratio [kg/kg]");
}

/// A dataset of hydrometeor arrays (`fields`: keyword → array, the keywords of from_arrays),
/// converted per timestep by the file loaders' optics and vertical resampling
/// (engine::convertModelTimestep). The values pass the loaders' gates (io/field_checks.h).
PyDataset fromArrays(const py::dict& fields, std::optional<FloatArray> terrain_height_m, const std::string& proj,
                     double dx, double dy, double x0, double y0, bool geographic, std::optional<FloatArray> lon_deg,
                     std::optional<FloatArray> lat_deg, const std::string& model, int microphysics_scheme,
                     const std::vector<std::string>& times_utc, const std::string& name) {
  if (model != "wrf" && model != "icon") {
    throw UsageError(fmt::format("{}: model {:?}: expected \"wrf\" (mixing ratios per kg of dry air) or \"icon\" "
                                 "(specific contents, per kg of moist air)",
                                 name, model));
  }
  std::optional<std::array<py::ssize_t, 4>> shape;
  std::map<std::string, std::vector<std::vector<float>>> values;
  for (const auto& [key, value] : fields) values[py::str(key)] = fieldArgument(value, py::str(key), name, shape);
  const auto take = [&](const std::string& arg) {
    const auto it = values.find(arg);
    return it == values.end() ? std::vector<std::vector<float>>{} : std::move(it->second);
  };
  const auto required = [&](const std::string& arg, const char* what) {
    if (!values.count(arg)) throw InputError(fmt::format("{}: {} is missing, expected {} (z, y, x)", name, arg, what));
    return take(arg);
  };
  bool any_q = false;
  for (const char* q : kMixingRatioArgs) any_q |= values.count(q) > 0;
  if (!any_q) {
    throw InputError(fmt::format("{}: no hydrometeor array, expected at least one of {} [kg/kg]", name,
                                 fmt::join(kMixingRatioArgs, ", ")));
  }
  auto pressure = required("pressure_pa", "the full pressure [Pa]");
  auto temperature = required("temperature_k", "the air temperature [K]");
  auto heights = required("heights_m", "the mass levels' heights above sea level [m]");
  auto vapour = take("qvapor");
  auto cover = take("cloud_cover");
  const std::size_t nt = std::size_t((*shape)[0]);
  if (!times_utc.empty() && times_utc.size() != nt) {
    throw InputError(fmt::format("{}: {} times_utc for {} timesteps", name, times_utc.size(), nt));
  }
  const int nz = int((*shape)[1]), ny = int((*shape)[2]), nx = int((*shape)[3]);
  const auto surface = [&](const std::optional<FloatArray>& a, const char* arg) {
    if (!a) return std::vector<float>{};
    if (a->ndim() != 2 || a->shape(0) != ny || a->shape(1) != nx) {
      throw InputError(fmt::format("{}: {} has {} dimensions{}, expected (y {}, x {})", name, arg, a->ndim(),
                                   a->ndim() == 2 ? fmt::format(" ({}, {})", a->shape(0), a->shape(1)) : "", ny, nx));
    }
    std::vector<float> v(a->data(), a->data() + a->size());
    io::requireFinite(name, arg, v);
    return v;
  };
  const std::vector<float> terrain = surface(terrain_height_m, "terrain_height_m");
  if (!terrain.empty()) {
    io::requireRange(name, "terrain_height_m", terrain, io::kLowestHeight_m, io::kHighestTerrain_m,
                     "a terrain height [m]");
  }
  std::vector<io::ModelTimestep> steps(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    io::ModelTimestep& ts = steps[t];
    const auto var = [&](const char* arg) {
      return nt > 1 ? fmt::format("{} (timestep {})", arg, t) : std::string(arg);
    };
    ts.source_file = name;
    ts.model = model == "icon" ? io::ModelKind::Icon : io::ModelKind::Wrf;
    ts.microphysics_scheme = microphysics_scheme;
    ts.nx = nx;
    ts.ny = ny;
    ts.nz = nz;
    if (!times_utc.empty() && !times_utc[t].empty()) ts.time_utc = geo::UtcTime::parse(times_utc[t]);
    for (std::size_t c = 0; c < kMixingRatioArgs.size(); ++c) {
      const auto it = values.find(kMixingRatioArgs[c]);
      if (it == values.end()) continue;
      requireMixingRatio(name, var(kMixingRatioArgs[c]), it->second[t]);
      ts.q_kg_per_kg[io::kAllHydrometeors[c]] = std::move(it->second[t]);
    }
    for (std::size_t c = 0; c < kNumberArgs.size(); ++c) {
      const auto it = values.find(kNumberArgs[c]);
      if (it == values.end()) continue;
      io::requireRange(name, var(kNumberArgs[c]), it->second[t], 0.0, io::kMaxNumberConcentration_per_kg,
                       "a number concentration [1/kg]");
      ts.number_per_kg[io::kAllHydrometeors[c]] = std::move(it->second[t]);
    }
    if (!vapour.empty()) {
      requireMixingRatio(name, var("qvapor"), vapour[t]);
      ts.water_vapour_kg_per_kg = std::move(vapour[t]);
    }
    io::requireRange(name, var("pressure_pa"), pressure[t], 1.0, 2.0e5, "a pressure [Pa]");
    io::requireRange(name, var("temperature_k"), temperature[t], 100.0, 400.0, "a temperature [K]");
    io::requireRange(name, var("heights_m"), heights[t], io::kLowestHeight_m, io::kHighestHeight_m, "a height [m]");
    ts.pressure_pa = std::move(pressure[t]);
    ts.temperature_k = std::move(temperature[t]);
    ts.height_m = std::move(heights[t]);
    if (!cover.empty()) {
      io::requireRange(name, var("cloud_cover"), cover[t], 0.0, 1.0, "a cloud cover fraction");
      ts.cloud_cover_fraction = std::move(cover[t]);
    }
    ts.terrain_height_m = terrain;
    ts.georef = georeferenceOf(proj, dx, dy, x0, y0, geographic);
    ts.georef.lon_deg = surface(lon_deg, "lon");
    ts.georef.lat_deg = surface(lat_deg, "lat");
  }
  return {engine::Dataset::fromModelFields(name, std::move(steps))};
}

/// Timestep t of a model file as the loaders read it (io::ModelSeries): the keywords of
/// from_arrays, so arrays from a file round-trip through it (and can be edited in between).
py::dict modelFieldsOf(const std::string& path, std::size_t t) {
  io::ModelTimestep ts;
  {
    py::gil_scoped_release release;
    ts = io::ModelSeries::open(io::expandModelInputs({path})).load(t);  // folders and patterns too
  }
  const auto volume = [&](const std::vector<float>& v) { return volumeArray(v, ts.nz, ts.ny, ts.nx); };
  const auto surface = [&](const std::vector<float>& v) {
    return v.empty() ? py::object(py::none())
                     : py::object(volumeArray(v, 1, ts.ny, ts.nx).reshape({py::ssize_t(ts.ny), py::ssize_t(ts.nx)}));
  };
  py::dict d;
  for (std::size_t c = 0; c < kMixingRatioArgs.size(); ++c) {
    const auto it = ts.q_kg_per_kg.find(io::kAllHydrometeors[c]);
    if (it != ts.q_kg_per_kg.end()) d[kMixingRatioArgs[c]] = volume(it->second);
    const auto n = ts.number_per_kg.find(io::kAllHydrometeors[c]);
    if (n != ts.number_per_kg.end()) d[kNumberArgs[c]] = volume(n->second);
  }
  if (!ts.water_vapour_kg_per_kg.empty()) d["qvapor"] = volume(ts.water_vapour_kg_per_kg);
  d["pressure_pa"] = volume(ts.pressure_pa);
  d["temperature_k"] = volume(ts.temperature_k);
  d["heights_m"] = volume(ts.height_m);
  if (!ts.cloud_cover_fraction.empty()) d["cloud_cover"] = volume(ts.cloud_cover_fraction);
  d["terrain_height_m"] = surface(ts.terrain_height_m);
  putGeoreference(d, ts.georef);
  d["lon"] = surface(ts.georef.lon_deg);
  d["lat"] = surface(ts.georef.lat_deg);
  d["model"] = ts.model == io::ModelKind::Icon ? "icon" : "wrf";
  d["microphysics_scheme"] = ts.microphysics_scheme;
  d["time_utc"] = geo::isoOrEmpty(ts.time_utc);
  return d;
}

/// The scene of a render call: the JSON file `scene_path`, or `scene_text` (JSON named
/// `scene_name`, relative paths against `base_dir`), with the overrides of `nephele render`'s
/// -o/--width/--height/--timestep (0 or negative: none).
scene::SceneDescription sceneOf(const std::string& scene_path, const std::string& scene_text,
                                const std::string& scene_name, const std::string& base_dir,
                                const std::optional<std::vector<std::string>>& outputs, int width, int height,
                                int timestep) {
  scene::SceneDescription s =
      scene_path.empty() ? scene::parseSceneText(scene_text, scene_name, base_dir) : scene::loadSceneFile(scene_path);
  if (width > 0) s.output.width = width;
  if (height > 0) s.output.height = height;
  if (outputs) s.output.paths = *outputs;  // as `nephele render -o`: replaces output.paths
  if (timestep >= 0) {
    if (!s.data) s.data.emplace();
    s.data->timestep = timestep;
    s.data->time_utc.reset();
  }
  return s;
}

void requireDtype(const std::string& dtype) {
  if (dtype != "float32" && dtype != "uint8") {
    throw UsageError(fmt::format("dtype {}: expected \"float32\" (scene-linear) or \"uint8\" (display codes)", dtype));
  }
}

/// The 8-bit codes a .png output stores of the frame (or the cloud layer); empty for float32.
/// Touches no Python object (called with the GIL released).
std::vector<std::uint8_t> displayCodes(const engine::SceneFrame& frame, const std::string& dtype, bool cloud_layer) {
  if (dtype != "uint8") return {};
  const scene::RgbaImage& img = cloud_layer ? frame.out.cloud_layer : frame.out.frame;
  if (frame.options.display.empty()) return scene::encodeSrgb8(img, frame.options);
  // an OpenColorIO display: its code values, 8-bit as writePng stores SDR displays
  const std::vector<float> v = scene::encodeDisplay(img, frame.options);
  std::vector<std::uint8_t> codes(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) codes[i] = static_cast<std::uint8_t>(std::lround(v[i] * 255.0f));
  return codes;
}

/// The frame as numpy: `codes` (uint8) or, for float32, what the OpenEXR output stores, the
/// linear values times 2^exposure (resolved for the frame's sun: frame.options,
/// scene/output_image.h), in float instead of half.
py::array frameArray(const engine::SceneFrame& frame, const std::vector<std::uint8_t>& codes, const std::string& dtype,
                     bool cloud_layer) {
  const scene::RgbaImage& img = cloud_layer ? frame.out.cloud_layer : frame.out.frame;
  if (dtype == "uint8") return imageArray(codes, img.height, img.width, 4);
  std::vector<float> linear = img.rgba;
  const glm::vec3 scale = scene::radianceScale(frame.options);  // 2^exposure × the white balance
  for (std::size_t i = 0; i < linear.size(); ++i) {
    if (i % 4 != 3) linear[i] *= scale[int(i % 4)];
  }
  return imageArray(linear, img.height, img.width, 4);
}

/// The dataset given, else the scene's data.path (opened later, without the GIL); InputError
/// when there is neither.
std::shared_ptr<const engine::Dataset> datasetOrScenePath(const PyDataset* dataset, const scene::SceneDescription& s) {
  if (dataset) return dataset->dataset;
  if (!s.data || s.data->path.empty()) {
    throw InputError(s.source_file + ": no dataset given and no \"data\" section: which .nph or model file to render?");
  }
  return nullptr;
}

/// Renders one frame: the scene (sceneOf), the dataset given or else the scene's data.path, in a
/// new session and GL context. Writes the scene's outputs; returns the frame (or the
/// premultiplied cloud layer).
py::array renderFrame(const PyDataset* dataset, const std::string& scene_path, const std::string& scene_text,
                      const std::string& scene_name, const std::string& base_dir, const std::string& gl,
                      std::optional<std::vector<std::string>> outputs, int width, int height, int timestep,
                      const std::string& dtype, bool cloud_layer) {
  requireDtype(dtype);
  const scene::SceneDescription s =
      sceneOf(scene_path, scene_text, scene_name, base_dir, outputs, width, height, timestep);
  std::shared_ptr<const engine::Dataset> data = datasetOrScenePath(dataset, s);
  engine::SceneFrame frame;
  std::vector<std::uint8_t> codes;
  {
    py::gil_scoped_release release;  // decoding, lighting and ray casting touch no Python object
    if (!data) data = engine::Dataset::open(s.data->path);
    const auto ctx = gl::createHeadlessContext(gl);
    frame = engine::renderSceneFrame(data, s);
    engine::writeSceneOutputs(s, frame);
    codes = displayCodes(frame, dtype, cloud_layer);
  }
  return frameArray(frame, codes, dtype, cloud_layer);
}

/// A persistent renderer (issue #16 item 3): one GL context and one engine::Session kept between
/// frames, so a frame rebuilds only what changed since the last (session.h; Nes 2008 §6.3 table
/// 6.1): a new timestep uploads a volume and rebuilds the deep light map, a new sun rebuilds the
/// DLM, a new camera only ray casts. Each frame is made by the engine function of
/// `nephele render` (engine::renderSceneFrame), so it equals a one-off render of the same scene.
class PyRenderer {
 public:
  PyRenderer(const PyDataset* dataset, const std::string& scene_path, const std::string& scene_text,
             const std::string& scene_name, const std::string& base_dir, const std::string& gl, int width, int height,
             int timestep)
      : scene_(sceneOf(scene_path, scene_text, scene_name, base_dir, std::nullopt, width, height, timestep)),
        base_dir_(base_dir) {
    std::shared_ptr<const engine::Dataset> data = datasetOrScenePath(dataset, scene_);
    py::gil_scoped_release release;
    if (!data) data = engine::Dataset::open(scene_.data->path);
    context_ = gl::createHeadlessContext(gl);
    session_ = std::make_unique<engine::Session>(std::move(data), scene_);
    // A fractional time blends as `nephele animate` would: the scene's animation.interpolation.
    session_->setTimeBlend(engine::timeBlendFor(scene::parseAnimation(scene_).interpolation));
    timestep_ = std::size_t(session_->time());
  }
  ~PyRenderer() { close(); }
  PyRenderer(const PyRenderer&) = delete;
  PyRenderer& operator=(const PyRenderer&) = delete;

  /// One frame. `time_index`: a timestep index (fractional: the blend of its two neighbours,
  /// dataset.h), NaN to keep the current one; `time_utc` instead: the timestep at that time.
  /// `overrides`: JSON of a scene's "camera" and/or "sun" sections, each replacing the current one
  /// when `has_camera`/`has_sun`. `outputs`: files written as output.paths (none: the scene's).
  py::array render(double time_index, const std::string& time_utc, const std::string& overrides, bool has_camera,
                   bool has_sun, std::optional<std::vector<std::string>> outputs, const std::string& dtype,
                   bool cloud_layer) {
    requireOpen();
    requireDtype(dtype);
    if (has_camera || has_sun) {  // parsed as a scene, so keys and values are checked as in a scene file
      const scene::SceneDescription o = scene::parseSceneText(overrides, "<Renderer.render camera/sun>", base_dir_);
      if (has_camera) scene_.camera = o.camera;
      if (has_sun) scene_.sun = o.sun;
    }
    const engine::Dataset& data = session_->dataset();
    if (!time_utc.empty()) {
      scene::DataSpec spec;
      spec.time_utc = time_utc;
      timestep_ = scene::timestepIndexFor(spec, data.times(), data.path());
      time_index = double(timestep_);
    } else if (!std::isnan(time_index)) {
      timestep_ = engine::bracketTime(time_index, data.timestepCount()).first;  // UsageError when infinite
    }
    scene::SceneDescription s = scene_;
    if (outputs) s.output.paths = *outputs;
    engine::SceneFrame frame;
    std::vector<std::uint8_t> codes;
    {
      py::gil_scoped_release release;
      context_->makeCurrent();  // another Renderer or nephele.render may have made theirs current
      if (!std::isnan(time_index)) {
        session_->setTime(time_index);
        session_->setPlaybackDirection(0);  // decode only what is shown: no reading ahead
      }
      session_->setSun(session_->sunFor(s.sun, timestep_));
      frame = engine::renderSceneFrame(*session_, s, session_->cameraFor(s.camera));
      engine::writeSceneOutputs(s, frame);
      codes = displayCodes(frame, dtype, cloud_layer);
    }
    return frameArray(frame, codes, dtype, cloud_layer);
  }

  /// The session's counters (engine::FrameStats, PrefetchStats): what the last frame rebuilt and
  /// how often the volume was uploaded, the DLM built and a timestep decoded since the start.
  py::dict stats() const {
    requireOpen();
    const engine::FrameStats& f = session_->stats();
    const engine::PrefetchStats p = session_->prefetchStats();
    py::dict d;
    d["time_index"] = f.time_index;
    d["volume_changed"] = f.volume_changed;
    d["dlm_rebuilt"] = f.dlm_rebuilt;
    d["volume_uploads"] = f.volume_uploads;
    d["dlm_builds"] = f.dlm_builds;
    d["dlm_reuses"] = f.dlm_reuses;
    d["timestep_decodes"] = p.misses + p.waits + p.prefetched;  // loads (model files: conversions)
    d["load_ms"] = f.load_ms;
    d["upload_ms"] = f.upload_ms;
    d["dlm_ms"] = f.dlm_ms;
    d["raycast_ms"] = f.raycast_ms;
    return d;
  }

  /// Frees the session's GL objects in its own context, then the context. Idempotent.
  void close() {
    if (!context_) return;
    py::gil_scoped_release release;
    context_->makeCurrent();
    session_.reset();
    context_.reset();
  }
  bool closed() const { return !context_; }

 private:
  void requireOpen() const {
    if (!context_) throw UsageError("nephele.Renderer: used after close()");
  }

  scene::SceneDescription scene_;  ///< the current scene: the camera and sun of the last frame
  std::string base_dir_;
  std::size_t timestep_ = 0;              ///< integer timestep of the current time (for the sun's time)
  std::unique_ptr<gl::Context> context_;  ///< declared before session_: destroyed after it
  std::unique_ptr<engine::Session> session_;
};

}  // namespace
}  // namespace nph::python

PYBIND11_MODULE(_nephele, m) {
  using namespace nph;
  using namespace nph::python;
  m.doc() = "nephele's engine: datasets, scenes and headless rendering (use the `nephele` package)";

  // nph::Error and its kinds as Python exceptions; the messages name the file, the variable and
  // what was expected (core/error.h). InputError and UsageError are also ValueErrors, IoError an OSError.
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  const py::tuple value_bases = py::make_tuple(error, py::handle(PyExc_ValueError));
  // Leaked on purpose: the module (which holds them too) lives until the interpreter ends, and a
  // static py::object would be released after it has.
  const auto make = [&](const char* name, const py::tuple& bases) {
    PyObject* type = PyErr_NewException(fmt::format("nephele._nephele.{}", name).c_str(), bases.ptr(), nullptr);
    m.attr(name) = py::handle(type);
    return type;
  };
  static PyObject* input_error = make("InputError", value_bases);
  static PyObject* usage_error = make("UsageError", value_bases);
  static PyObject* io_error = make("IoError", py::make_tuple(error, py::handle(PyExc_OSError)));
  static PyObject* gl_error = make("GlError", py::make_tuple(error));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input_error, e.what());
    } catch (const UsageError& e) {
      PyErr_SetString(usage_error, e.what());
    } catch (const IoError& e) {
      PyErr_SetString(io_error, e.what());
    } catch (const GlError& e) {
      PyErr_SetString(gl_error, e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  py::class_<PyDataset>(m, "Dataset")
      .def_property_readonly("path", [](const PyDataset& d) { return d.dataset->path(); })
      .def_property_readonly("timestep_count", [](const PyDataset& d) { return d.dataset->timestepCount(); })
      .def_property_readonly("times",
                             [](const PyDataset& d) {
                               std::vector<std::optional<std::string>> times;
                               for (std::size_t t = 0; t < d.dataset->timestepCount(); ++t) {
                                 const std::string& iso = d.dataset->isoTime(t);
                                 times.push_back(iso.empty() ? std::nullopt : std::optional<std::string>(iso));
                               }
                               return times;
                             })
      .def("source_file", [](const PyDataset& d, std::size_t t) { return d.dataset->sourceFile(t); })
      .def("grid", &gridOf, py::arg("timestep") = 0)
      .def("extinction", &extinctionOf, py::arg("timestep") = 0);

  m.def(
      "open",
      [](const std::string& path) {
        py::gil_scoped_release release;
        return PyDataset{engine::Dataset::open(path)};
      },
      py::arg("path"));
  m.def(
      "open_series",
      [](const std::vector<std::string>& paths) {
        py::gil_scoped_release release;
        return PyDataset{engine::Dataset::openSeries(paths)};
      },
      py::arg("paths"));
  m.def("from_extinction", &fromExtinction, py::arg("ice_per_m"), py::arg("water_per_m"), py::arg("dx"), py::arg("dy"),
        py::arg("dz_m"), py::arg("z_bottom_m"), py::arg("proj"), py::arg("x0"), py::arg("y0"), py::arg("geographic"),
        py::arg("times_utc"), py::arg("terrain_height_m"), py::arg("name"));
  py::class_<PyRenderer>(m, "Renderer")
      .def(py::init<const PyDataset*, const std::string&, const std::string&, const std::string&, const std::string&,
                    const std::string&, int, int, int>(),
           py::arg("dataset"), py::arg("scene_path"), py::arg("scene_text"), py::arg("scene_name"), py::arg("base_dir"),
           py::arg("gl"), py::arg("width"), py::arg("height"), py::arg("timestep"))
      .def("render", &PyRenderer::render, py::arg("time_index"), py::arg("time_utc"), py::arg("overrides"),
           py::arg("has_camera"), py::arg("has_sun"), py::arg("outputs"), py::arg("dtype"), py::arg("cloud_layer"))
      .def("stats", &PyRenderer::stats)
      .def("close", &PyRenderer::close)
      .def_property_readonly("closed", &PyRenderer::closed);
  m.def("from_arrays", &fromArrays, py::arg("fields"), py::arg("terrain_height_m"), py::arg("proj"), py::arg("dx"),
        py::arg("dy"), py::arg("x0"), py::arg("y0"), py::arg("geographic"), py::arg("lon"), py::arg("lat"),
        py::arg("model"), py::arg("microphysics_scheme"), py::arg("times_utc"), py::arg("name"));
  m.def("quick_look", &quickLookOf, py::arg("dataset"), py::arg("data_path"), py::arg("width"), py::arg("height"));
  m.def("model_fields", &modelFieldsOf, py::arg("path"), py::arg("timestep"));
  m.def("render", &renderFrame, py::arg("dataset"), py::arg("scene_path"), py::arg("scene_text"), py::arg("scene_name"),
        py::arg("base_dir"), py::arg("gl"), py::arg("outputs"), py::arg("width"), py::arg("height"),
        py::arg("timestep"), py::arg("dtype"), py::arg("cloud_layer"));
}
