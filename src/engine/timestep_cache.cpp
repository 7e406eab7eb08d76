#include "engine/timestep_cache.h"

#include <algorithm>
#include <chrono>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"

namespace nph::engine {
namespace {

bool contains(const std::vector<std::size_t>& v, std::size_t t) { return std::find(v.begin(), v.end(), t) != v.end(); }

}  // namespace

TimestepCache::TimestepCache(std::shared_ptr<const Dataset> dataset, PrefetchSettings settings)
    : dataset_(std::move(dataset)), settings_(settings) {
  if (!dataset_) throw UsageError("TimestepCache: no dataset");
  settings_.max_timesteps = std::max<std::size_t>(settings_.max_timesteps, 2);
  worker_ = std::thread([this] { run(); });
}

TimestepCache::~TimestepCache() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    queue_.clear();
  }
  work_cv_.notify_all();
  idle_cv_.notify_all();
  worker_.join();
}

std::size_t TimestepCache::bytesOf(const ExtinctionVolumes& v) {
  return (v.ice_per_m.size() + v.water_per_m.size() + v.terrain_height_m.size()) * sizeof(float);
}

bool TimestepCache::keptLocked(std::size_t t) const { return contains(pinned_, t) || contains(ahead_, t); }

void TimestepCache::accountLocked() {
  std::size_t bytes = 0;
  for (const auto& [t, e] : entries_) {
    if (e.volumes) bytes += bytesOf(*e.volumes);
  }
  stats_.bytes = bytes;
  stats_.peak_bytes = std::max(stats_.peak_bytes, bytes);
}

void TimestepCache::trimLocked() {
  // Evict until the count and the budget hold: first the least recently used timesteps that
  // neither the current frame nor the read-ahead needs, then read-ahead ones from the far end;
  // pinned timesteps stay even over budget. The peak is taken after trimming: what is *held*.
  const auto heldBytes = [this] {
    std::size_t bytes = 0;
    for (const auto& [t, e] : entries_) bytes += e.volumes ? bytesOf(*e.volumes) : 0;
    return bytes;
  };
  for (;;) {
    std::size_t held = 0;
    for (const auto& [t, e] : entries_) held += e.volumes ? 1 : 0;
    if (held <= settings_.max_timesteps && heldBytes() <= settings_.memory_budget_bytes) break;
    auto victim = entries_.end();
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->second.in_flight || !it->second.volumes || keptLocked(it->first)) continue;
      if (victim == entries_.end() || it->second.last_use < victim->second.last_use) victim = it;
    }
    for (auto a = ahead_.rbegin(); victim == entries_.end() && a != ahead_.rend(); ++a) {
      const auto it = entries_.find(*a);
      if (it != entries_.end() && it->second.volumes && !it->second.in_flight && !contains(pinned_, *a)) {
        victim = it;
        ahead_.erase(std::next(a).base());
        ++stats_.over_budget;
        break;
      }
    }
    if (victim == entries_.end()) break;
    entries_.erase(victim);
  }
  accountLocked();
}

void TimestepCache::prefetch(const std::vector<std::size_t>& pinned, int direction) {
  {
    std::lock_guard lock(mutex_);
    pinned_ = pinned;
    ahead_.clear();
    queue_.clear();
    const std::size_t count = dataset_->timestepCount();
    if (settings_.enabled && !pinned.empty() && direction != 0) {
      const std::size_t edge = direction > 0 ? *std::max_element(pinned.begin(), pinned.end())
                                             : *std::min_element(pinned.begin(), pinned.end());
      std::size_t planned_bytes = timestep_bytes_ * pinned.size();
      std::size_t planned_count = pinned.size();
      for (std::size_t i = 1; i <= settings_.lookahead; ++i) {
        if (direction > 0 ? edge + i >= count : i > edge) break;
        const std::size_t t = direction > 0 ? edge + i : edge - i;
        if (t < settings_.first_timestep || t > settings_.last_timestep) break;
        // No timestep decoded yet: its size is unknown, so the budget cannot be checked. Read one
        // step ahead only; its size is known once it is decoded, and the next prefetch() (every
        // frame calls it) plans the rest within the budget.
        if (timestep_bytes_ == 0 && i > 1) break;
        if (planned_count + 1 > std::max(settings_.max_timesteps, pinned.size()) ||
            planned_bytes + timestep_bytes_ > settings_.memory_budget_bytes) {
          ++stats_.over_budget;
          break;
        }
        planned_bytes += timestep_bytes_;
        ++planned_count;
        ahead_.push_back(t);
        const auto it = entries_.find(t);
        if (it == entries_.end() || (!it->second.volumes && !it->second.in_flight && !it->second.error)) {
          queue_.push_back(t);
        }
      }
    }
    trimLocked();
  }
  work_cv_.notify_one();
  idle_cv_.notify_all();  // an emptied queue may have made the cache idle
}

bool TimestepCache::decode(std::unique_lock<std::mutex>& lock, std::size_t t) {
  entries_[t].in_flight = true;
  lock.unlock();  // others may use the cache (and the worker decode) meanwhile
  std::shared_ptr<const ExtinctionVolumes> volumes;
  std::exception_ptr error;
  try {
    volumes = std::make_shared<const ExtinctionVolumes>(dataset_->load(t));
  } catch (...) {
    error = std::current_exception();  // thrown by the get() of the frame that needs t
  }
  lock.lock();
  Entry& e = entries_[t];
  e.in_flight = false;
  e.volumes = volumes;
  e.error = error;
  e.last_use = clock_;
  if (volumes) timestep_bytes_ = std::max(timestep_bytes_, bytesOf(*volumes));
  done_cv_.notify_all();
  return volumes != nullptr;
}

void TimestepCache::run() {
  // Linux gives each thread its own nice value (setpriority on the thread id); elsewhere this
  // only fails, harmlessly.
  if (::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), settings().worker_nice) != 0) {
    log::debug("prefetch: could not lower the worker's priority");
  }
  std::unique_lock lock(mutex_);
  for (;;) {
    work_cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const std::size_t t = queue_.front();
    queue_.pop_front();
    Entry& e = entries_[t];
    if (!(e.volumes || e.in_flight || e.error)) {
      worker_busy_ = true;
      if (decode(lock, t)) ++stats_.prefetched;
      worker_busy_ = false;
      trimLocked();
    }
    if (queue_.empty()) idle_cv_.notify_all();
  }
}

std::shared_ptr<const ExtinctionVolumes> TimestepCache::get(std::size_t t) {
  if (t >= dataset_->timestepCount()) {
    throw UsageError(
        fmt::format("{}: timestep {} requested, the dataset has {}", dataset_->path(), t, dataset_->timestepCount()));
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto blocked = [&] {
    stats_.blocked_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  std::unique_lock lock(mutex_);
  ++clock_;
  bool counted = false;
  for (;;) {  // until t is decoded or failed (a finished entry may have been trimmed meanwhile)
    Entry& e = entries_[t];
    if (e.volumes || e.error) break;
    if (e.in_flight) {
      if (!counted) ++stats_.waits;
      counted = true;
      done_cv_.wait(lock, [&] { return !entries_[t].in_flight; });
      continue;
    }
    if (!counted) ++stats_.misses;
    counted = true;
    (void)decode(lock, t);
  }
  if (counted) blocked();
  else ++stats_.hits;
  Entry& e = entries_[t];
  if (e.error) {
    const std::exception_ptr error = e.error;
    entries_.erase(t);  // a later get() tries again (the file may have been repaired)
    std::rethrow_exception(error);
  }
  e.last_use = clock_;
  auto volumes = e.volumes;
  trimLocked();
  return volumes;
}

void TimestepCache::waitIdle() const {
  std::unique_lock lock(mutex_);
  idle_cv_.wait(lock, [this] { return stop_ || (queue_.empty() && !worker_busy_); });
}

void TimestepCache::releaseAll() {
  std::lock_guard lock(mutex_);
  pinned_.clear();
  ahead_.clear();
  queue_.clear();
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (it->second.in_flight) ++it;
    else it = entries_.erase(it);
  }
  accountLocked();
}

void TimestepCache::setSettings(const PrefetchSettings& settings) {
  std::lock_guard lock(mutex_);
  settings_ = settings;
  settings_.max_timesteps = std::max<std::size_t>(settings_.max_timesteps, 2);
  if (!settings_.enabled) {
    ahead_.clear();
    queue_.clear();
  }
  trimLocked();
}

PrefetchSettings TimestepCache::settings() const {
  std::lock_guard lock(mutex_);
  return settings_;
}

PrefetchStats TimestepCache::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace nph::engine
