// Quick look: a scene file written for the data (quick_look.h).
#include "cli/quick_look.h"

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <utility>

#include "core/error.h"
#include "core/log.h"
#include "engine/quick_look.h"
#include "io/model_file.h"

namespace nph::cli {
namespace {

/// The dataset with timestep `t` already read: hands that volume out once instead of reading (or,
/// for model files, converting) it a second time; every other load goes to the wrapped dataset.
class PreloadedDataset final : public engine::Dataset {
 public:
  PreloadedDataset(std::shared_ptr<const engine::Dataset> inner, std::size_t t, ExtinctionVolumes v)
      : Dataset(inner->path(), inner->times(), sourcesOf(*inner)),
        inner_(std::move(inner)),
        t_(t),
        volume_(std::move(v)) {}
  ExtinctionVolumes load(std::size_t t) const override {
    {
      std::lock_guard lock(mutex_);
      if (t == t_ && volume_) {
        ExtinctionVolumes v = std::move(*volume_);
        volume_.reset();
        return v;
      }
    }
    return inner_->load(t);
  }

 private:
  static std::vector<std::string> sourcesOf(const engine::Dataset& d) {
    std::vector<std::string> s;
    for (std::size_t t = 0; t < d.timestepCount(); ++t) s.push_back(d.sourceFile(t));
    return s;
  }
  std::shared_ptr<const engine::Dataset> inner_;
  std::size_t t_;
  mutable std::mutex mutex_;
  mutable std::optional<ExtinctionVolumes> volume_;
};

}  // namespace

bool isDataFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return true;  // a folder of model files (GRIB2: DWD's layout)
  if (io::hasModelFileSignature(path)) return true;
  if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the read
  std::ifstream in(path, std::ios::binary);
  std::array<char, 8> head{};
  in.read(head.data(), head.size());
  return in.gcount() == 8 && std::memcmp(head.data(), "NPHCACHE", 8) == 0;
}

QuickLook makeQuickLook(const QuickLookRequest& r) {
  auto opened = engine::Dataset::open(r.data_path);
  if (opened->timestepCount() == 0) throw InputError(r.data_path + ": no timesteps to render");
  log::info("quick look: reading timestep 0 of {} to frame it", r.data_path);
  ExtinctionVolumes v = opened->load(0);

  QuickLook q;
  q.scene_json = engine::quickLookSceneText({r.data_path, r.outputs, r.width, r.height, ""}, v);
  q.scene = scene::parseSceneText(q.scene_json, "<quick look of " + r.data_path + ">",
                                  std::filesystem::current_path().string());
  q.dataset = std::make_shared<PreloadedDataset>(std::move(opened), 0, std::move(v));
  return q;
}

}  // namespace nph::cli
