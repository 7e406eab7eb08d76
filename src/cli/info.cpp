// `nephele info FILE...`: what a wrfout, ICON or .nph file holds.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cache/nph_cache.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/terminal_text.h"
#include "io/grib2_loader.h"
#include "io/model_file.h"
#include "physics/optics_settings.h"

namespace nph::cli {

namespace {

struct InfoOptions {
  std::vector<std::string> files;
  bool ranges = true;
  std::size_t timestep = 0;
  bool verify = false;
};

/// Everything printed holds strings from the files (times, provenance, attributes): control
/// characters are escaped so that a crafted file cannot drive the terminal (issue #18).
void out(const std::string& text) { std::fputs(terminalSafe(text).c_str(), stdout); }

std::string rangeText(const std::vector<float>& v) {
  if (v.empty()) return "absent";
  float lo = INFINITY, hi = -INFINITY;
  std::size_t bad = 0;
  for (float x : v) {
    if (!std::isfinite(x)) {
      ++bad;
      continue;
    }
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  std::string s = bad == v.size() ? "no finite values" : fmt::format("{:.4g} .. {:.4g}", lo, hi);
  if (bad > 0) s += fmt::format(" ({} non-finite)", bad);
  return s;
}

/// One line per aspect of the optics settings stored in a .nph index (OpticsSettings::toJson).
std::string opticsText(const std::string& json_text) {
  const nlohmann::json j = nlohmann::json::parse(json_text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("classes")) return json_text;
  std::string s = fmt::format("preset {}, r_eff from number concentrations {}\n", j.value("preset", "?"),
                              j.value("use_number_concentrations", false) ? "on" : "off");
  for (const auto& [name, c] : j["classes"].items()) {
    s += fmt::format("                {:8s} r_eff {:8.1f} um, density {:6.0f} kg/m3 -> {} volume\n", name,
                     c.value("effective_radius_m", 0.0) * 1e6, c.value("particle_density_kg_per_m3", 0.0),
                     c.value("volume", "?"));
  }
  if (j.contains("icon_corrections")) {
    const auto& ic = j["icon_corrections"];
    s += fmt::format("                ICON corrections (Muth 2026 3.3.1): cloud cover {}, condensate {}",
                     ic.value("diagnose_cloud_cover", false) ? "on" : "off",
                     ic.value("reconstruct_condensate", false) ? "on" : "off");
  }
  return s;
}

std::string projectionText(const std::string& proj, bool geographic) {
  if (proj.empty()) return "none (Cartesian, idealized run)";
  return geographic ? proj + " (grid in degrees)" : proj;
}

void describeNph(const std::string& path, const InfoOptions& o) {
  const cache::NphReader r(path);
  const cache::NphMetadata& m = r.metadata();
  out(fmt::format("{}: nephele extinction cache (.nph version {}, {:.2f} MB)\n", path, r.formatVersion(),
                  double(r.fileBytes()) / 1e6));
  out(fmt::format("  grid          {} x {} x {} (nx, ny, nz), dz {} m, z {} .. {} m above MSL\n", m.nx, m.ny, r.nz(),
                  m.dz_m, m.z_bottom_m, m.z_bottom_m + r.nz() * m.dz_m));
  out(fmt::format("  projection    {}\n", projectionText(m.georef.proj_definition, m.georef.geographic)));
  out(fmt::format("  spacing       dx {} dy {}, origin ({}, {})\n", m.georef.dx_m, m.georef.dy_m, m.georef.x0,
                  m.georef.y0));
  out(fmt::format("  geolocation   {}\n", m.georef.lat_deg.empty() ? "absent" : "lat/lon per column"));
  out(fmt::format("  terrain [m]   {}\n",
                  m.terrain_height_m.empty() ? std::string("absent (sea level)") : rangeText(m.terrain_height_m)));
  std::size_t windy = 0;
  for (std::size_t t = 0; t < r.timestepCount(); ++t) windy += r.timestep(t).hasWind() ? 1 : 0;
  out(fmt::format(
      "  variables     ice_per_m, water_per_m [1/m] (16-bit, linear per timestep){}\n",
      windy == 0 ? std::string()
                 : fmt::format("; wind U, V [m/s] (int16, 0.01 m/s) in {} of {} timesteps", windy, r.timestepCount())));
  out(fmt::format("  optics        {}\n", opticsText(m.optics_json)));
  out(fmt::format("  inputs        {}\n", fmt::join(m.inputs, ", ")));
  out(fmt::format("  created by    {}\n", m.created_by));
  out(fmt::format("  timesteps     {}\n", r.timestepCount()));
  for (std::size_t t = 0; t < r.timestepCount(); ++t) {
    const cache::TimestepInfo& s = r.timestep(t);
    out(fmt::format("    {:3d} {:22s} nz {:3d}  max ice {:.4g} /m  max water {:.4g} /m  "
                    "{:.2f} MB ({:.1f}x)  from {}[{}]\n",
                    t, geo::isoOrEmpty(s.time_utc), s.nz, s.max_ice_per_m, s.max_water_per_m,
                    double(s.chunk_bytes) / 1e6, s.chunk_bytes > 0 ? double(s.raw_bytes) / double(s.chunk_bytes) : 0.0,
                    s.source_file, s.source_time_index));
  }
  if (o.verify) {
    for (std::size_t t = 0; t < r.timestepCount(); ++t) (void)r.read(t);
    out(fmt::format("  verified      all {} chunks: checksums and sizes match\n", r.timestepCount()));
  }
}

/// Grid, projection and value ranges of one loaded model timestep.
void describeTimestep(const io::ModelTimestep& ts, const InfoOptions& o) {
  out(fmt::format("  grid          {} x {} x {} mass points (nx, ny, levels)\n", ts.nx, ts.ny, ts.nz));
  out(fmt::format("  projection    {}\n", projectionText(ts.georef.proj_definition, ts.georef.geographic)));
  out(fmt::format("  spacing       dx {} dy {}, origin ({}, {})\n", ts.georef.dx_m, ts.georef.dy_m, ts.georef.x0,
                  ts.georef.y0));
  out(fmt::format("  geolocation   {}\n", ts.georef.lat_deg.empty() ? "absent" : "lat/lon per column"));
  if (ts.model == io::ModelKind::Wrf) {
    out(fmt::format("  microphysics  MP_PHYSICS = {}\n", ts.microphysics_scheme));
  }
  out(fmt::format("  value ranges of timestep {} ({}):\n", o.timestep,
                  ts.time_utc ? ts.time_utc->iso8601() : "no time"));
  const char* unit_q = ts.model == io::ModelKind::Wrf ? "kg/kg dry air" : "kg/kg moist air";
  for (const auto& [h, v] : ts.q_kg_per_kg) {
    out(fmt::format("    q {:8s} [{}]  {}\n", physics::hydrometeorName(h), unit_q, rangeText(v)));
  }
  for (const auto& [h, v] : ts.number_per_kg) {
    out(fmt::format("    N {:8s} [1/kg]  {}\n", physics::hydrometeorName(h), rangeText(v)));
  }
  out(fmt::format("    water vapour [kg/kg]  {}\n", rangeText(ts.water_vapour_kg_per_kg)));
  out(fmt::format("    pressure [Pa]         {}\n", rangeText(ts.pressure_pa)));
  out(fmt::format("    temperature [K]       {}\n", rangeText(ts.temperature_k)));
  out(fmt::format("    height [m]            {}\n", rangeText(ts.height_m)));
  out(fmt::format("    terrain [m]           {}\n", rangeText(ts.terrain_height_m)));
  out(fmt::format("    cloud cover [0-1]     {}\n", rangeText(ts.cloud_cover_fraction)));
  out(fmt::format("  repairs       {} negative values set to 0, {} fill values read as 0\n",
                  ts.repairs.negative_clamped, ts.repairs.missing_as_zero));
  if (!ts.cloud_cover_fraction.empty()) {
    // the two inconsistencies the ICON corrections address (Muth 2026 §3.3.1)
    const auto qc = ts.q_kg_per_kg.find(io::Hydrometeor::Cloud);
    const auto qi = ts.q_kg_per_kg.find(io::Hydrometeor::Ice);
    std::size_t clc_zero = 0, clc_without = 0;
    for (std::size_t m = 0; m < ts.voxelCount(); ++m) {
      const float q =
          (qc != ts.q_kg_per_kg.end() ? qc->second[m] : 0.0f) + (qi != ts.q_kg_per_kg.end() ? qi->second[m] : 0.0f);
      if (ts.cloud_cover_fraction[m] <= 0.0f && q > 0.0f) ++clc_zero;
      if (ts.cloud_cover_fraction[m] > 0.0f && q <= 0.0f) ++clc_without;
    }
    out(fmt::format("  consistency   {} cells with CLC = 0 but qc + qi > 0, {} with CLC > 0 but "
                    "qc + qi = 0 (corrected by convert, Muth 2026 3.3.1)\n",
                    clc_zero, clc_without));
  }
}

void describeModel(const std::string& path, const InfoOptions& o) {
  const io::FileFormat format = io::sniffFormat(path);
  const io::ModelFile f = io::openModelFile(path);
  out(fmt::format("{}: {} ({:.2f} MB)\n", path, io::formatName(format),
                  double(std::filesystem::file_size(path)) / 1e6));
  out(fmt::format("  timesteps     {}\n", f.timesteps().size()));
  for (const io::TimestepRef& t : f.timesteps()) {
    out(fmt::format("    {:3d} {}\n", t.index, t.time_utc ? t.time_utc->iso8601() : "(no time)"));
  }
  if (!o.ranges || f.timesteps().empty()) return;
  if (o.timestep >= f.timesteps().size()) {
    throw UsageError(
        fmt::format("{}: --timestep {} requested, the file has {}", path, o.timestep, f.timesteps().size()));
  }
  describeTimestep(f.load(o.timestep), o);
}

/// GRIB2 files are described together: DWD writes one file per variable, level and step.
void describeGrib(const std::vector<std::string>& files, const InfoOptions& o) {
  const io::ModelSeries series = io::ModelSeries::open(files);
  const io::Grib2Dataset& g = *series.at(0).grib;
  std::uintmax_t bytes = 0;
  for (const std::string& f : g.files()) bytes += std::filesystem::file_size(f);
  const std::string name = g.files().size() == 1
                               ? g.files().front()
                               : fmt::format("{} (and {} more)", g.files().front(), g.files().size() - 1);
  out(fmt::format("{}: {} ({} files, {} messages, {:.2f} MB)\n", name, io::formatName(series.at(0).format),
                  g.files().size(), g.messageCount(), double(bytes) / 1e6));
  out(fmt::format("  GRIB2 grid    {}\n", g.grid().describe()));
  out(fmt::format("  levels        {} model levels (HHL: {} half levels)\n", g.levels(), g.levels() + 1));
  out(fmt::format("  variables     {}\n", g.variableSummary()));
  out(fmt::format("  timesteps     {}\n", series.size()));
  for (std::size_t t = 0; t < series.size(); ++t) {
    out(fmt::format("    {:3d} {}  (first file {})\n", t, geo::isoOrEmpty(series.at(t).time_utc),
                    std::filesystem::path(series.at(t).file).filename().string()));
  }
  if (!o.ranges) return;
  if (o.timestep >= series.size()) {
    throw UsageError(fmt::format("{}: --timestep {} requested, the data has {}", name, o.timestep, series.size()));
  }
  describeTimestep(series.load(o.timestep), o);
}

int runInfo(const InfoOptions& o) {
  int status = kExitOk;
  std::vector<std::string> files, grib;
  for (const std::string& input : o.files) {
    try {  // folders and unexpanded patterns become files; GRIB2 files are described together
      for (const std::string& f : io::expandModelInputs({input})) {
        (std::filesystem::is_regular_file(f) && io::hasGribSignature(f) ? grib : files).push_back(f);
      }
    } catch (const InputError& e) {
      std::fprintf(stderr, "nephele: error: %s\n", terminalSafe(e.what(), false).c_str());
      status = kExitFailure;
    }
  }
  if (!grib.empty()) {
    try {
      describeGrib(grib, o);
    } catch (const UsageError&) {
      throw;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "nephele: error: %s\n", terminalSafe(e.what(), false).c_str());
      status = kExitFailure;
    }
  }
  for (const std::string& path : files) {
    try {
      if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: no such file", path));
      if (cache::NphReader::sniff(path)) {
        describeNph(path, o);
      } else {
        describeModel(path, o);
      }
    } catch (const UsageError&) {
      throw;
    } catch (const std::exception& e) {  // report and go on with the next file
      std::fprintf(stderr, "nephele: error: %s\n", terminalSafe(e.what(), false).c_str());
      status = kExitFailure;
    }
  }
  return status;
}

}  // namespace

void addInfoCommand(CLI::App& app, Action& run) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand(
      "info", "Print what files hold: for wrfout and ICON files the format, timesteps, grid, projection,\n"
              "variables present and their value ranges (of one timestep); for .nph caches the grid,\n"
              "georeference, optics settings and per-timestep maxima and chunk sizes. ICON GRIB2 files\n"
              "(also from folders and quoted patterns) are described together as one data set.\n"
              "Exit status 1 when any file cannot be read (the others are still described).");
  sub->add_option("files", o->files, "wrfout, ICON NetCDF, ICON GRIB2 or .nph files, folders, quoted patterns")
      ->required();
  sub->add_flag("!--no-ranges", o->ranges, "model files: skip loading a timestep for value ranges");
  sub->add_option("--timestep", o->timestep, "model files: which timestep's ranges (default 0)");
  sub->add_flag("--verify", o->verify, ".nph files: read and checksum every chunk");
  sub->callback([o, &run] { run = [o] { return runInfo(*o); }; });
}

}  // namespace nph::cli
