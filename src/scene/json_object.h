#pragma once
// Strict reading of JSON objects for scene and keyframe files (docs/scene-file.md): every key must
// be asked for or finish() reports it as unknown, and every error names the file and the JSON path
// ("scene.json: camera.fov_deg: expected a number, got a string"). Internal to src/scene.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace nph::scene {
struct CameraSpec;
}

namespace nph::scene::json_detail {

using json = nlohmann::json;

inline std::string typeName(const json& j) {
  switch (j.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return "a boolean";
    case json::value_t::string: return "a string";
    case json::value_t::array: return "an array";
    case json::value_t::object: return "an object";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: return "a number";
    default: return "an unsupported value";
  }
}

/// A JSON object being read: every key must be asked for, or finish() reports it as unknown.
class Object {
 public:
  Object(const json& j, std::string path, const std::string& file, const std::string& base_dir)
      : j_(j), path_(std::move(path)), file_(file), base_(base_dir) {
    if (!j.is_object()) fail(path_, "expected an object, got " + typeName(j));
  }

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(fmt::format("{}: {}: {}", file_, where.empty() ? "(top level)" : where, what));
  }
  std::string at(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
  }
  const json* get(std::string_view key) {
    known_.emplace_back(key);
    const auto it = j_.find(std::string(key));
    return it == j_.end() ? nullptr : &*it;
  }
  bool has(std::string_view key) const { return j_.contains(std::string(key)); }

  std::optional<double> optNumber(std::string_view key, double lo, double hi) {
    const json* v = get(key);
    if (!v) return std::nullopt;
    if (!v->is_number()) fail(at(key), "expected a number, got " + typeName(*v));
    const double d = v->get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) {
      fail(at(key), fmt::format("expected a number in [{}, {}], got {}", lo, hi, d));
    }
    return d;
  }
  double number(std::string_view key, double def, double lo, double hi) { return optNumber(key, lo, hi).value_or(def); }
  int integer(std::string_view key, int def, int lo, int hi) {
    const json* v = get(key);
    if (!v) return def;
    if (!v->is_number() || !(std::floor(v->get<double>()) == v->get<double>())) {
      fail(at(key), "expected an integer, got " + (v->is_number() ? v->dump() : typeName(*v)));
    }
    const double d = v->get<double>();
    if (d < lo || d > hi) fail(at(key), fmt::format("expected an integer in [{}, {}], got {}", lo, hi, d));
    return static_cast<int>(d);
  }
  bool boolean(std::string_view key, bool def) {
    const json* v = get(key);
    if (!v) return def;
    if (!v->is_boolean()) fail(at(key), "expected true or false, got " + typeName(*v));
    return v->get<bool>();
  }
  std::optional<std::string> optString(std::string_view key) {
    const json* v = get(key);
    if (!v) return std::nullopt;
    if (!v->is_string()) fail(at(key), "expected a string, got " + typeName(*v));
    return v->get<std::string>();
  }
  std::string path(std::string_view key, bool required) {
    const auto s = optString(key);
    if (!s) {
      if (required) fail(at(key), "required (a file path)");
      return {};
    }
    if (s->empty()) fail(at(key), "expected a file path, got an empty string");
    const std::filesystem::path p(*s);
    return p.is_absolute() || base_.empty() ? *s : (std::filesystem::path(base_) / p).lexically_normal().string();
  }
  template <std::size_t N>
  std::optional<std::array<double, N>> optNumbers(std::string_view key) {
    const json* v = get(key);
    if (!v) return std::nullopt;
    if (!v->is_array() || v->size() != N) {
      fail(at(key), fmt::format("expected an array of {} numbers, got {}", N,
                                v->is_array() ? fmt::format("{} elements", v->size()) : typeName(*v)));
    }
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) {
      const json& e = (*v)[i];
      if (!e.is_number() || !std::isfinite(e.get<double>())) {
        fail(fmt::format("{}[{}]", at(key), i), "expected a number, got " + typeName(e));
      }
      out[i] = e.get<double>();
    }
    return out;
  }
  std::optional<glm::dvec3> optVec3(std::string_view key) {
    const auto a = optNumbers<3>(key);
    if (!a) return std::nullopt;
    return glm::dvec3((*a)[0], (*a)[1], (*a)[2]);
  }
  std::optional<Object> optObject(std::string_view key) {
    const json* v = get(key);
    if (!v) return std::nullopt;
    return Object(*v, at(key), file_, base_);
  }
  /// The value whose name is the key's string (`options`: pairs of name and value, a braced list
  /// or a table such as animation_spec.h kTimeInterpolationNames); `def` when the key is absent.
  template <class E, class Options = std::initializer_list<std::pair<const char*, E>>>
  E choice(std::string_view key, E def, const Options& options) {
    const auto s = optString(key);
    if (!s) return def;
    std::string list;
    for (const auto& [name, value] : options) {
      if (*s == name) return value;
      list += (list.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    }
    fail(at(key), fmt::format("expected one of {}, got \"{}\"", list, *s));
  }
  /// Unknown keys are errors (typos must not silently become defaults).
  void finish() const {
    for (const auto& [key, value] : j_.items()) {
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        std::string list;
        for (const auto& k : known_) list += (list.empty() ? "" : ", ") + k;
        fail(at(key), fmt::format("unknown key (expected one of: {})", list));
      }
    }
  }
  const std::string& where() const { return path_; }
  const std::string& file() const { return file_; }
  const std::string& baseDir() const { return base_; }
  const json& value() const { return j_; }

 private:
  const json& j_;
  std::string path_;
  const std::string& file_;
  const std::string& base_;
  std::vector<std::string> known_;
};

/// The keys of a "camera" object (docs/scene-file.md), shared by scene files and camera keyframes;
/// calls c.finish().
void parseCameraObject(Object& c, CameraSpec& cam);

}  // namespace nph::scene::json_detail
