#pragma once
// Summary of a sweep: per variant, the mean over the scenes of its time (DLM build + ray cast)
// and of its errors; the Pareto front of time against RMSE vs the ground truth (no other variant
// is both faster and more accurate); and the plot.
#include <string>
#include <vector>

#include "accuracy/accuracy_sweep.h"

namespace nph::accuracy {

struct VariantSummary {
  std::string knob, value;
  double total_ms = 0.0, dlm_ms = 0.0, raycast_ms = 0.0;
  double rmse_truth = 0.0, rel_mse_truth = 0.0, share_off_truth = 0.0;
  double rmse_reference = 0.0, share_off_reference = 0.0;
  bool pareto = false;
};

std::vector<VariantSummary> summarise(const std::vector<SweepRow>& rows);
/// Marks `pareto` on the variants of the front (time vs rmse_truth).
void markParetoFront(std::vector<VariantSummary>& summary);
void writeSummaryCsv(const std::vector<VariantSummary>& summary, const std::string& path);
/// A Markdown table of the summary (docs/accuracy.md).
std::string summaryMarkdown(const std::vector<VariantSummary>& summary);
/// Writes <stem>.gp and the data it plots, and runs gnuplot (Debian gnuplot-nox) to make
/// <stem>.png: RMSE vs ground truth and vs the CPU reference against time, front highlighted.
/// Returns false (and logs why) when gnuplot is missing or fails; the CSVs stand on their own.
bool plotSummary(const std::vector<VariantSummary>& summary, const std::string& stem);

}  // namespace nph::accuracy
