#pragma once
// Output colour through OpenColorIO (issue 15; docs/colour.md): scene-linear radiance (Rec.709
// primaries, what the renderer writes, times 2^exposure) to the code values of a display — sRGB,
// Rec.1886 / Rec.709, Rec.2100 PQ or HLG — through a view (nephele's ACES fitted curve, ACES SDR or
// HDR video). nephele ships its own config (src/scene/ocio/config.ocio); a station may name its
// own (output.ocio_config, or the NEPHELE_OCIO_CONFIG environment variable).
#include <cstddef>
#include <memory>
#include <string>

namespace nph::scene {

/// The colour tags ffmpeg writes into a video for a display (`-color_primaries`, `-color_trc`,
/// `-colorspace`); empty for a display nephele does not know.
struct VideoColourTags {
  std::string primaries;   ///< bt709, bt2020
  std::string transfer;    ///< iec61966-2-1, bt709, smpte2084, arib-std-b67
  std::string colorspace;  ///< bt709, bt2020nc
  bool empty() const { return primaries.empty(); }
};

/// The config used when a scene names none: $NEPHELE_OCIO_CONFIG, else the build tree's, else the
/// installed one (share/nephele/ocio/config.ocio). InputError when none exists.
std::string defaultOcioConfig();

class DisplayOutput {
 public:
  /// The processor scene-linear → `display`/`view` of `config` (empty: defaultOcioConfig(); empty
  /// view: the display's default view). Cached: the same arguments return the same processor.
  /// InputError naming the config and listing what it has for an unknown display or view, or a
  /// config OpenColorIO cannot read.
  static std::shared_ptr<const DisplayOutput> open(const std::string& config, const std::string& display,
                                                   const std::string& view);

  /// In place: `pixels` straight (not premultiplied) linear RGB triples → display code values
  /// in [0, 1] (clamped; non-finite input counts as 0).
  void apply(float* rgb, std::size_t pixels) const;
  /// Whether the display is an HDR one (OCIO encoding "hdr-video"): PNGs then hold 16 bits.
  bool hdr() const { return hdr_; }
  const std::string& display() const { return display_; }
  const std::string& view() const { return view_; }
  const std::string& config() const { return config_; }
  VideoColourTags videoTags() const;

  struct Impl;
  explicit DisplayOutput(std::shared_ptr<const Impl> impl, std::string config, std::string display, std::string view,
                         bool hdr);

 private:
  std::shared_ptr<const Impl> impl_;
  std::string config_, display_, view_;
  bool hdr_ = false;
};

}  // namespace nph::scene
