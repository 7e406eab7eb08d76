#include "accuracy/pareto.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/process.h"

namespace nph::accuracy {

std::vector<VariantSummary> summarise(const std::vector<SweepRow>& rows) {
  std::vector<VariantSummary> out;
  std::vector<int> counts;
  for (const SweepRow& r : rows) {
    auto it = std::find_if(out.begin(), out.end(),
                           [&](const VariantSummary& s) { return s.knob == r.knob && s.value == r.value; });
    if (it == out.end()) {
      out.push_back({r.knob, r.value});
      counts.push_back(0);
      it = out.end() - 1;
    }
    VariantSummary& s = *it;
    counts[std::size_t(it - out.begin())] += 1;
    s.dlm_ms += r.dlm_ms;
    s.raycast_ms += r.raycast_ms;
    s.rmse_truth += r.vs_truth.rmse;
    s.rel_mse_truth += r.vs_truth.rel_mse;
    s.share_off_truth += r.vs_truth.share_off_2_255;
    s.rmse_reference += r.vs_reference.rmse;
    s.share_off_reference += r.vs_reference.share_off_2_255;
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    VariantSummary& s = out[i];
    const double n = double(counts[i]);
    s.dlm_ms /= n;
    s.raycast_ms /= n;
    s.total_ms = s.dlm_ms + s.raycast_ms;
    s.rmse_truth /= n;
    s.rel_mse_truth /= n;
    s.share_off_truth /= n;
    s.rmse_reference /= n;
    s.share_off_reference /= n;
  }
  markParetoFront(out);
  return out;
}

void markParetoFront(std::vector<VariantSummary>& s) {
  // On the front: no other variant is at least as fast and at least as accurate, and better in one.
  for (VariantSummary& a : s) {
    a.pareto = std::none_of(s.begin(), s.end(), [&](const VariantSummary& b) {
      return b.total_ms <= a.total_ms && b.rmse_truth <= a.rmse_truth &&
             (b.total_ms < a.total_ms || b.rmse_truth < a.rmse_truth);
    });
  }
}

void writeSummaryCsv(const std::vector<VariantSummary>& summary, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw IoError(path + ": cannot write");
  out << "knob,value,dlm_ms,raycast_ms,total_ms,truth_rmse,truth_rel_mse,truth_share_off_2_255,ref_rmse,"
         "ref_share_off_2_255,pareto\n";
  for (const VariantSummary& s : summary) {
    out << fmt::format("{},{},{:.3f},{:.3f},{:.3f},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{}\n", s.knob, s.value, s.dlm_ms,
                       s.raycast_ms, s.total_ms, s.rmse_truth, s.rel_mse_truth, s.share_off_truth, s.rmse_reference,
                       s.share_off_reference, s.pareto ? 1 : 0);
  }
}

std::string summaryMarkdown(const std::vector<VariantSummary>& summary) {
  std::string md =
      "| knob | value | DLM ms | ray cast ms | total ms | RMSE vs truth | relMSE vs truth | > 2/255 vs truth | RMSE vs "
      "CPU ref | "
      "> 2/255 vs CPU ref | front |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | :---: |\n";
  for (const VariantSummary& s : summary) {
    md += fmt::format("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.4f} | {:.4f} | {:.1f} % | {:.2e} | {:.2f} % | {} |\n",
                      s.knob, s.value, s.dlm_ms, s.raycast_ms, s.total_ms, s.rmse_truth, s.rel_mse_truth,
                      100.0 * s.share_off_truth, s.rmse_reference, 100.0 * s.share_off_reference, s.pareto ? "●" : "");
  }
  return md;
}

bool plotSummary(const std::vector<VariantSummary>& summary, const std::string& stem) {
  const std::string dat = stem + ".dat", gp = stem + ".gp", png = stem + ".png";
  {
    std::ofstream d(dat);
    d << "# total_ms rmse_truth rmse_reference pareto label\n";
    for (const VariantSummary& s : summary) {
      d << fmt::format("{:.3f} {:.6g} {:.6g} {} \"{}\"\n", s.total_ms, s.rmse_truth, std::max(s.rmse_reference, 1e-9),
                       s.pareto ? 1 : 0, s.knob == "default" ? "default" : s.knob + "=" + s.value);
    }
    std::ofstream f(stem + "-front.dat");
    std::vector<VariantSummary> front;
    for (const VariantSummary& s : summary)
      if (s.pareto) front.push_back(s);
    std::sort(front.begin(), front.end(), [](const auto& a, const auto& b) { return a.total_ms < b.total_ms; });
    for (const VariantSummary& s : front) f << fmt::format("{:.3f} {:.6g}\n", s.total_ms, s.rmse_truth);
  }
  {
    std::ofstream g(gp);
    g << "# nephele-bench accuracy: error against time (mean over the standard scenes)\n"
         "set terminal pngcairo size 1400,620 font 'DejaVu Sans,10'\n"
         "set output "
      << process::gnuplotQuoted(png)
      << "\n"
         "set multiplot layout 1,2\n"
         "set logscale x\nset logscale y\nset grid\nset key top right\n"
         "set xlabel 'GPU time per frame: DLM build + ray cast [ms, llvmpipe]'\n"
         "set ylabel 'RMSE of luminance vs path-traced ground truth'\n"
         "set title 'Model bias + discretisation (vs ground truth)'\n"
         "plot "
      << process::gnuplotQuoted(dat)
      << " using 1:2 with points pt 7 ps 1.2 lc rgb '#4477aa' title 'variants', \\\n"
         "     "
      << process::gnuplotQuoted(stem + "-front.dat")
      << " using 1:2 with linespoints lw 2 pt 6 ps 2 lc rgb '#cc3311' title 'Pareto front', \\\n"
         "     "
      << process::gnuplotQuoted(dat)
      << " using 1:2:5 with labels font ',7' offset 0.5,0.5 left notitle\n"
         "set ylabel 'RMSE of luminance vs CPU reference (same DLM)'\n"
         "set title 'Discretisation + float (vs CPU reference of the same approximation)'\n"
         "plot "
      << process::gnuplotQuoted(dat)
      << " using 1:3 with points pt 7 ps 1.2 lc rgb '#228833' title 'variants', \\\n"
         "     "
      << process::gnuplotQuoted(dat)
      << " using 1:3:5 with labels font ',7' offset 0.5,0.5 left notitle\n"
         "unset multiplot\n";
  }
  // No shell: the paths come from --out and may hold any character (issue #18).
  const int rc = process::run({process::toolPath("NEPHELE_GNUPLOT", "gnuplot"), gp});
  if (rc != 0) {
    log::warn("gnuplot failed or is missing (exit {}): no {} (install Debian gnuplot-nox; the CSVs are complete)", rc,
              png);
    return false;
  }
  return true;
}

}  // namespace nph::accuracy
