// A bounded, deterministic mutation campaign without libFuzzer (issue 18 item 7), so that the
// normal build (gcc, `make test`, CI) fuzzes too: `nephele_fuzz_mutate_<target> -seed=S -runs=N
// FILE|FOLDER...` feeds N mutants of the given inputs to the target's LLVMFuzzerTestOneInput.
// Every mutant is a pure function of the seed, the run number and the sorted inputs, so a run
// gives the same mutants on every machine, and a finding is reproduced by running the same
// command again.
//
// What it is not: libFuzzer. The libraries are not instrumented for coverage in the normal build
// (gcc has no -fsanitize=fuzzer), so nothing steers the mutations towards new branches; they are
// libFuzzer's blind operators (bit flips, interesting integers in both byte orders, erased,
// duplicated and spliced ranges, and, for text, numbers replaced by extreme ones) stacked 1–4 per
// run. The coverage-guided campaign is `make fuzz` (clang, ASan + UBSan; docs/reliability.md).
//
// A finding (fuzz_support.h: an unexpected exception, a message without the file name, a crash)
// aborts; the SIGABRT/SIGSEGV/SIGBUS/SIGFPE handler first writes the mutant to
// `fuzz-mutant-<run>` in the current folder and prints its name, so it can go into
// tests/fuzz/corpus/<target>/ as a regression case.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "input_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

// The mutant being run and its name, for the signal handler (which may only call
// async-signal-safe functions: open, write, close).
const Bytes* g_current = nullptr;
char g_artifact[64] = "";

extern "C" void saveMutantAndDie(int sig) {
  if (g_current != nullptr) {
    const int fd = ::open(g_artifact, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      std::size_t done = 0;
      while (done < g_current->size()) {
        const ssize_t w = ::write(fd, g_current->data() + done, g_current->size() - done);
        if (w <= 0) break;
        done += std::size_t(w);
      }
      ::close(fd);
    }
    static const char kMsg[] = "fuzz mutate: the mutant is saved as ";
    (void)!::write(2, kMsg, sizeof kMsg - 1);
    (void)!::write(2, g_artifact, std::strlen(g_artifact));
    (void)!::write(2, "\n", 1);
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// libFuzzer's "interesting values" (FuzzerDictionary / MutationDispatcher::Mutate_ChangeBinaryInteger).
constexpr std::array<std::uint64_t, 12> kInteresting{
    0, 1, 0x7f, 0x80, 0xff, 0x7fff, 0xffff, 0x7fffffff, 0x80000000, 0xffffffff, 0x40000000, ~std::uint64_t(0)};
constexpr std::array<std::string_view, 12> kNumbers{
    "0", "-1", "1e308", "-1e308", "1e-320", "NaN", "1e20", "2147483648", "4294967296", "-2147483649", "65536", "1e999"};

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  Bytes mutate(const std::vector<Bytes>& inputs, std::size_t maxLen) {
    Bytes b = inputs[pick(inputs.size())];
    const int count = 1 + int(pick(4));
    for (int m = 0; m < count; ++m) once(b, inputs, maxLen);
    if (b.size() > maxLen) b.resize(maxLen);
    return b;
  }

 private:
  std::size_t pick(std::size_t n) { return n == 0 ? 0 : std::size_t(rng_() % n); }

  void once(Bytes& b, const std::vector<Bytes>& inputs, std::size_t maxLen) {
    switch (pick(b.empty() ? 1 : 8)) {
      case 0: {  // insert 1–8 random bytes (the only operator for an empty input)
        const std::size_t at = pick(b.size() + 1), n = 1 + pick(8);
        Bytes ins(n);
        for (auto& x : ins) x = std::uint8_t(rng_());
        b.insert(b.begin() + std::ptrdiff_t(at), ins.begin(), ins.end());
        break;
      }
      case 1:  // flip a bit
        b[pick(b.size())] ^= std::uint8_t(1u << pick(8));
        break;
      case 2:  // a byte to a random value
        b[pick(b.size())] = std::uint8_t(rng_());
        break;
      case 3: {  // an interesting 1/2/4/8-byte integer, big- or little-endian (NetCDF is big-endian)
        const std::size_t width = std::size_t(1) << pick(4);
        if (b.size() < width) break;
        const std::size_t at = pick(b.size() - width + 1);
        const std::uint64_t v = kInteresting[pick(kInteresting.size())];
        const bool big = pick(2) == 0;
        for (std::size_t i = 0; i < width; ++i) {
          const std::size_t shift = 8 * (big ? width - 1 - i : i);
          b[at + i] = std::uint8_t(shift < 64 ? v >> shift : 0);
        }
        break;
      }
      case 4: {  // erase a range (up to 1/8 of the input, at least one byte)
        const std::size_t at = pick(b.size()), n = 1 + pick(std::max<std::size_t>(1, b.size() / 8));
        b.erase(b.begin() + std::ptrdiff_t(at), b.begin() + std::ptrdiff_t(std::min(b.size(), at + n)));
        break;
      }
      case 5: {  // duplicate a range of up to 64 bytes somewhere else
        const std::size_t from = pick(b.size()), n = std::min(b.size() - from, 1 + pick(64));
        const Bytes piece(b.begin() + std::ptrdiff_t(from), b.begin() + std::ptrdiff_t(from + n));
        if (b.size() + n > maxLen) break;
        b.insert(b.begin() + std::ptrdiff_t(pick(b.size() + 1)), piece.begin(), piece.end());
        break;
      }
      case 6: {  // splice: this input's head and another input's tail
        const Bytes& other = inputs[pick(inputs.size())];
        if (other.empty()) break;
        const std::size_t cut = pick(b.size() + 1), from = pick(other.size());
        b.resize(cut);
        b.insert(b.end(), other.begin() + std::ptrdiff_t(from), other.end());
        break;
      }
      default: {  // text: the digits at a random position become an extreme number
        const std::size_t start = pick(b.size());
        std::size_t i = start;
        while (i < b.size() && !(b[i] >= '0' && b[i] <= '9')) ++i;
        if (i == b.size()) {  // no digit after it: flip a bit instead
          b[start] ^= std::uint8_t(1u << pick(8));
          break;
        }
        std::size_t j = i;
        while (j < b.size() && ((b[j] >= '0' && b[j] <= '9') || b[j] == '.' || b[j] == 'e' || b[j] == '-')) ++j;
        const std::string_view n = kNumbers[pick(kNumbers.size())];
        b.erase(b.begin() + std::ptrdiff_t(i), b.begin() + std::ptrdiff_t(j));
        b.insert(b.begin() + std::ptrdiff_t(i), n.begin(), n.end());
        break;
      }
    }
  }

  std::mt19937_64 rng_;
};

bool numberFlag(std::string_view arg, std::string_view name, std::uint64_t& value) {
  if (arg.substr(0, name.size()) != name) return false;
  const std::string digits(arg.substr(name.size()));
  char* end = nullptr;
  value = std::strtoull(digits.c_str(), &end, 10);
  if (digits.empty() || *end != '\0') {
    std::fprintf(stderr, "fuzz mutate: %.*s wants a whole number, got '%s'\n", int(name.size()), name.data(),
                 digits.c_str());
    std::exit(2);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t seed = 1, runs = 1000, maxLen = 1 << 20;
  std::vector<std::filesystem::path> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    if (numberFlag(a, "-seed=", seed) || numberFlag(a, "-runs=", runs) || numberFlag(a, "-max_len=", maxLen)) continue;
    if (!nph::fuzz::addInputs(argv[i], paths)) {
      std::fprintf(stderr, "fuzz mutate: %s is neither a flag, a file nor a folder\n", argv[i]);
      return 2;
    }
  }
  if (paths.empty()) {
    std::fprintf(stderr, "usage: %s [-seed=N] [-runs=N] [-max_len=BYTES] FILE|FOLDER...\n", argv[0]);
    return 2;
  }
  std::sort(paths.begin(), paths.end());  // the mutants depend on the inputs' order: make it fixed
  std::vector<Bytes> inputs;
  for (const auto& p : paths) {
    inputs.push_back(nph::fuzz::readInput(p));
    maxLen = std::max<std::uint64_t>(maxLen, inputs.back().size());
  }
  for (int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, saveMutantAndDie);

  Mutator mutator(seed);
  for (std::uint64_t run = 0; run < runs; ++run) {
    const Bytes mutant = mutator.mutate(inputs, std::size_t(maxLen));
    std::snprintf(g_artifact, sizeof g_artifact, "fuzz-mutant-%llu", static_cast<unsigned long long>(run));
    g_current = &mutant;
    LLVMFuzzerTestOneInput(mutant.data(), mutant.size());
    g_current = nullptr;
  }
  std::printf("fuzz mutate: %llu mutants of %zu inputs (seed %llu) without a finding\n",
              static_cast<unsigned long long>(runs), inputs.size(), static_cast<unsigned long long>(seed));
  return 0;
}
