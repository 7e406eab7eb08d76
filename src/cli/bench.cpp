// `nephele-bench accuracy`: run time against error of every quality knob (issue 6; the sweep is
// src/accuracy/accuracy_sweep.h, its output is described in docs/accuracy.md).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "accuracy/accuracy_sweep.h"
#include "accuracy/decompose.h"
#include "accuracy/ms_fit.h"
#include "accuracy/octave_fit.h"
#include "accuracy/pareto.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/log.h"
#include "render/gl/context.h"

namespace nph::cli {
namespace {

struct BenchAccuracyOptions {
  accuracy::SweepOptions sweep;
  std::string gl = "auto";
  int spp = 0;
  bool fit_octaves = false;
  bool compare_ms = false;
  bool decompose = false;
  int decompose_spp = 4;
};

int runBenchAccuracy(BenchAccuracyOptions o) {
  accuracy::SweepOptions& s = o.sweep;
  if (s.quick) {
    s.width = std::min(s.width, 48);
    s.height = std::min(s.height, 27);
    s.runs = std::min(s.runs, 1);
    s.ground_truth.samples_per_pixel = 8;
    s.ground_truth.max_events = 2000;
    s.ground_truth.roulette_after_events = 100;
    s.mc_photons = std::min<std::uint64_t>(s.mc_photons, 4096);
  }
  if (o.spp > 0) s.ground_truth.samples_per_pixel = o.spp;
  std::filesystem::create_directories(s.out_dir);
  const auto ctx = gl::createHeadlessContext(o.gl);
  if (o.compare_ms) {
    const std::string md = accuracy::msComparisonMarkdown(accuracy::compareMultipleScattering(s));
    std::ofstream((std::filesystem::path(s.out_dir) / "ms-comparison.md").string()) << md;
    std::fputs(md.c_str(), stdout);
    log::info("wrote {}/ms-comparison.md", s.out_dir);
    return kExitOk;
  }
  if (o.decompose) {
    const std::string md = accuracy::decompositionMarkdown(accuracy::decomposeBias(s, o.decompose_spp));
    std::ofstream((std::filesystem::path(s.out_dir) / "bias-decomposition.md").string()) << md;
    std::fputs(md.c_str(), stdout);
    log::info("wrote {}/bias-decomposition.md", s.out_dir);
    return kExitOk;
  }
  if (o.fit_octaves) {
    const accuracy::OctaveFitResult fit = accuracy::fitOctaveSeries(s);
    const std::string md = accuracy::octaveFitMarkdown(fit);
    std::ofstream((std::filesystem::path(s.out_dir) / "octave-fit.md").string()) << md;
    std::fputs(md.c_str(), stdout);
    log::info("wrote {}/octave-fit.md", s.out_dir);
    return kExitOk;
  }

  const std::vector<accuracy::SweepRow> rows = accuracy::runSweep(s);
  if (rows.empty()) throw UsageError("accuracy: no scene matches --scenes " + s.scene_filter);
  const std::filesystem::path dir(s.out_dir);
  accuracy::writeCsv(rows, (dir / "accuracy.csv").string());
  auto summary = accuracy::summarise(rows);
  accuracy::writeSummaryCsv(summary, (dir / "accuracy-summary.csv").string());
  std::ofstream((dir / "accuracy-summary.md").string()) << accuracy::summaryMarkdown(summary);
  const bool plotted = accuracy::plotSummary(summary, (dir / "accuracy").string());
  log::info("wrote {}/accuracy.csv, accuracy-summary.csv, accuracy-summary.md{}", s.out_dir,
            plotted ? ", accuracy.png" : "");
  return kExitOk;
}

}  // namespace

void addBenchAccuracyCommand(CLI::App& app, Action& run) {
  auto o = std::make_shared<BenchAccuracyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "accuracy", "Run time against error: the standard scenes (hurricane above/oblique, stratus, cumulus, cirrus; sun "
                  "high, low, behind the camera) rendered on the GPU with each quality knob swept around the default "
                  "and the presets; error vs a cached path-traced ground truth and vs the CPU reference of the same "
                  "approximation. Writes accuracy.csv, accuracy-summary.csv/.md and accuracy.png (gnuplot) to --out.");
  cmd->add_option("-o,--out", o->sweep.out_dir, "output folder")->capture_default_str();
  cmd->add_option("--cache", o->sweep.cache_dir, "ground-truth cache folder (default OUT/ground-truth)");
  cmd->add_flag("--quick", o->sweep.quick, "tiny scenes, 48x27, 1 run, 8 spp, two values a knob (tests)");
  cmd->add_option("--runs", o->sweep.runs, "timed runs per setting (median)")->capture_default_str();
  cmd->add_option("--width", o->sweep.width, "image width")->capture_default_str();
  cmd->add_option("--height", o->sweep.height, "image height")->capture_default_str();
  cmd->add_option("--spp", o->spp, "path-tracer samples per pixel (default 256; quick 8)");
  cmd->add_option("--max-events", o->sweep.ground_truth.max_events,
                  "path-tracer collisions per path before it is cut (counted)")
      ->capture_default_str();
  cmd->add_option("--roulette-after", o->sweep.ground_truth.roulette_after_events,
                  "path tracer: unbiased Russian roulette past this many collisions (0 = off)")
      ->capture_default_str();
  cmd->add_option("--scenes", o->sweep.scene_filter, "only scenes whose name contains this");
  cmd->add_option("--knobs", o->sweep.knob_filter,
                  "only settings whose knob name contains this (default, step_voxels, dlm_texel_voxels, "
                  "dlm_step_voxels, dlm_step_growth_max, epsilon, multiple_scattering, scatter_downsample, "
                  "forward_angle_deg, preset)");
  cmd->add_flag("--fit-octaves", o->fit_octaves,
                "instead of the sweep: fit the multiple-scattering octave series (a, b, c, N) to the path-traced "
                "truth on the CPU reference and write octave-fit.md (issue 12)");
  cmd->add_flag("--compare-ms", o->compare_ms,
                "instead of the sweep: compare the multiple-scattering terms (octaves, two-stream, octave weights by "
                "column depth) against the path-traced truth on the CPU reference, fitting their free weights, and "
                "write ms-comparison.md (issue 12)");
  cmd->add_flag("--decompose", o->decompose,
                "instead of the sweep: split the truth and the renderer into sky light, sunlight of order 1 and "
                "orders >= 2 and compare them part by part (mean luminance), write bias-decomposition.md (issue 12)");
  cmd->add_option("--decompose-spp", o->decompose_spp,
                  "--decompose: samples per pixel of the truth's parts (their image means need few)")
      ->capture_default_str()
      ->check(CLI::Range(1, 65536));
  cmd->add_option("--reference-dlm-texel", o->sweep.reference_dlm_texel_voxels,
                  "--decompose: texel size of the converged CPU deep light maps, in voxels")
      ->capture_default_str()
      ->check(CLI::Range(0.0625, 8.0));
  cmd->add_option("--ms-diffusion-coarsen", o->sweep.diffusion_coarsen_xy,
                  "--compare-ms: fine voxels per cell of the coarse diffusion volume, horizontally")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--ms-diffusion-coarsen-z", o->sweep.diffusion_coarsen_z,
                  "--compare-ms: fine voxels per cell of the coarse diffusion volume, vertically")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--ms-diffusion-min-resistance", o->sweep.diffusion_min_resistance,
                  "--compare-ms: floor of the diffusion volume's face resistance (clear air)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1e3));
  cmd->add_option("--ms-diffusion-flux-limited", o->sweep.diffusion_flux_limited_passes,
                  "--compare-ms: passes of flux-limited diffusion (Levermore-Pomraning) after the linear solve")
      ->capture_default_str()
      ->check(CLI::Range(0, 50));
  cmd->add_option("--ms-mc-photons", o->sweep.mc_photons,
                  "--compare-ms: photons per scene of the Monte Carlo radiance volume (quick: 4096)")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 30));
  cmd->add_option("--ms-mc-coarsen", o->sweep.mc_coarsen_xy,
                  "--compare-ms: fine voxels per cell of the Monte Carlo volume's first tally, horizontally")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--ms-mc-coarsen-z", o->sweep.mc_coarsen_z,
                  "--compare-ms: fine voxels per cell of the Monte Carlo volume's first tally, vertically")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--ms-mc-subdivide-z", o->sweep.mc_subdivide_z,
                  "--compare-ms: cells per coarse layer of the Monte Carlo volume's first tally (finer than a voxel)")
      ->capture_default_str()
      ->check(CLI::Range(1, 16));
  cmd->add_flag("--images", o->sweep.write_images, "also write PNGs of the ground truth and every variant");
  cmd->add_option("--gl", o->gl, "OpenGL backend: auto (EGL, then OSMesa), egl, osmesa")->capture_default_str();
  cmd->callback([o, &run] { run = [o] { return runBenchAccuracy(*o); }; });
}

}  // namespace nph::cli
