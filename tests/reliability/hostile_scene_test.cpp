// Hostile scene files, keyframe files, basemaps and animation lengths (issue #18): real JSON and
// image files, refused with the file, the JSON path and what was expected.
#include <sys/stat.h>

#include <array>
#include <fstream>
#include <string>

#include "core/error.h"
#include "engine/animation.h"
#include "engine/dataset.h"
#include "reliability_support.h"
#include "scene/animation_spec.h"
#include "scene/basemap.h"
#include "scene/scene_file.h"
#include "scene/scene_setup.h"
#include "volume/volume_frame.h"
#include "wrf_hurricane.h"

namespace nph::reliability {
namespace {

void expectSceneError(const std::string& text, std::initializer_list<std::string> mentions) {
  SCOPED_TRACE(text.substr(0, 120));
  saveFuzzText(text, "scene");
  expectError<InputError>([&] { (void)scene::parseSceneText(text, "hostile.json", "."); }, mentions);
}

TEST(HostileScene, AnimationNested100000DeepIsRefusedWithoutStackOverflow) {
  // The "animation" section is kept as JSON text (dump) and parsed again later: dump() recursed
  // once per level and overflowed the stack.
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  expectSceneError(R"({"animation": {"keys": )" + deep + "}}",
                   {"hostile.json", "the scene file", "nests deeper than 64 levels"});
}

TEST(HostileScene, DuplicateKeysAreRefusedNotSilentlyOverwritten) {
  expectSceneError(R"({"camera": {"fov_deg": 30, "fov_deg": 90}})", {"hostile.json", "key \"fov_deg\" appears twice"});
  expectSceneError(R"({"sun": {}, "sun": {}})", {"hostile.json", "key \"sun\" appears twice"});
  // The same key in two different objects is fine.
  EXPECT_NO_THROW(
      (void)scene::parseSceneText(R"({"camera": {"fov_deg": 30}, "output": {"width": 30}})", "ok.json", "."));
}

TEST(HostileScene, DegenerateCamerasAreRefused) {
  // Looking straight down with the default up (0, 0, 1): no image plane orientation.
  expectSceneError(R"({"camera": {"position_m": [0, 0, 9000], "target_m": [0, 0, 0]}})",
                   {"hostile.json", "camera.target_m", "parallel to the view direction"});
  expectSceneError(R"({"camera": {"position_m": [0, 0, 0], "target_m": [5, 0, 0], "up": [-3, 0, 0]}})",
                   {"hostile.json", "camera.up", "parallel to the view direction"});
  expectSceneError(R"({"camera": {"position_m": [1e300, 0, 0], "target_m": [0, 0, 0], "up": [0, 0, 1]}})",
                   {"hostile.json", "camera.position_m", "expected coordinates within +-1000000000 m"});
  // Nearly vertical but not parallel stays allowed (the animation tests use it).
  EXPECT_NO_THROW((void)scene::parseSceneText(R"({"camera": {"position_m": [0, 0, 9000], "target_m": [1, 1, 0]}})",
                                              "ok.json", "."));
}

TEST(HostileScene, SunColourBeyondATintIsRefused) {
  expectSceneError(R"({"sun": {"colour": [1e300, 1, 1]}})",
                   {"hostile.json", "sun.colour", "expected components in [0, 100]"});
}

TEST(HostileScene, OutputLargerThanTheImageLimitIsRefusedBeforeRendering) {
  expectSceneError(R"({"output": {"width": 16384, "height": 16384}})",
                   {"hostile.json", "output.width", "16384 x 16384 pixels", "limits::kMaxImagePixels"});
  const ExtinctionVolumes v = ExtinctionVolumes::zeros(4, 4, 4, 1000.0, 250.0, 0.0);
  const volume::VolumeFrame frame = volume::frameOf(v, 1.0);
  expectError<UsageError>([&] { (void)scene::cameraFor(scene::CameraSpec{}, frame, 16384, 16384); },
                          {"16384 x 16384 pixels", "limits::kMaxImagePixels"});
}

TEST(HostileScene, AbsurdGridSpacingNamesTheFile) {
  // "frameOf: non-positive grid spacing" named nothing; dx = 1e+-300 overflowed the DLM's counts.
  for (const double dx : {1e-300, 1e300}) {
    ExtinctionVolumes v = ExtinctionVolumes::zeros(4, 4, 4, 1000.0, 250.0, 0.0);
    v.georef.dx_m = dx;
    v.source_file = "storm.nph";
    expectError<InputError>([&] { (void)volume::frameOf(v, 1.0); },
                            {"storm.nph", "grid spacing", "expected spacings in"});
  }
}

TEST(HostileScene, SceneAndKeyframeFifosAreRefusedByFileType) {
  const Scratch dir;
  const std::string fifo = dir.file("scene.json");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expectError<InputError>([&] { (void)scene::loadSceneFile(fifo); }, {fifo, "is a FIFO", "a scene file"});
  expectError<InputError>([&] { (void)scene::loadCameraKeyframes(fifo); }, {fifo, "is a FIFO", "keyframe file"});
  expectError<InputError>([&] { (void)scene::EquirectangularImage::load(fifo); }, {fifo, "is a FIFO", "basemap"});
}

std::string bigEndian32(std::uint32_t v) {
  return std::string{char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
}

/// CRC-32 of PNG chunks (ISO 3309, polynomial 0xEDB88320 reflected; PNG spec §5.5).
std::uint32_t pngCrc(const std::string& bytes) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (const char ch : bytes) {
    c ^= std::uint8_t(ch);
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xFFFFFFFFu;
}

/// A PNG of `width` x `height` whose pixel data is missing: its header (IHDR) is all a decoder
/// reads before allocating, so a few dozen bytes can declare any size.
void writePngHeaderOnly(const std::string& path, std::uint32_t width, std::uint32_t height) {
  std::string png = "\x89PNG\r\n\x1a\n";
  auto chunk = [&](const std::string& type, const std::string& data) {
    const std::string body = type + data;
    png += bigEndian32(std::uint32_t(data.size())) + body + bigEndian32(pngCrc(body));
  };
  const auto be32 = bigEndian32;
  // width, height, bit depth 8, colour type 2 (RGB), compression, filter, interlace
  chunk("IHDR", be32(width) + be32(height) + std::string{8, 2, 0, 0, 0});
  chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8));  // an empty zlib stream
  chunk("IEND", "");
  std::ofstream(path, std::ios::binary) << png;
}

TEST(HostileScene, HugeBasemapIsRefusedFromItsHeader) {
  // 16000 x 8000 once took 3.3 GB from a 373 KB PNG. GDAL's warper now reads only the windows it
  // needs (limits::kMaxBasemapSourcePixels = 65536^2): 100000 x 50000 is refused from the header.
  const Scratch dir;
  const std::string path = dir.file("huge.png");
  writePngHeaderOnly(path, 100000, 50000);
  expectError<InputError>([&] { (void)scene::EquirectangularImage::load(path); },
                          {path, "basemap width x height = 100000 x 50000", "downsample"});
  // Within the limit, the same header-only PNG fails when its pixels are read, naming the file.
  writePngHeaderOnly(path, 16000, 8000);
  expectError<InputError>([&] { (void)scene::EquirectangularImage::load(path); }, {path, "cannot read"});
}

TEST(HostileScene, AnimationPlanningMoreFramesThanTheLimitIsRefused) {
  // animation.speed = 1e-10 planned 1.8e15 frames.
  const Scratch dir;
  const std::string wrf = dir.file("wrfout.nc");
  writeSmallWrf(wrf, 2);
  const auto ds = engine::Dataset::open(wrf);
  const ExtinctionVolumes v0 = ds->load(0);
  for (const bool from_cli : {false, true}) {
    SCOPED_TRACE(from_cli ? "--duration 1e12" : "animation.speed 1e-10");
    const scene::SceneDescription s = scene::parseSceneText(
        R"({"data": {"path": ")" + wrf + R"("}, "output": {"width": 32, "height": 18}, "animation": )" +
            (from_cli ? std::string("{}") : std::string(R"({"speed": 1e-10})")) + "}",
        "anim.json", ".");
    scene::AnimationSpec animation = scene::parseAnimation(s);
    if (from_cli) animation.duration_s = 1e12;  // what nephele animate --duration sets
    const scene::PreparedScene prepared = scene::prepareScene(s, v0);
    expectError<InputError>([&] { (void)engine::AnimationPlan(animation, *ds, s, prepared); },
                            {"anim.json", "frames", "limits::kMaxFrames"});
  }
}

TEST(SeriesBlend, TimestepsCroppedDifferentlyBlendOnTheUnionOfTheirColumns) {
  // Converted on the fly, each timestep gets its own bottom (lowest surface) and top (highest
  // condensate): "cannot blend timesteps on different grids" stopped animate at frame 1.
  // a: layers 0..3 from 0 m; b: a cloud risen higher, layers 0..3 from 500 m (= out layers 2..5).
  ExtinctionVolumes a = ExtinctionVolumes::zeros(2, 1, 4, 1000.0, 250.0, 0.0);
  ExtinctionVolumes b = ExtinctionVolumes::zeros(2, 1, 4, 1000.0, 250.0, 500.0);
  for (std::size_t i = 0; i < a.ice_per_m.size(); ++i) {
    a.ice_per_m[i] = float(i + 1);         // 1..8
    b.ice_per_m[i] = float(10 * (i + 1));  // 10..80
  }
  for (const bool swapped : {false, true}) {
    const ExtinctionVolumes m = swapped ? engine::blendVolumes(b, a, 0.5, engine::TimeBlend::Linear)
                                        : engine::blendVolumes(a, b, 0.5, engine::TimeBlend::Linear);
    ASSERT_EQ(m.nz, 6);
    EXPECT_EQ(m.z_bottom_m, 0.0);
    // out layer k, column c: 0.5 a[k] (k < 4) + 0.5 b[k - 2] (k >= 2)
    for (int k = 0; k < 6; ++k) {
      for (int c = 0; c < 2; ++c) {
        const float av = k < 4 ? float(2 * k + c + 1) : 0.0f;
        const float bv = k >= 2 ? float(10 * (2 * (k - 2) + c + 1)) : 0.0f;
        EXPECT_EQ(m.ice_per_m[std::size_t(2 * k + c)], 0.5f * av + 0.5f * bv) << "layer " << k << " column " << c;
      }
    }
  }
  // Bottoms off the dz lattice are still refused, naming both grids.
  ExtinctionVolumes off = ExtinctionVolumes::zeros(2, 1, 4, 1000.0, 250.0, 100.0);
  expectError<UsageError>([&] { (void)engine::blendVolumes(a, off, 0.5, engine::TimeBlend::Linear); },
                          {"different grids", "from 100 m"});
}

}  // namespace
}  // namespace nph::reliability
