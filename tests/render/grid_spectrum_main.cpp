// nephele_grid_spectrum: what issue 13's artefact metric (grid_artefacts.h) measures on the coarse
// storm — a measurement program, not a test (docs/rendering.md "Reconstruction", "What the
// artefact metric measures").
//
// The metric sums the rendered luminance's power at 0.75 … 1.25 cycles per model column and calls
// it the grid's artefact, on the premise that the data carry nothing above ½ cycle per column. This
// program checks the premise: besides trilinear and the cubic B-spline on the 10 km grid it renders
// the *band-limited* rendition of the same data — every horizontal row upsampled 4× with a
// Lanczos-3 kernel (windowed sinc: the data's own content below ½ cycle per column, no grid kinks
// or steps) and rendered trilinearly on the 2.5 km grid — at the same view, light and steps, and
// prints the spectra of all three (and of the interpolating cubic spline,
// volume/spline_coefficients.h) and of each filter's difference from the band-limited one.
//
// With --analytic the storm is grid-free instead (dlm_scenes.h analyticStorm: smooth cells and a
// shield as functions of position, nothing at the column spacing), sampled at the 10 km cell
// centres for the two filters and at the 2.5 km centres for the reference: there the reference's
// power in the band is the picture's own, and each filter's difference from it is the filter's
// artefact alone (docs/rendering.md "A grid-free storm").
//
//   NEPHELE_GL=egl NEPHELE_LOG=warn build/tests/render/nephele_grid_spectrum [single|two_stream] [PNG_DIR] [--analytic]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <numbers>
#include <string>
#include <vector>

#include "dlm_scenes.h"
#include "grid_artefacts.h"
#include "render_scenes.h"
#include "scene/output_image.h"
#include "support/gl_fixture.h"

namespace nph::test {
namespace {

double lanczos3(double x) {
  x = std::abs(x);
  if (x < 1e-12) return 1.0;
  if (x >= 3.0) return 0.0;
  const double px = std::numbers::pi * x;
  return 3.0 * std::sin(px) * std::sin(px / 3.0) / (px * px);
}

/// `in` (nx × ny × nz, x fastest) upsampled `factor`× along x (alongX) or y with Lanczos-3, the
/// fine cells tiling the coarse ones (same faces), edges clamped, negative lobes clipped at 0.
std::vector<float> upsampleAxis(const std::vector<float>& in, int nx, int ny, int nz, int factor, bool alongX) {
  const int ox = alongX ? nx * factor : nx, oy = alongX ? ny : ny * factor, n = alongX ? nx : ny;
  std::vector<float> out(std::size_t(ox) * std::size_t(oy) * std::size_t(nz));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < oy; ++j)
      for (int i = 0; i < ox; ++i) {
        const double u = ((alongX ? i : j) + 0.5) / factor - 0.5;  // fine centre in coarse indices
        const int m0 = int(std::floor(u));
        double sum = 0.0, wsum = 0.0;
        for (int m = m0 - 2; m <= m0 + 3; ++m) {
          const double w = lanczos3(u - m);
          const int mc = std::clamp(m, 0, n - 1);
          const std::size_t src =
              alongX ? (std::size_t(k) * std::size_t(ny) + std::size_t(j)) * std::size_t(nx) + std::size_t(mc)
                     : (std::size_t(k) * std::size_t(ny) + std::size_t(mc)) * std::size_t(nx) + std::size_t(i);
          sum += w * double(in[src]);
          wsum += w;
        }
        out[(std::size_t(k) * std::size_t(oy) + std::size_t(j)) * std::size_t(ox) + std::size_t(i)] =
            float(std::max(0.0, sum / wsum));
      }
  return out;
}

ExtinctionVolumes bandLimited(const ExtinctionVolumes& v, int f) {
  ExtinctionVolumes o = v;
  o.nx = v.nx * f;
  o.ny = v.ny * f;
  o.georef = refinedGeoreference(v.georef, f);
  auto up = [&](const std::vector<float>& a, int nz) {
    return a.empty() ? a : upsampleAxis(upsampleAxis(a, v.nx, v.ny, nz, f, true), v.nx * f, v.ny, nz, f, false);
  };
  o.ice_per_m = up(v.ice_per_m, v.nz);
  o.water_per_m = up(v.water_per_m, v.nz);
  o.terrain_height_m = up(v.terrain_height_m, 1);
  o.tke_m2_per_s2.clear();
  o.cloud_fraction.clear();
  o.wind_w_m_per_s.clear();
  o.updateMaxima();
  return o;
}

int run(lighting::MultipleScattering ms, const char* png_dir, bool analytic) {
  glContext().makeCurrent();
  const ExtinctionVolumes storm = coarseStorm();
  const ExtinctionVolumes v = analytic ? analyticStorm(storm) : storm;
  const ExtinctionVolumes fine = analytic ? analyticStorm(storm, 4) : bandLimited(v, 4);
  const std::string prefix = analytic ? "grid-spectrum-analytic-" : "grid-spectrum-";
  // The test's view (ReconstructionTest.CubicLowersTheGridArtefactsOfTheCoarseStorm): the demo's
  // direction at half its distance, 640 × 360, quarter-voxel steps, DLM texels of ¼ column, no
  // jitter; the ground a plane (the island's terrain is not under test).
  const DemoView d = demoView(v, 640, 360, 0.5), df = demoView(fine, 640, 360, 0.5);
  const double zMid_m = d.frame.min_m().z + 0.5 * d.frame.size_m().z;
  render::RenderSettings rs;
  rs.jitter = false;
  rs.step_voxels = 0.25;
  rs.multiple_scattering = ms;
  rs.terrain = false;
  using volume::Reconstruction;
  const auto tri = renderDemoView(v, d, rs, Reconstruction::Trilinear, volume::Detail::None, 0.25).cloud_layer;
  const auto cub = renderDemoView(v, d, rs, Reconstruction::Cubic, volume::Detail::None, 0.25).cloud_layer;
  const auto ref = renderDemoView(fine, df, rs, Reconstruction::Trilinear, volume::Detail::None, 1.0).cloud_layer;
  const auto itp = renderDemoView(v, d, rs, Reconstruction::CubicInterpolating, volume::Detail::None, 0.25).cloud_layer;
  if (png_dir != nullptr) {  // the three cloud layers, for looking at (default exposure)
    scene::ImageOutputOptions o;
    o.exposure_ev = scene::kDefaultExposureEv;
    const std::string dir(png_dir);
    scene::writePng(tri, dir + "/" + prefix + "trilinear.png", o);
    scene::writePng(cub, dir + "/" + prefix + "cubic.png", o);
    scene::writePng(itp, dir + "/" + prefix + "interpolating.png", o);
    scene::writePng(ref, dir + "/" + prefix + (analytic ? "fine.png" : "band-limited.png"), o);
  }
  std::vector<double> f;
  for (int k = 0; k <= 24; ++k) f.push_back(0.3 + 0.1 * k);
  // Every spectrum in the coarse grid's columns (the band-limited field's frame has the same faces).
  auto spectrum = [&](const scene::RgbaImage& l) { return gridPowerSpectrum(l, d.camera, d.frame, zMid_m, f); };
  const auto sTri = spectrum(tri), sCub = spectrum(cub), sRef = spectrum(ref);
  const auto dTri = spectrum(layerMinus(tri, ref)), dCub = spectrum(layerMinus(cub, ref));
  const auto sItp = spectrum(itp), dItp = spectrum(layerMinus(itp, ref));
  std::printf("%s storm %dx%dx%d at %.0f km, %s rendition %dx%d at %.1f km; light model %s\n",
              analytic ? "grid-free" : "coarse", v.nx, v.ny, v.nz, v.georef.dx_m / 1000.0,
              analytic ? "fine analytic" : "band-limited", fine.nx, fine.ny, fine.georef.dx_m / 1000.0,
              ms == lighting::MultipleScattering::Single ? "single" : "two_stream");
  std::printf(
      "| cycles per column | trilinear | cubic | interpolating cubic | reference | trilinear − ref | cubic − ref | "
      "interpolating − ref |\n| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (std::size_t k = 0; k < f.size(); ++k)
    std::printf("| %.1f | %.4g | %.4g | %.4g | %.4g | %.4g | %.4g | %.4g |\n", f[k], sTri[k], sCub[k], sItp[k], sRef[k],
                dTri[k], dCub[k], dItp[k]);
  auto band = [&](const std::vector<double>& s, double lo, double hi) {
    double p = 0.0;
    for (std::size_t k = 0; k < f.size(); ++k)
      if (f[k] >= lo - 1e-9 && f[k] <= hi + 1e-9) p += s[k];
    return p;
  };
  std::printf("band 0.8 … 1.2: trilinear %.4g, cubic %.4g, band-limited %.4g (trilinear / band-limited %.2f); "
              "difference from band-limited: trilinear %.4g, cubic %.4g (ratio %.2f)\n",
              band(sTri, 0.8, 1.2), band(sCub, 0.8, 1.2), band(sRef, 0.8, 1.2),
              band(sTri, 0.8, 1.2) / band(sRef, 0.8, 1.2), band(dTri, 0.8, 1.2), band(dCub, 0.8, 1.2),
              band(dTri, 0.8, 1.2) / band(dCub, 0.8, 1.2));
  for (const auto& [lo, hi] : {std::pair{0.3, 0.7}, std::pair{0.8, 1.2}, std::pair{1.8, 2.2}})
    std::printf("difference from the reference at %.1f … %.1f: trilinear %.4g, cubic %.4g, interpolating cubic %.4g\n",
                lo, hi, band(dTri, lo, hi), band(dCub, lo, hi), band(dItp, lo, hi));
  return 0;
}

}  // namespace
}  // namespace nph::test

int main(int argc, char** argv) {
  try {
    bool analytic = false, single = false;
    std::vector<const char*> positional;
    for (int i = 1; i < argc; ++i) {
      if (std::strcmp(argv[i], "--analytic") == 0) analytic = true;
      else positional.push_back(argv[i]);
    }
    single = !positional.empty() && std::strcmp(positional[0], "single") == 0;
    if (positional.size() > 2 || (!positional.empty() && !single && std::strcmp(positional[0], "two_stream") != 0)) {
      std::fprintf(stderr,
                   "usage: %s [single|two_stream] [PNG_DIR] [--analytic]\n"
                   "  default two_stream; PNG_DIR: write the layers; --analytic: the grid-free storm\n",
                   argv[0]);
      return 2;
    }
    return nph::test::run(
        single ? nph::lighting::MultipleScattering::Single : nph::lighting::MultipleScattering::TwoStream,
        positional.size() > 1 ? positional[1] : nullptr, analytic);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nephele_grid_spectrum: %s\n", e.what());
    return 1;
  }
}
