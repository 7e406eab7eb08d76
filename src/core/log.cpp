#include "core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>
#include <string>

#include "core/env.h"

namespace nph::log {
namespace {

Level levelFromEnv() {
  const std::string v = env::get("NEPHELE_LOG").value_or("info");
  if (v == "error") return Level::Error;
  if (v == "warn") return Level::Warn;
  if (v == "debug") return Level::Debug;
  return Level::Info;
}

std::atomic<Level>& thresholdRef() {
  static std::atomic<Level> level{levelFromEnv()};
  return level;
}

std::mutex& sinkMutex() {
  static std::mutex m;
  return m;
}

constexpr const char* kNames[] = {"error", "warn", "info", "debug"};

}  // namespace

Level threshold() { return thresholdRef().load(std::memory_order_relaxed); }
void setThreshold(Level level) { thresholdRef().store(level, std::memory_order_relaxed); }

void write(Level level, std::string_view message) {
  std::lock_guard lock(sinkMutex());
  std::fprintf(stderr, "nephele[%s] %.*s\n", kNames[static_cast<int>(level)], static_cast<int>(message.size()),
               message.data());
  std::fflush(stderr);
}

}  // namespace nph::log
