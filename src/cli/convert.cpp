// `nephele convert INPUTS... -o storm.nph`: loader -> optics -> vertical resampling -> cache, for
// every timestep of every input, one timestep in memory at a time.
#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cache/nph_cache.h"
#include "cli/commands.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/large_buffer.h"
#include "core/log.h"
#include "io/model_file.h"
#include "physics/optics_settings.h"
#include "physics/vertical_resampling.h"
#include "physics/volume_builder.h"

namespace nph::cli {

namespace {

struct ConvertOptions {
  std::vector<std::string> inputs;
  std::string output;
  std::string preset = "default";
  std::vector<std::string> radii;
  bool no_number_concentrations = false;
  bool no_wind = false;
  bool no_icon_cloud_cover = false;
  bool no_icon_condensate = false;
  double dz_m = 250.0;
  std::optional<double> z_top_m;
  std::optional<double> z_bottom_m;
  double crop_threshold_per_m = 1e-6;
  int zstd_level = 3;
  bool progress = false;
  bool no_progress = false;
  bool stats = false;
  bool force = false;
  std::size_t memory_budget_mb = 0;
};

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Bytes of the model fields held by a loaded timestep (what NetCDF decompressed for us).
std::size_t fieldBytes(const io::ModelTimestep& ts) {
  std::size_t floats = ts.water_vapour_kg_per_kg.size() + ts.pressure_pa.size() + ts.temperature_k.size() +
                       ts.height_m.size() + ts.terrain_height_m.size() + ts.cloud_cover_fraction.size();
  for (const auto& [h, v] : ts.q_kg_per_kg) floats += v.size();
  for (const auto& [h, v] : ts.number_per_kg) floats += v.size();
  return floats * sizeof(float);
}

double peakResidentMb() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

/// Same projection and grid placement (to 1e-6 of a grid spacing; lat/lon follow from these).
bool sameGrid(const geo::GridGeoreference& a, const geo::GridGeoreference& b) {
  auto close = [](double x, double y, double spacing) {
    return std::abs(x - y) <= 1e-6 * std::max(std::abs(spacing), 1e-12);
  };
  return a.proj_definition == b.proj_definition && a.geographic == b.geographic && close(a.dx_m, b.dx_m, b.dx_m) &&
         close(a.dy_m, b.dy_m, b.dy_m) && close(a.x0, b.x0, b.dx_m) && close(a.y0, b.y0, b.dy_m);
}

physics::OpticsSettings opticsFrom(const ConvertOptions& o) {
  physics::OpticsSettings s = physics::opticsPreset(o.preset);
  for (const std::string& r : o.radii) physics::applyRadiusOverride(s, r);
  if (o.no_number_concentrations) s.use_number_concentrations = false;
  s.icon.diagnose_cloud_cover = !o.no_icon_cloud_cover;
  s.icon.reconstruct_condensate = !o.no_icon_condensate;
  return s;
}

int runConvert(const ConvertOptions& o) {
  const physics::OpticsSettings optics = opticsFrom(o);
  physics::VerticalGridOptions vertical;
  vertical.dz_m = o.dz_m;
  vertical.z_top_m = o.z_top_m;
  vertical.z_bottom_m = o.z_bottom_m;
  vertical.crop_threshold_per_m = o.crop_threshold_per_m;
  if (!(o.dz_m > 0.0)) throw UsageError(fmt::format("--dz must be > 0 m, got {}", o.dz_m));
  if (std::filesystem::is_directory(o.output)) {
    throw UsageError(fmt::format("{}: is a directory; -o names the .nph file to write", o.output));
  }
  // Folders and unexpanded patterns (DWD's GRIB2: one file per variable, level and step).
  const std::vector<std::string> inputs = io::expandModelInputs(o.inputs);
  for (const std::string& input : inputs) {
    std::error_code ec;
    if (std::filesystem::equivalent(input, o.output, ec)) {
      throw UsageError(fmt::format("{}: the output would replace an input file", o.output));
    }
  }
  // Replacing an older .nph is normal; replacing anything else (a typo naming a model file) is not.
  if (std::filesystem::exists(o.output) && !cache::NphReader::sniff(o.output) && !o.force) {
    throw UsageError(fmt::format("{}: exists and is not a .nph file; refusing to replace it (use --force)", o.output));
  }

  // Timestep after timestep the same large blocks are allocated and freed: keep them in the
  // process, faulted in (core/large_buffer.h; issue 19, convert speed).
  reuseFreedMemoryForLargeBlocks();

  io::LoadOptions load;
  load.memory_budget_bytes = o.memory_budget_mb * 1024 * 1024;
  // WRF's detail fields (CLDFRA, TKE, W, U, V) are read after the optics' fields are freed, into
  // their memory (io::LoadOptions::defer_detail; issue 19: five fields less at the peak).
  load.defer_detail = true;
  // ICON condensate corrections (Muth 2026 §3.3.1): the loaders hand over the file's fields
  // unchanged; the optics apply the corrections (physics/icon_corrections.h, switches above).

  const auto t_start = Clock::now();
  auto t0 = Clock::now();
  const io::ModelSeries series = io::ModelSeries::open(inputs, load);
  double seconds_open = secondsSince(t0);
  if (series.size() == 0) throw InputError(fmt::format("{}: no timesteps", fmt::join(o.inputs, ", ")));

  std::uintmax_t input_bytes = 0;
  for (const std::string& f : inputs) input_bytes += std::filesystem::file_size(f);

  ProgressBar bar(series.size(), !o.no_progress && (o.progress || ProgressBar::stderrIsTerminal()));
  std::unique_ptr<cache::NphWriter> writer;
  double seconds_load = 0.0, seconds_optics = 0.0, seconds_write = 0.0;
  std::size_t model_bytes = 0;
  std::int64_t negative_clamped = 0, missing_as_zero = 0;
  int nx = 0, ny = 0;
  geo::GridGeoreference first_georef;
  for (std::size_t t = 0; t < series.size(); ++t) {
    const io::TimestepRef& ref = series.at(t);
    bar.update(
        t, fmt::format("{} {}", std::filesystem::path(ref.file).filename().string(), geo::isoOrEmpty(ref.time_utc)));
    t0 = Clock::now();
    // The heap above its current top on huge pages before the timestep's fields and HDF5's buffers
    // are allocated from it (core/large_buffer.h; 10× fewer page faults).
    reserveHugePageHeap(kHugePageHeapReserveBytes);
    io::ModelTimestep ts = series.load(t);
    seconds_load += secondsSince(t0);
    model_bytes += fieldBytes(ts);
    negative_clamped += ts.repairs.negative_clamped;
    missing_as_zero += ts.repairs.missing_as_zero;

    t0 = Clock::now();
    if (!writer) {  // the first timestep fixes the grid of the whole file
      nx = ts.nx;
      ny = ts.ny;
      first_georef = ts.georef;
      first_georef.lat_deg.clear();
      first_georef.lon_deg.clear();
      if (!vertical.z_bottom_m) vertical.z_bottom_m = physics::defaultBottomHeight_m(ts, o.dz_m);
      cache::NphMetadata meta;
      meta.nx = ts.nx;
      meta.ny = ts.ny;
      meta.dz_m = o.dz_m;
      meta.z_bottom_m = *vertical.z_bottom_m;
      meta.georef = ts.georef;
      meta.terrain_height_m = ts.terrain_height_m;  // static: the first timestep's
      meta.optics_json = optics.toJson();
      meta.inputs = o.inputs;
      meta.created_by = "nephele " NEPHELE_VERSION;
      cache::WriterOptions wo;
      wo.zstd_level = o.zstd_level;
      writer = std::make_unique<cache::NphWriter>(o.output, std::move(meta), wo);
    } else if (ts.nx != nx || ts.ny != ny) {
      throw InputError(
          fmt::format("{}: timestep {} has a {}x{} grid, the earlier inputs {}x{}: one .nph file holds one grid",
                      ref.file, ref.index, ts.nx, ts.ny, nx, ny));
    } else if (!sameGrid(ts.georef, first_georef)) {
      throw InputError(
          fmt::format("{}: timestep {} is on another grid ({}, dx {}, origin {}, {}) than the earlier inputs "
                      "({}, dx {}, origin {}, {}): one .nph file holds one grid",
                      ref.file, ref.index, ts.georef.proj_definition, ts.georef.dx_m, ts.georef.x0, ts.georef.y0,
                      first_georef.proj_definition, first_georef.dx_m, first_georef.x0, first_georef.y0));
    }
    // Given up: each model field is freed once its last stage is done (issue 19, peak memory).
    ExtinctionVolumes volumes = physics::buildExtinctionVolumes(
        std::move(ts), optics, vertical, [&load](io::ModelTimestep& fields) { io::loadDeferredDetail(fields, load); });
    if (o.no_wind) {  // a smaller file that animates with the cross-fade (docs/animation.md)
      volumes.wind_u_m_per_s.clear();
      volumes.wind_v_m_per_s.clear();
    }
    ts = io::ModelTimestep{};  // release the model fields before compressing
    seconds_optics += secondsSince(t0);

    t0 = Clock::now();
    writer->append(volumes);
    seconds_write += secondsSince(t0);
    log::debug("{}[{}] {}: nz {}, max ice {:.3g} /m, water {:.3g} /m", ref.file, ref.index,
               geo::isoOrEmpty(volumes.time_utc), volumes.nz, volumes.max_ice_per_m, volumes.max_water_per_m);
  }
  t0 = Clock::now();
  writer->commit();
  seconds_write += secondsSince(t0);
  bar.update(series.size(), "done");
  bar.finish();

  const double total = secondsSince(t_start);
  const std::uintmax_t out_bytes = std::filesystem::file_size(o.output);
  log::info("{}: {} timesteps, {:.1f} MB from {:.1f} MB of input in {:.2f} s", o.output, series.size(),
            double(out_bytes) / 1e6, double(input_bytes) / 1e6, total);
  if (negative_clamped > 0 || missing_as_zero > 0) {
    log::info("inputs: {} negative values set to 0, {} fill values read as 0", negative_clamped, missing_as_zero);
  }
  if (o.stats) {
    // machine-readable, one key=value per line on stdout
    std::printf("timesteps=%zu\ninput_file_mb=%.3f\nmodel_field_mb=%.3f\noutput_mb=%.3f\n"
                "seconds_total=%.3f\nseconds_open=%.3f\nseconds_read=%.3f\nseconds_optics_resample=%.3f\n"
                "seconds_quantise_compress_write=%.3f\ninput_file_mb_per_s=%.2f\nmodel_field_mb_per_s=%.2f\n"
                "compute_model_field_mb_per_s=%.2f\npeak_rss_mb=%.1f\n",
                series.size(), double(input_bytes) / 1e6, double(model_bytes) / 1e6, double(out_bytes) / 1e6, total,
                seconds_open, seconds_load, seconds_optics, seconds_write, double(input_bytes) / 1e6 / total,
                double(model_bytes) / 1e6 / total, double(model_bytes) / 1e6 / (seconds_optics + seconds_write),
                peakResidentMb());
  }
  return kExitOk;
}

}  // namespace

void addConvertCommand(CLI::App& app, Action& run) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* sub = app.add_subcommand(
      "convert", "Convert model output into ice and water extinction volumes [1/m] (Nes 2008 eq. 5.3, §5.6)\n"
                 "on a uniform height grid (PCHIP, cropped just above the highest condensate) and write them,\n"
                 "all timesteps of all inputs in time order, into one .nph cache file (zstd, checksummed,\n"
                 "16-bit). The output appears only when the whole conversion succeeded (an existing file\n"
                 "is replaced then); on any error nothing is written and the exit status is 1.\n"
                 "Example: nephele convert wrfout_d01_* -o storm.nph --preset nes2008 --dz 250");
  sub->add_option("inputs", o->inputs,
                  "wrfout or ICON NetCDF files, ICON GRIB2 files (DWD's one file per variable, level and step, or "
                  "multi-message), folders of them or quoted patterns ('icon-d2_*.grib2'); several: one time series")
      ->required()
      ->check(existingPathOrPattern());
  sub->add_option("-o,--output", o->output, "the .nph file to write")->required();
  sub->add_option("--preset", o->preset,
                  "optics preset: default (literature radii, r_eff from number concentrations) | "
                  "nes2008 (Nes 2008 table 5.1 radii)")
      ->check(CLI::IsMember(physics::opticsPresetNames()));
  sub->add_option("--radius", o->radii,
                  "override an effective radius, CLASS=VALUE[um|mm|m], e.g. --radius snow=400um; "
                  "classes: cloud rain ice snow graupel hail (repeatable)");
  sub->add_flag("--no-number-concentrations", o->no_number_concentrations,
                "use the fixed radii even where the file has number concentrations");
  sub->add_flag("--no-wind", o->no_wind,
                "leave out U, V (about 2.5x smaller; animate then cross-fades between timesteps instead of "
                "moving them along the wind)");
  sub->add_flag("--no-icon-cloud-cover-fix", o->no_icon_cloud_cover,
                "ICON: do not raise CLC where condensate exists (Muth 2026 §3.3.1, eq. 3.1)");
  sub->add_flag("--no-icon-condensate-fix", o->no_icon_condensate,
                "ICON: do not reconstruct condensate where CLC > 0 (Muth 2026 §3.3.1)");
  sub->add_option("--dz", o->dz_m, "vertical spacing of the output grid [m] (default 250)")->check(CLI::PositiveNumber);
  sub->add_option("--z-top", o->z_top_m, "fixed top of the grid [m above MSL] instead of the crop");
  sub->add_option("--z-bottom", o->z_bottom_m,
                  "bottom of the grid [m above MSL] (default: lowest terrain, rounded down to dz)");
  sub->add_option("--crop-threshold", o->crop_threshold_per_m,
                  "extinction [1/m] below which a level counts as clear for the crop (default 1e-6)");
  sub->add_option("--zstd-level", o->zstd_level, "zstd level 1..19 (default 3)")->check(CLI::Range(1, 19));
  sub->add_flag("--progress", o->progress, "show the progress bar even when stderr is no terminal");
  sub->add_flag("--no-progress", o->no_progress, "never show the progress bar");
  sub->add_flag("--stats", o->stats,
                "print timings (NetCDF read vs optics vs compression), throughput and peak memory "
                "as key=value lines on stdout");
  sub->add_flag("--force", o->force, "replace an existing output even if it is not a .nph file");
  sub->add_option("--memory-budget-mb", o->memory_budget_mb,
                  "refuse inputs whose one timestep would need more memory (default: "
                  "NEPHELE_IO_MEMORY_BUDGET_MB or 8 GiB)");
  sub->callback([o, &run] { run = [o] { return runConvert(*o); }; });
}

}  // namespace nph::cli
