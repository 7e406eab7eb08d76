#pragma once
// Shared pieces of the fuzz targets (issue 18 item 7): what counts as a finding, and a scratch
// file for parsers that take a path.
//
// A target feeds one input to a parser of untrusted data. The parser may refuse it with the
// errors a user sees (nph::InputError naming the file and field, nph::UsageError for a scene
// that asks for something impossible, nph::IoError); those are correct outcomes. Anything else
// is a finding and aborts the process so libFuzzer (or the replay driver) stops with the input:
// another exception type (std::bad_alloc, std::length_error, "vector too long", a bare
// std::runtime_error from a third-party parser), an error message that does not name the input,
// a crash, or what ASan/UBSan report in the sanitizer build.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/error.h"

namespace nph::fuzz {

[[noreturn]] inline void finding(std::string_view what, std::string_view message) {
  std::fprintf(stderr, "fuzz finding: %.*s: %.*s\n", int(what.size()), what.data(), int(message.size()),
               message.data());
  std::abort();
}

/// Runs `parse`; a user-facing refusal is fine if its message names `name` (the input's file
/// name or scene name), anything else is a finding.
template <class F>
void expectCleanOutcome(const std::string& name, F&& parse) {
  try {
    parse();
  } catch (const nph::InputError& e) {
    if (std::string_view(e.what()).find(name) == std::string_view::npos)
      finding("InputError without the file name", e.what());
  } catch (const nph::UsageError& e) {
    if (std::string_view(e.what()).find(name) == std::string_view::npos)
      finding("UsageError without the file name", e.what());
  } catch (const nph::IoError& e) {
    if (std::string_view(e.what()).find(name) == std::string_view::npos)
      finding("IoError without the file name", e.what());
  } catch (const std::exception& e) {
    finding("unexpected exception type", e.what());
  } catch (...) {
    finding("non-standard exception", "");
  }
}

/// A file in $TMPDIR (or /tmp) named `stem`-PID`suffix` holding the input, removed when destroyed.
class ScratchInput {
 public:
  ScratchInput(const std::uint8_t* data, std::size_t size, const std::string& stem, const std::string& suffix) {
    const char* tmp = std::getenv("TMPDIR");
    path_ = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") / (stem + "-" + std::to_string(::getpid()) + suffix);
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (f == nullptr) finding("cannot write the scratch input", path_.string());
    if (size > 0 && std::fwrite(data, 1, size, f) != size) finding("short write of the scratch input", path_.string());
    std::fclose(f);
  }
  ~ScratchInput() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  ScratchInput(const ScratchInput&) = delete;
  ScratchInput& operator=(const ScratchInput&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace nph::fuzz
