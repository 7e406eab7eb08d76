#pragma once
// Handles of the C API and the boundary every entry point goes through (STYLE.md 6: errors as
// values at the boundary, exceptions inside; after OpenFX's ofxsImageEffect.cpp).
//
// A handle is never a pointer to the object: it is a number from a process-wide counter that is
// never reused, with the kind in its low bits, looked up in a registry under a mutex. A null,
// destroyed, forged or wrong-kind handle is therefore a failed look-up (NPH_ERROR_INVALID_HANDLE),
// never a dangling dereference, and a destroyed handle cannot alias a newer object at the same
// address. Objects are held by shared_ptr, so a dataset closed on one thread while another thread
// is inside a call on it stays alive until that call returns.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "nephele/nephele.h"

namespace nph::api {

/// A failure with a specific status (wrong thread, wrong order, ...). Other exceptions are
/// mapped by type: InputError/IoError → INPUT, GlError → GL, UsageError → INVALID_ARGUMENT,
/// std::bad_alloc → OUT_OF_MEMORY, anything else → INTERNAL.
class ApiError : public std::runtime_error {
 public:
  ApiError(nph_status status, const std::string& message) : std::runtime_error(message), status_(status) {}
  nph_status status() const { return status_; }

 private:
  nph_status status_;
};

enum class Kind : std::uintptr_t { Dataset = 1, Renderer = 2 };

/// Registers `object`; returns its new handle value.
const void* registerHandle(Kind kind, std::shared_ptr<void> object);
/// The object of `handle` if it is a live handle of `kind`, else nullptr.
std::shared_ptr<void> lookupHandle(const void* handle, Kind kind);
/// Removes `handle` (live, of `kind`); returns its object (the caller destroys it) or nullptr.
std::shared_ptr<void> unregisterHandle(const void* handle, Kind kind);

/// The object of a live handle of `kind`, or ApiError(INVALID_HANDLE) naming what was expected.
template <class T>
std::shared_ptr<T> require(const void* handle, Kind kind, const char* what) {
  auto object = lookupHandle(handle, kind);
  if (!object) {
    throw ApiError(
        NPH_ERROR_INVALID_HANDLE,
        std::string(what) +
            (handle == nullptr ? " is NULL" : " is not a live handle (destroyed, or not a " + std::string(what) + ")"));
  }
  return std::static_pointer_cast<T>(std::move(object));
}

/// Stores `message` as the last error of `handle` (if live) or of the calling thread.
void setLastError(const void* handle, const std::string& message);
const char* lastError(const void* handle);

/// Runs `body`, converting every exception into a status and a last-error message on `handle`.
nph_status guarded(const void* handle, const char* call, void (*body)(void*), void* closure) noexcept;

template <class F>
nph_status guarded(const void* handle, const char* call, F&& f) noexcept {
  return guarded(
      handle, call, [](void* c) { (*static_cast<F*>(c))(); }, &f);
}

}  // namespace nph::api
