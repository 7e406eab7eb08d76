#include "api/handles.h"

#include <map>
#include <mutex>
#include <new>

#include "core/error.h"
#include "core/log.h"

namespace nph::api {
namespace {

constexpr std::uintptr_t kKindBits = 4;  // low bits of a handle value: its Kind
constexpr std::uintptr_t kKindMask = (std::uintptr_t(1) << kKindBits) - 1;

struct Entry {
  Kind kind;
  std::shared_ptr<void> object;
  std::string last_error;
};

struct Registry {
  std::mutex mutex;
  std::map<std::uintptr_t, Entry> entries;
  std::uintptr_t next = 1;
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: calls during static destruction stay safe
  return *r;
}

thread_local std::string t_last_error;

std::uintptr_t value(const void* handle) { return reinterpret_cast<std::uintptr_t>(handle); }

}  // namespace

const void* registerHandle(Kind kind, std::shared_ptr<void> object) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  const std::uintptr_t v = (r.next++ << kKindBits) | std::uintptr_t(kind);
  r.entries.emplace(v, Entry{kind, std::move(object), {}});
  return reinterpret_cast<const void*>(v);
}

std::shared_ptr<void> lookupHandle(const void* handle, Kind kind) {
  if ((value(handle) & kKindMask) != std::uintptr_t(kind)) return nullptr;
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  const auto it = r.entries.find(value(handle));
  return it == r.entries.end() ? nullptr : it->second.object;
}

std::shared_ptr<void> unregisterHandle(const void* handle, Kind kind) {
  if ((value(handle) & kKindMask) != std::uintptr_t(kind)) return nullptr;
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  const auto it = r.entries.find(value(handle));
  if (it == r.entries.end()) return nullptr;
  auto object = std::move(it->second.object);
  r.entries.erase(it);
  return object;
}

void setLastError(const void* handle, const std::string& message) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  if (const auto it = r.entries.find(value(handle)); it != r.entries.end()) {
    it->second.last_error = message;
  } else {
    t_last_error = message;
  }
}

const char* lastError(const void* handle) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  if (const auto it = r.entries.find(value(handle)); handle != nullptr && it != r.entries.end()) {
    return it->second.last_error.c_str();
  }
  return t_last_error.c_str();
}

nph_status guarded(const void* handle, const char* call, void (*body)(void*), void* closure) noexcept {
  nph_status status = NPH_OK;
  std::string message;
  try {
    body(closure);
    return NPH_OK;
  } catch (const ApiError& e) {
    status = e.status();
    message = e.what();
  } catch (const InputError& e) {
    status = NPH_ERROR_INPUT;
    message = e.what();
  } catch (const IoError& e) {
    status = NPH_ERROR_INPUT;
    message = e.what();
  } catch (const GlError& e) {
    status = NPH_ERROR_GL;
    message = e.what();
  } catch (const UsageError& e) {
    status = NPH_ERROR_INVALID_ARGUMENT;
    message = e.what();
  } catch (const std::bad_alloc&) {
    status = NPH_ERROR_OUT_OF_MEMORY;
    message = "out of memory";
  } catch (const std::exception& e) {
    status = NPH_ERROR_INTERNAL;
    message = e.what();
  } catch (...) {
    status = NPH_ERROR_INTERNAL;
    message = "unknown exception";
  }
  try {
    const std::string text = std::string(call) + ": " + message;
    setLastError(handle, text);
    log::debug("plugin API: {}", text);
  } catch (...) {
    // Out of memory while recording the message: the status still says what happened.
  }
  return status;
}

}  // namespace nph::api
