// image_diff ACTUAL EXPECTED MAX_ABS MEAN_ABS NAME: compares two images (PNG, PPM, EXR; values in
// [0, 1]) with tests/support's golden-image comparison; exit 0 when within tolerance, else 1 with
// actual/expected/diff written to <build>/test-output/NAME.*. Tolerances are in 8-bit codes.
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "support/image_compare.h"

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: %s ACTUAL EXPECTED MAX_ABS_CODES MEAN_ABS_CODES NAME\n", argv[0]);
    return 2;
  }
  constexpr double kCode = 1.0 / 255.0;
  try {
    const auto actual = nph::test::readImage(argv[1]);
    const nph::test::Tolerance tolerance{std::atof(argv[3]) * kCode, std::atof(argv[4]) * kCode};
    const auto r = nph::test::compareToFile(actual, argv[2], tolerance, argv[5]);
    std::printf("%s: max |diff| %.2f codes, mean %.4f codes (tolerance %s / %s): %s\n", argv[5], r.max_abs / kCode,
                r.mean_abs / kCode, argv[3], argv[4], r.pass ? "pass" : "FAIL");
    if (!r.pass) std::fprintf(stderr, "%s\n", r.message.c_str());
    return r.pass ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[5], e.what());
    return 2;
  }
}
