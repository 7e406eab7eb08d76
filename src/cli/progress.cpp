#include "cli/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace nph::cli {

ProgressBar::ProgressBar(std::size_t total, bool enabled)
    : total_(total), enabled_(enabled), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

bool ProgressBar::stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

void ProgressBar::update(std::size_t done, const std::string& label) {
  if (!enabled_) return;
  constexpr std::size_t kWidth = 30;
  const std::size_t filled = total_ == 0 ? kWidth : std::min(kWidth, done * kWidth / total_);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string eta;
  if (done > 0 && done < total_) {
    eta = fmt::format(" ~{:.0f} s left", seconds / double(done) * double(total_ - done));
  }
  std::fputs(fmt::format("\r[{}{}] {}/{} {}{}\033[K", std::string(filled, '#'), std::string(kWidth - filled, '.'), done,
                         total_, label, eta)
                 .c_str(),
             stderr);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (drawn_) {
    std::fputs("\n", stderr);
    std::fflush(stderr);
    drawn_ = false;
  }
}

}  // namespace nph::cli
