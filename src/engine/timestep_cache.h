#pragma once
// Decoded timesteps of a dataset, with a background thread that decodes the next ones in the
// direction of playback while the current frame renders.
//
// Nes 2008 §5.1.2 buffers the previous and next timesteps so that stepping through time never
// waits for the disk; his table 6.1 (§6.3) shows a time change costing a volume upload and a DLM
// build on top of the load, so the load is the part worth hiding. Thomann 2021 §5.5 interpolates
// hourly model output, which needs the two timesteps around the current time in memory at once.
// Here:
//   - the timesteps the current frame needs are *pinned*: always kept, whatever the budget;
//   - prefetch(pinned, direction) queues the next `lookahead` timesteps beyond the pinned ones in
//     the direction of playback (within the animation's range), each only if it fits the memory
//     budget next to what is kept;
//   - the worker's CPU priority is a setting (worker_nice, default: the renderer's);
//   - one worker thread decodes the queue (Dataset::load is thread-safe); get() of a timestep in
//     flight waits for it, get() of one never asked for decodes it in the caller (a "miss").
//   - a decode error is kept with its timestep and thrown by the get() that asks for it, so a
//     broken file stops the frame that needs it, not an earlier one.
// In steady state (playback at a constant speed, lookahead ≥ 1) every get() is a hit.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/dataset.h"

namespace nph::engine {

struct PrefetchSettings {
  bool enabled = true;
  std::size_t lookahead = 2;  ///< timesteps decoded ahead of the pinned ones
  /// Decoded timesteps held (pinned + prefetched + recently used), bytes of float volumes.
  std::size_t memory_budget_bytes = std::size_t(2) << 30;
  std::size_t max_timesteps = 4;  ///< at most this many held (pinned ones always are)
  /// Read ahead only within [first_timestep, last_timestep] (an animation's range), so no decode
  /// is spent on timesteps that will not be shown.
  std::size_t first_timestep = 0;
  std::size_t last_timestep = std::size_t(-1);
  /// Nice value of the worker thread (Linux: per thread), set when it starts. 0: the read-ahead
  /// competes evenly with the renderer's threads. A higher value lets it use only CPU time the
  /// frame leaves idle, but on a machine loaded by other processes it then starves and frames
  /// wait for it (docs/benchmarks.md#animation-playback: 10 turned 0 ms of waiting into seconds).
  int worker_nice = 0;
};

struct PrefetchStats {
  std::uint64_t hits = 0;         ///< get() found the timestep decoded
  std::uint64_t waits = 0;        ///< get() waited for the background decode of it
  std::uint64_t misses = 0;       ///< get() decoded it in the caller's thread
  std::uint64_t prefetched = 0;   ///< timesteps decoded by the background thread
  std::uint64_t over_budget = 0;  ///< prefetches left out because they did not fit the budget
  double blocked_ms = 0.0;        ///< caller's time spent in waits and misses
  std::size_t bytes = 0;          ///< decoded bytes held now
  std::size_t peak_bytes = 0;
};

class TimestepCache {
 public:
  TimestepCache(std::shared_ptr<const Dataset> dataset, PrefetchSettings settings = {});
  ~TimestepCache();  ///< stops the worker after its current decode
  TimestepCache(const TimestepCache&) = delete;
  TimestepCache& operator=(const TimestepCache&) = delete;

  /// Timestep t decoded: from memory, by waiting for the worker, or decoded now. Rethrows the
  /// error of its decode (InputError naming the file).
  std::shared_ptr<const ExtinctionVolumes> get(std::size_t t);
  /// Pins `pinned` (the timesteps of the current frame), drops what is neither pinned nor ahead,
  /// and (when enabled) queues the next timesteps after the pinned ones in `direction` (+1 or −1).
  void prefetch(const std::vector<std::size_t>& pinned, int direction);

  /// Blocks until the read-ahead queued so far is decoded (or failed): nothing queued, nothing in
  /// the worker's hands. For callers that must know the cache's state (tests; a batch renderer
  /// that wants the next timestep ready before it reports progress).
  void waitIdle() const;
  /// Drops every decoded timestep that no decode is writing, the pinned ones too, and the
  /// read-ahead queue (issue 19, memory: a single frame whose volume is on the GPU reads none of
  /// them again). A later get() decodes anew; callers still holding a volume keep it alive.
  void releaseAll();

  void setSettings(const PrefetchSettings& settings);
  PrefetchSettings settings() const;
  PrefetchStats stats() const;

 private:
  struct Entry {
    std::shared_ptr<const ExtinctionVolumes> volumes;
    std::exception_ptr error;
    bool in_flight = false;
    std::uint64_t last_use = 0;
  };
  static std::size_t bytesOf(const ExtinctionVolumes& v);
  void run();
  /// Decodes t with `lock` released meanwhile; stores the volumes or the error. true on success.
  bool decode(std::unique_lock<std::mutex>& lock, std::size_t t);
  void trimLocked();
  bool keptLocked(std::size_t t) const;
  void accountLocked();

  std::shared_ptr<const Dataset> dataset_;
  mutable std::mutex mutex_;
  std::condition_variable work_cv_, done_cv_;
  PrefetchSettings settings_;
  std::map<std::size_t, Entry> entries_;
  std::deque<std::size_t> queue_;
  std::vector<std::size_t> pinned_, ahead_;
  std::size_t timestep_bytes_ = 0;  ///< size of a decoded timestep, once one was seen
  std::uint64_t clock_ = 0;
  PrefetchStats stats_;
  bool stop_ = false;
  bool worker_busy_ = false;  ///< the worker holds a queued timestep (decoding it)
  mutable std::condition_variable idle_cv_;
  std::thread worker_;
};

}  // namespace nph::engine
