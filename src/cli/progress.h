#pragma once
// A one-line progress bar on stderr ("[#####.....] 3/6 label"), redrawn with '\r'. Drawn only
// when enabled (by default: stderr is a terminal), so logs and pipes stay clean.
#include <chrono>
#include <cstddef>
#include <string>

namespace nph::cli {

class ProgressBar {
 public:
  ProgressBar(std::size_t total, bool enabled);
  ~ProgressBar();  ///< ends the line if one was drawn
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void update(std::size_t done, const std::string& label);
  void finish();

  /// true when stderr is a terminal.
  static bool stderrIsTerminal();

 private:
  std::size_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace nph::cli
