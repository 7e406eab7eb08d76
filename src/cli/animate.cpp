// `nephele animate`: an image sequence (and optionally a video with alpha) of a scene file's
// animation section (docs/animation.md): model time from a time range at a rational frame rate,
// camera keyframes, the sun fixed or following the clock.
//
// Render-farm rules: frame k is a function of k alone (engine/animation.h; the ray caster's jitter
// is a hash of the pixel, glsl/render/clouds.comp), so `--frames A:B` on any machine gives the
// same bytes as one run; a frame whose every output exists is skipped (resume), and every image is
// written under a temporary name and renamed (scene::writeImage), so a killed run never leaves a
// half-written frame under a final name.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "cli/commands.h"
#include "cli/output_options.h"
#include "cli/progress.h"
#include "cli/quick_look.h"
#include "core/error.h"
#include "core/log.h"
#include "core/process.h"
#include "core/temp_files.h"
#include "engine/animation.h"
#include "engine/dataset.h"
#include "engine/session.h"
#include "render/gl/context.h"
#include "scene/animation_spec.h"
#include "scene/colour_output.h"
#include "scene/image_codec.h"
#include "scene/output_image.h"
#include "scene/passes.h"
#include "scene/scene_file.h"

namespace nph::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// --interpolation's values: the scene file's names (scene/animation_spec.h), in one table.
std::vector<std::string> interpolationNames() {
  std::vector<std::string> names;
  for (const auto& entry : scene::kTimeInterpolationNames) names.emplace_back(entry.first);
  return names;
}

struct AnimateOptions {
  std::string scene;
  std::string output_dir;
  std::string formats = "png";
  bool layer = false;
  bool passes = false;
  std::string display, view;
  std::string frames;
  std::string chunk;
  bool print_scene = false;
  std::vector<std::string> data;
  std::string from, to, fps, keyframes, interpolation;
  std::optional<double> duration_s, speed;
  std::string gl = "auto";
  int width = 0, height = 0;
  bool no_prefetch = false;
  double prefetch_budget_mb = 2048.0;
  int lookahead = 2;
  int write_threads = 0;  // 0: FrameWriter::automaticThreads()
  bool progress = false, no_progress = false;
  bool overwrite = false;
  std::string video;
  std::string video_codec = "prores4444";
};

/// Writes the frames' files on worker threads while the next frames render (issue 19): on a GPU a
/// 1080p frame renders and reads back in ≈ 0.1 s while its PNG and EXR take ≈ 0.5 s to encode
/// (docs/benchmarks.md "Read-back"), so written in line the encoders set the frame rate. At most
/// `threads` frames wait or are being written (each holds its images); submit() blocks beyond that.
/// A job's error is rethrown by the next submit() or by finish(); the jobs handed over before it
/// still run, so every frame rendered before an error is written. The destructor (also on an
/// exception of the render loop) waits for every job handed over.
class FrameWriter {
 public:
  explicit FrameWriter(std::size_t threads) : capacity_(std::max<std::size_t>(threads, 1)) {
    for (std::size_t i = 0; i < capacity_; ++i) workers_.emplace_back([this] { work(); });
  }
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;
  ~FrameWriter() { stop(); }

  /// A quarter of the hardware threads, 1 to 4: one on this 2-core VM (llvmpipe needs the cores
  /// for the ray cast), four on a 16-core GPU machine.
  static std::size_t automaticThreads() {
    return std::clamp<std::size_t>(std::thread::hardware_concurrency() / 4, 1, 4);
  }

  void submit(std::function<void()> job) {
    std::unique_lock lock(mutex_);
    space_.wait(lock, [&] { return queue_.size() + running_ < capacity_ || error_; });
    if (error_) std::rethrow_exception(error_);
    queue_.push_back(std::move(job));
    ready_.notify_one();
  }
  /// Waits for every job; rethrows the first error.
  void finish() {
    stop();
    if (error_) std::rethrow_exception(error_);
  }

 private:
  void work() {
    for (;;) {
      std::function<void()> job;
      {
        std::unique_lock lock(mutex_);
        ready_.wait(lock, [&] { return !queue_.empty() || stopping_; });
        if (queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
        ++running_;
      }
      try {
        job();
      } catch (...) {
        const std::lock_guard lock(mutex_);
        if (!error_) error_ = std::current_exception();
      }
      job = nullptr;  // its images and its frame claim go now, not at the next job
      {
        const std::lock_guard lock(mutex_);
        --running_;
      }
      space_.notify_all();
    }
  }
  void stop() {
    {
      const std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    ready_.notify_all();
    for (auto& t : workers_)
      if (t.joinable()) t.join();
  }

  const std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable ready_, space_;
  std::deque<std::function<void()>> queue_;
  std::size_t running_ = 0;
  bool stopping_ = false;
  std::exception_ptr error_;
  std::vector<std::thread> workers_;
};

/// A whole number ≥ 0 from `s` (all of it), or `def` when `s` is empty; -1 when it is not one.
std::int64_t wholeNumber(const std::string& s, std::int64_t def) {
  if (s.empty()) return def;
  if (s.find_first_not_of("0123456789") != std::string::npos || s.size() > 18) return -1;
  return std::stoll(s);
}

/// The frames to render among [0, count): `frames` "A:B" or "A-B" (inclusive, either side may be
/// empty, as render farms write ranges), or `chunk` "I/N": the frames split into N contiguous
/// chunks of near-equal length, chunk I (0 ≤ I < N; Slurm `--array=0-(N-1)` with
/// `--chunk $SLURM_ARRAY_TASK_ID/N`). An empty chunk (more chunks than frames) is {0, -1}.
std::pair<std::int64_t, std::int64_t> frameRangeFor(const std::string& frames, const std::string& chunk,
                                                    std::int64_t count) {
  if (!frames.empty() && !chunk.empty()) throw UsageError("give either --frames or --chunk, not both");
  if (!chunk.empty()) {
    const auto slash = chunk.find('/');
    const std::int64_t i = slash == std::string::npos ? -1 : wholeNumber(chunk.substr(0, slash), -1);
    const std::int64_t n = slash == std::string::npos ? -1 : wholeNumber(chunk.substr(slash + 1), -1);
    if (i < 0 || n < 1 || i >= n) {
      throw UsageError(fmt::format("--chunk {}: expected I/N with 0 ≤ I < N (chunk I of N contiguous chunks)", chunk));
    }
    // Boundaries floor(i·count/n) in 128-bit arithmetic: no overflow for any count and n.
    __extension__ using Wide = __int128;
    const auto bound = [&](std::int64_t k) { return static_cast<std::int64_t>(Wide(k) * count / n); };
    return {bound(i), bound(i + 1) - 1};
  }
  if (frames.empty()) return {0, count - 1};
  auto sep = frames.find(':');
  if (sep == std::string::npos) sep = frames.find('-');
  const std::int64_t a = wholeNumber(frames.substr(0, sep), 0);
  const std::int64_t b = sep == std::string::npos ? a : wholeNumber(frames.substr(sep + 1), count - 1);
  if (a < 0 || b < 0) throw UsageError(fmt::format("--frames {}: expected A:B or A-B with frame numbers ≥ 0", frames));
  if (a > b || b >= count) {
    throw UsageError(fmt::format("--frames {}: the animation has frames 0 to {}", frames, count - 1));
  }
  return {a, b};
}

scene::TimePoint timePointFromText(const std::string& text) {
  scene::TimePoint p;
  std::size_t used = 0;
  try {
    const double index = std::stod(text, &used);
    if (used == text.size() && index >= 0.0) {
      p.index = index;
      return p;
    }
  } catch (const std::exception&) {
  }
  p.utc = text;
  return p;
}

/// EXR capDate of a frame: the model time it shows ("YYYY:MM:DD hh:mm:ss"), the epoch without
/// times: never the wall clock, so frames rendered anywhere are byte-identical.
std::string exrDateTime(const engine::AnimationFrame& f) {
  std::string iso = f.utc ? f.utc->iso8601() : std::string("1970-01-01T00:00:00Z");  // YYYY-MM-DDThh:mm:ssZ
  iso[4] = iso[7] = ':';
  iso[10] = ' ';
  return iso.substr(0, 19);
}

double peakResidentMb() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

/// Encodes the PNG sequence `pattern` (printf-style) of frames first..last into `video` with
/// alpha: ProRes 4444 (prores_ks, yuva444p10le) or QuickTime Animation (qtrle, argb), through
/// Debian's ffmpeg, tagged with the display's colour (primaries, transfer, matrix: what players and
/// broadcast chains read). Written under a temporary name and renamed.
void encodeVideo(const std::string& pattern, std::int64_t first, std::int64_t last, const scene::FrameRate& fps,
                 const std::string& codec, const scene::VideoColourTags& tags, const std::string& video) {
  std::vector<std::string> args{process::toolPath("NEPHELE_FFMPEG", "ffmpeg"),
                                "-nostdin",
                                "-y",
                                "-loglevel",
                                "error",
                                "-framerate",
                                fps.text(),
                                "-start_number",
                                std::to_string(first),
                                "-i",
                                pattern,
                                "-frames:v",
                                std::to_string(last - first + 1)};
  if (codec == "prores4444") {
    args.insert(args.end(), {"-c:v", "prores_ks", "-profile:v", "4444", "-pix_fmt", "yuva444p10le", "-vendor", "apl0"});
  } else {
    args.insert(args.end(), {"-c:v", "qtrle", "-pix_fmt", "argb"});
  }
  if (!tags.empty()) {
    // The stream's tags (the mov 'colr' atom) and, for ProRes, its frame headers, which the
    // encoder fills from the input frames (PNG: unknown) unless the metadata filter sets them.
    args.insert(args.end(), {"-color_primaries", tags.primaries, "-color_trc", tags.transfer, "-colorspace",
                             tags.colorspace, "-movflags", "+write_colr"});
    if (codec == "prores4444") {  // a ProRes frame header knows no sRGB transfer: "unknown" there
      const bool proresTrc =
          tags.transfer == "bt709" || tags.transfer == "smpte2084" || tags.transfer == "arib-std-b67";
      args.insert(args.end(),
                  {"-bsf:v", fmt::format("prores_metadata=color_primaries={}:color_trc={}:colorspace={}",
                                         tags.primaries, proresTrc ? tags.transfer : "unknown", tags.colorspace)});
    }
  }
  const fs::path final(video);
  temp_files::removeStale(final.has_parent_path() ? final.parent_path() : fs::path("."), ".partial-");
  const temp_files::Created created =
      temp_files::createExclusive(final, "." + final.filename().string(), ".partial-", "");
  ::close(created.fd);
  const fs::path tmp = created.path;
  const temp_files::CleanupRegistration cleanup(tmp);
  args.insert(args.end(), {"-f", "mov", tmp.string()});
  log::info("encoding {} with ffmpeg ({})", video, codec);
  const int status = process::run(args);
  if (status != 0) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(status == 127 ? fmt::format("{}: ffmpeg not found (Debian package ffmpeg; make deps)", video)
                                : fmt::format("{}: ffmpeg failed with status {}", video, status));
  }
  fs::rename(tmp, final);
}

int runAnimate(const AnimateOptions& o) {
  std::shared_ptr<const engine::Dataset> quick_dataset;
  scene::SceneDescription s;
  if (isDataFile(o.scene)) {
    // Quick look: a scene written for the data, its whole time range at one second per timestep.
    QuickLook q = makeQuickLook({o.scene, {}, o.width > 0 ? o.width : 1920, o.height > 0 ? o.height : 1080});
    if (o.print_scene) std::fputs(q.scene_json.c_str(), stdout);
    s = std::move(q.scene);
    if (o.data.empty()) quick_dataset = std::move(q.dataset);
  } else {
    if (o.print_scene) throw UsageError("--print-scene: " + o.scene + " is already a scene file");
    s = scene::loadSceneFile(o.scene);
  }
  if (o.width > 0) s.output.width = o.width;
  if (o.height > 0) s.output.height = o.height;
  if (!s.data && o.data.empty())
    throw InputError(o.scene + ": no \"data\" section: which .nph or model files to animate?");
  if (!o.data.empty()) {
    if (!s.data) s.data = scene::DataSpec{};
    s.data->path = o.data.front();
    s.data->timestep = 0;
    s.data->time_utc.reset();
  }
  scene::AnimationSpec spec = scene::parseAnimation(s);
  if (!o.from.empty()) spec.from = timePointFromText(o.from);
  if (!o.to.empty()) spec.to = timePointFromText(o.to);
  if (!o.fps.empty()) spec.fps = scene::FrameRate::parse(o.fps);
  if (o.duration_s && o.speed) throw UsageError("give either --duration or --speed, not both");
  if (o.duration_s) spec.duration_s = *o.duration_s, spec.speed.reset();
  if (o.speed) spec.speed = *o.speed, spec.duration_s.reset();
  if (!o.interpolation.empty()) spec.interpolation = scene::timeInterpolationNamed(o.interpolation);
  if (!o.keyframes.empty()) spec.keyframes = scene::loadCameraKeyframes(o.keyframes);

  std::vector<std::string> exts;
  for (const std::string f : {"png", "exr"}) {
    if (o.formats.find(f) != std::string::npos) exts.push_back("." + f);
  }
  if (exts.empty() || (o.formats != "png" && o.formats != "exr" && o.formats != "png,exr" && o.formats != "exr,png")) {
    throw UsageError(fmt::format("--format {}: expected png, exr or png,exr", o.formats));
  }
  if (!o.video.empty() && std::find(exts.begin(), exts.end(), ".png") == exts.end()) {
    throw UsageError("--video encodes the PNG sequence: add png to --format");
  }
  scene::image_codec::modulePath(o.output_dir);  // a missing image codec stops the run before frame 0
  const auto dataset = quick_dataset       ? quick_dataset
                       : o.data.size() > 1 ? engine::Dataset::openSeries(o.data)
                                           : engine::Dataset::open(s.data->path);

  auto ctx = gl::createHeadlessContext(o.gl);

  if (o.passes) s.output.passes = true;
  applyColourOptions(o.display, o.view, s.output.image);
  engine::Session session(dataset, s);
  session.setTimeBlend(engine::timeBlendFor(spec.interpolation));
  const engine::AnimationPlan plan(spec, *dataset, session.scene(), session.prepared());
  const auto [first, last] = frameRangeFor(o.frames, o.chunk, plan.frameCount());

  fs::create_directories(o.output_dir);
  const auto pathOf = [&](std::string_view kind, std::int64_t k, const std::string& ext) {
    return (fs::path(o.output_dir) / fmt::format("{}_{:06d}{}", kind, k, ext)).string();
  };
  // What each frame writes: the frame (an .exr with --passes carries every pass as a layer and Z);
  // the cloud layer alone with --layer; with --passes, PNG sequences get one file per pass.
  const auto outputsOf = [&](std::int64_t k) {
    std::vector<std::pair<scene::Pass, std::string>> paths;
    for (const auto& ext : exts) {
      paths.emplace_back(scene::Pass::Beauty, pathOf("frame", k, ext));
      if (o.layer || (o.passes && ext == ".png")) paths.emplace_back(scene::Pass::Cloud, pathOf("layer", k, ext));
      if (o.passes && ext == ".png") {
        for (scene::Pass p : {scene::Pass::Ground, scene::Pass::Sky, scene::Pass::Shadow}) {
          paths.emplace_back(p, pathOf(scene::passName(p), k, ext));
        }
      }
    }
    return paths;
  };
  // The cloud layer is copied to host memory only when a file takes it (issue 19: on a GPU the
  // read-back is most of a frame's wall time, docs/benchmarks.md "Read-back").
  render::ReadBack read_back;
  read_back.cloud_layer = o.layer || s.output.wantsPasses();
  const auto complete = [&](std::int64_t k) {
    const auto outs = outputsOf(k);
    return std::all_of(outs.begin(), outs.end(), [](const auto& p) { return fs::exists(p.second); });
  };
  std::vector<std::int64_t> todo;
  std::int64_t skipped = 0, rendered_elsewhere = 0, rendered = 0;
  for (std::int64_t k = first; k <= last; ++k) {
    if (complete(k) && !o.overwrite) {
      ++skipped;
      log::info("frame {}: complete, skipped", k);
    } else {
      todo.push_back(k);
    }
  }
  log::info("animation: {} frames at {} fps ({:.3f} s), timesteps {:.3f} to {:.3f}, sun {}; frames {} to {}: {} to "
            "render, {} complete",
            plan.frameCount(), spec.fps.text(), plan.durationSeconds(), plan.fromIndex(), plan.toIndex(),
            plan.sunFollowsClock() ? "following the clock" : "fixed", first, last, todo.size(), skipped);

  engine::PrefetchSettings prefetch;
  prefetch.enabled = !o.no_prefetch;
  prefetch.lookahead = std::size_t(std::max(o.lookahead, 0));
  prefetch.memory_budget_bytes = std::size_t(std::max(o.prefetch_budget_mb, 0.0) * 1024.0 * 1024.0);
  prefetch.max_timesteps = std::max<std::size_t>(4, prefetch.lookahead + 2);
  prefetch.first_timestep = std::size_t(std::floor(plan.fromIndex()));
  prefetch.last_timestep = std::size_t(std::ceil(plan.toIndex()));
  session.setPrefetch(prefetch);
  session.setPlaybackDirection(+1);

  ProgressBar bar(todo.size(), o.progress || (!o.no_progress && ProgressBar::stderrIsTerminal()));
  const auto t_start = Clock::now();
  double first_s = 0.0;  // the first frame rendered (programs compiled, first volume and DLM)
  std::uint64_t dlm_reused_frames = 0, volume_reused_frames = 0, stalls = 0;
  const std::size_t write_threads =
      o.write_threads > 0 ? std::size_t(o.write_threads) : FrameWriter::automaticThreads();
  FrameWriter writer(write_threads);
  for (std::size_t i = 0; i < todo.size(); ++i) {
    const std::int64_t k = todo[i];
    // A frame is claimed before it is rendered (temp_files::Claim), so that two runs on one
    // folder share the frames instead of both rendering every one (issue #18).
    // Held until the frame's files are written (by the writer's job).
    auto claim = std::make_unique<temp_files::Claim>();
    if (!claim->tryAcquire(pathOf(".frame", k, ".claim"))) {
      ++rendered_elsewhere;
      log::info("frame {}: claimed by process {}, left to it", k, claim->holder());
      bar.update(i + 1, fmt::format("frame {} (other run)", k));
      continue;
    }
    if (!o.overwrite && complete(k)) {  // finished by another run since the list was made
      ++skipped;
      bar.update(i + 1, fmt::format("frame {} (complete)", k));
      continue;
    }
    const engine::AnimationFrame f = plan.frame(k);
    const auto t0 = Clock::now();
    const std::string when = f.utc ? f.utc->iso8601() : fmt::format("timestep {:.4f}", f.time_index);
    auto out = std::make_shared<render::RenderOutput>();
    try {
      session.setTime(f.time_index);
      session.setSun(f.sun);
      *out = session.render(f.camera, read_back);
    } catch (const Error& e) {
      const engine::TimeBracket b = engine::bracketTime(f.time_index, dataset->timestepCount());
      const std::string files = b.weight > 0.0 && dataset->sourceFile(b.first) != dataset->sourceFile(b.second)
                                    ? dataset->sourceFile(b.first) + " / " + dataset->sourceFile(b.second)
                                    : dataset->sourceFile(b.first);
      bar.finish();
      writer.finish();  // the frames rendered before this one are written first
      throw InputError(fmt::format("frame {} ({}, timestep {:.4f} of {}): {} — frames written before it are kept; run "
                                   "again to resume",
                                   k, when, f.time_index, files, e.what()));
    }
    scene::ImageOutputOptions image = scene::imageOptionsFor(s.output, f.sun.elevation_deg);
    image.date_time = exrDateTime(f);
    writer.submit(
        [&s, k, out, image, paths = outputsOf(k), claim = std::shared_ptr<temp_files::Claim>(std::move(claim))] {
          const auto w0 = Clock::now();
          const scene::FramePasses* passes = out->passes ? &*out->passes : nullptr;
          // The frame and the layer are written as they are; only a frame with pass layers or Z and
          // a pass image are made (a conditional expression would copy the frame and the layer: 33 MB
          // each at 1080p, per frame).
          for (const auto& [pass, path] : paths) {
            if (pass == scene::Pass::Cloud || (pass == scene::Pass::Beauty && !s.output.wantsPasses())) {
              scene::writeImage(pass == scene::Pass::Cloud ? out->cloud_layer : out->frame, path, image);
            } else if (pass == scene::Pass::Beauty) {
              scene::writeImage(scene::outputFrame(s.output, out->frame, out->cloud_layer, passes), path, image);
            } else {
              scene::writeImage(scene::passImage(pass, out->frame, out->cloud_layer, *passes), path, image);
            }
          }
          log::debug("frame {}: files written in {:.0f} ms", k,
                     std::chrono::duration<double, std::milli>(Clock::now() - w0).count());
        });
    ++rendered;
    const engine::FrameStats& st = session.stats();
    dlm_reused_frames += st.dlm_rebuilt ? 0 : 1;
    volume_reused_frames += st.volume_changed ? 0 : 1;
    stalls += st.blocked_ms > 0.0 ? 1 : 0;
    const double frame_s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (first_s == 0.0) first_s = std::chrono::duration<double>(Clock::now() - t_start).count();
    log::info("frame {} ({}, timestep {:.4f}): {:.2f} s (load {:.0f} ms of which blocked {:.0f}, upload {:.0f}, DLM "
              "{}, ray cast {:.0f} ms)",
              k, when, f.time_index, frame_s, st.load_ms, st.blocked_ms, st.upload_ms,
              st.dlm_rebuilt ? fmt::format("{:.0f} ms", st.dlm_ms) : std::string("reused"), st.raycast_ms);
    bar.update(i + 1, fmt::format("frame {}", k));
  }
  writer.finish();
  bar.finish();
  const double total_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  // Sustained: the frames after the first over the time after it, the last files written.
  const double steady_s = total_s - first_s;
  const auto pf = session.prefetchStats();
  std::printf("animate: rendered %lld frames, skipped %lld complete and %lld claimed by another run (frames %lld to "
              "%lld of %lld)\n",
              static_cast<long long>(rendered), static_cast<long long>(skipped),
              static_cast<long long>(rendered_elsewhere), static_cast<long long>(first), static_cast<long long>(last),
              static_cast<long long>(plan.frameCount()));
  if (!todo.empty()) {
    std::printf(
        "animate: %.2f s, %.3f frames/s sustained (after the first), DLM reused on %llu of %zu frames, volume reused "
        "on %llu, frames that waited for data %llu; prefetch hits %llu waits %llu misses %llu (%.0f ms blocked), "
        "peak decoded %.0f MB, peak RSS %.0f MB\n",
        total_s, todo.size() > 1 ? double(todo.size() - 1) / steady_s : 0.0,
        static_cast<unsigned long long>(dlm_reused_frames), todo.size(),
        static_cast<unsigned long long>(volume_reused_frames), static_cast<unsigned long long>(stalls),
        static_cast<unsigned long long>(pf.hits), static_cast<unsigned long long>(pf.waits),
        static_cast<unsigned long long>(pf.misses), pf.blocked_ms, double(pf.peak_bytes) / 1048576.0, peakResidentMb());
  }
  if (!o.video.empty() && rendered_elsewhere > 0) {
    std::printf("animate: no video: %lld frames are being rendered by another run; run again when it ends\n",
                static_cast<long long>(rendered_elsewhere));
  } else if (!o.video.empty() && first <= last) {
    const char* kind = o.layer ? "layer" : "frame";
    // The PNGs' colour: the OCIO display's, else nephele's sRGB encoding.
    const scene::VideoColourTags tags =
        s.output.image.display.empty()
            ? scene::VideoColourTags{"bt709", "iec61966-2-1", "bt709"}
            : scene::DisplayOutput::open(s.output.image.ocio_config, s.output.image.display, s.output.image.view)
                  ->videoTags();
    encodeVideo((fs::path(o.output_dir) / fmt::format("{}_%06d.png", kind)).string(), first, last, spec.fps,
                o.video_codec, tags, o.video);
    std::printf("animate: wrote %s (%s, %s frames with alpha)\n", o.video.c_str(), o.video_codec.c_str(), kind);
  }
  return kExitOk;
}

}  // namespace

void addAnimateCommand(CLI::App& app, Action& run) {
  auto opts = std::make_shared<AnimateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "animate",
      "Render an image sequence of a scene file's animation section (time range, frame rate, camera "
      "keyframes, sun fixed or following the clock; docs/animation.md) to OUTPUT_DIR/frame_NNNNNN.png/.exr, "
      "optionally the premultiplied cloud layer (layer_NNNNNN) and a video with alpha through ffmpeg. "
      "Frames already complete are skipped; --frames A:B (or A-B) and --chunk I/N render a sub-range with the "
      "same bytes as one run (render farms: examples/03-slurm-farm). Quick look: a wrfout, ICON or .nph file instead "
      "of a scene animates all its timesteps, framed automatically (--print-scene shows the scene).");
  cmd->add_option("scene", opts->scene,
                  "scene file (JSON) with an optional \"animation\" section, or a data file for a quick look")
      ->required()
      ->check(CLI::ExistingPath);  // a folder: GRIB2 quick look
  cmd->add_option("-o,--output-dir", opts->output_dir, "folder of the image sequence")->required();
  cmd->add_option("--format", opts->formats, "png, exr or png,exr")->capture_default_str();
  cmd->add_flag("--layer", opts->layer, "also write the premultiplied cloud layer alone (layer_NNNNNN)");
  cmd->add_flag("--passes", opts->passes,
                "compositing passes (docs/passes.md): .exr frames carry cloud, ground, sky, shadow layers and the "
                "cloud depth Z; PNG sequences get layer_, ground_, sky_ and shadow_NNNNNN.png");
  addColourOptions(*cmd, opts->display, opts->view);
  cmd->add_option("--frames", opts->frames, "sub-range A:B or A-B of frame numbers, inclusive (render farms)");
  cmd->add_option("--chunk", opts->chunk,
                  "I/N: chunk I (0-based) of the frames split into N contiguous chunks, e.g. "
                  "--chunk $SLURM_ARRAY_TASK_ID/8 with sbatch --array=0-7");
  cmd->add_flag("--print-scene", opts->print_scene, "quick look: print the generated scene (JSON) to stdout");
  cmd->add_option("--data", opts->data, "model files (a series, time-ordered) or one .nph; replaces data.path")
      ->check(CLI::ExistingFile);
  cmd->add_option("--from", opts->from, "start: timestep index or UTC time (replaces animation.from)");
  cmd->add_option("--to", opts->to, "end: timestep index or UTC time (replaces animation.to)");
  cmd->add_option("--fps", opts->fps, "frame rate: 25, 50, 59.94 (= 60000/1001), 60000/1001, ...");
  cmd->add_option("--duration", opts->duration_s, "video length in seconds (replaces animation.duration_s)");
  cmd->add_option("--speed", opts->speed, "model seconds per video second (replaces animation.speed)");
  cmd->add_option("--interpolation", opts->interpolation,
                  "motion (blend timesteps carried along the wind; the default), linear (cross-fade) or step "
                  "(hold each)")
      ->check(CLI::IsMember(interpolationNames()));
  cmd->add_option("--keyframes", opts->keyframes, "camera keyframe file (JSON; replaces the scene's)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--gl", opts->gl, "OpenGL backend: auto (EGL, then OSMesa), egl, osmesa")->capture_default_str();
  cmd->add_option("--width", opts->width, "image width (default: the scene's)");
  cmd->add_option("--height", opts->height, "image height (default: the scene's)");
  cmd->add_flag("--no-prefetch", opts->no_prefetch, "decode timesteps only when a frame needs them");
  cmd->add_option("--prefetch-budget-mb", opts->prefetch_budget_mb, "memory for decoded timesteps")
      ->capture_default_str();
  cmd->add_option("--lookahead", opts->lookahead, "timesteps decoded ahead of the current ones")->capture_default_str();
  cmd->add_option("--write-threads", opts->write_threads,
                  "threads that write frames' files while the next frames render (0: a quarter of the hardware "
                  "threads, 1 to 4); at most this many rendered frames wait in memory")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_flag("--progress", opts->progress, "progress bar with ETA on stderr even when it is not a terminal");
  cmd->add_flag("--no-progress", opts->no_progress, "no progress bar");
  cmd->add_flag("--overwrite", opts->overwrite, "render complete frames again instead of skipping them");
  cmd->add_option("--video", opts->video, "also encode a .mov with alpha (needs png in --format)");
  cmd->add_option("--video-codec", opts->video_codec, "prores4444 (ProRes 4444, 10-bit + alpha) or qtrle (Animation)")
      ->check(CLI::IsMember({"prores4444", "qtrle"}))
      ->capture_default_str();
  cmd->callback([opts, &run] { run = [opts] { return runAnimate(*opts); }; });
}

}  // namespace nph::cli
