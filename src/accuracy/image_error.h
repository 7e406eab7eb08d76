#pragma once
// Error of a rendered cloud layer against a reference image (issue 6). Both are premultiplied
// linear RGBA (row 0 at the top); the errors are those of what a viewer sees of the layer over
// black, i.e. of its premultiplied colour:
//   luminance        Y = 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709 / sRGB primaries)
//   rmse             √ mean (Y − Y_ref)²
//   rel_mse          mean (Y − Y_ref)² / (Y_ref² + 0.01)   (Rousselle et al. 2011's relMSE; the
//                    0.01 keeps near-black pixels from dominating)
//   mean_abs, max_abs  mean and max |Y − Y_ref|
//   share_off_2_255  share of pixels where any channel differs by more than 2/255 after the
//                    display transform of scene/output_image.h (ACES fitted curve, sRGB encode)
//   alpha_max_abs    max |α − α_ref| (coverage)
//   ref_noise_rmse   √ mean σ²(Y_ref) when the reference carries a per-pixel standard error (the
//                    path tracer's): the floor below which rmse says nothing
//   luminance_bias   Σ Y / Σ Y_ref − 1: the mean brightness of the layer against the reference
//                    (issue 12: "mean cloud-layer luminance within ±5 %")
//   rel_mse_noise    mean σ²(Y_ref) / (Y_ref² + 0.01): what the reference's own noise adds to
//                    rel_mse in expectation (zero-mean noise adds its variance to every squared
//                    difference), so rel_mse − rel_mse_noise estimates the relMSE against the
//                    converged reference (with the noisy Y_ref in the denominator)
#include <vector>

#include "scene/output_image.h"

namespace nph::accuracy {

struct ImageError {
  double rmse = 0.0;
  double rel_mse = 0.0;
  double mean_abs = 0.0;
  double max_abs = 0.0;
  double share_off_2_255 = 0.0;
  double alpha_max_abs = 0.0;
  double ref_noise_rmse = 0.0;
  double luminance_bias = 0.0;
  double rel_mse_noise = 0.0;
};

/// `reference_standard_error`: empty, or 3 floats per pixel (RGB standard error of the mean).
ImageError compareImages(const scene::RgbaImage& image, const scene::RgbaImage& reference,
                         const std::vector<float>& reference_standard_error = {});

double luminance(double r, double g, double b);

/// √ mean σ²(Y) of a per-pixel RGB standard error (3 floats per pixel), σ(Y) taken as the
/// luminance of the channel errors (the bound for perfectly correlated channels, which one path's
/// RGB are): the ground truth's own noise.
double luminanceNoiseRmse(const std::vector<float>& standard_error);

}  // namespace nph::accuracy
