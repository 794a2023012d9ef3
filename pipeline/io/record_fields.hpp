#pragma once
// The field readers the stage records of run.json share (calibrate_record, gnss_record,
// align_record, detect_record, intersect_record; docs/outputs.md): a key that is missing keeps the
// field's default, a value of the wrong type throws rangecal::Error (input) naming the file and the
// field's JSON path.
#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "config/json_view.hpp"

namespace rangecal {

/// A non-negative integer; 0 when missing.
std::size_t count_field(const JsonView& v, const std::string& key);
/// An integer; 0 when missing.
std::int64_t integer_field(const JsonView& v, const std::string& key);
/// A number, or null read as NaN (non-finite figures are written as null); `fallback` when missing.
double number_field(const JsonView& v, const std::string& key, double fallback = 0);
/// A string; "" when missing.
std::string string_field(const JsonView& v, const std::string& key);
/// A boolean; false when missing.
bool bool_field(const JsonView& v, const std::string& key);
/// An object of non-negative integers {name: n}; empty when missing.
std::map<std::string, std::size_t> counts_field(const JsonView& v, const std::string& key);

/// Per-camera records as run.json holds them: one object per camera id, written by `write`.
template <typename Camera, typename Write>
nlohmann::json by_camera_json(const std::map<std::string, Camera>& cameras, Write write) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [id, c] : cameras) j[id] = write(c);
  return j;
}

/// The per-camera records of the object `v` ({camera id: {...}}), each read by `parse` from its view
/// (path `<v's path>.<camera id>`).
template <typename Camera, typename Parse>
std::map<std::string, Camera> parse_by_camera(const JsonView& v, Parse parse) {
  v.require_object("an object {camera id: {...}}");
  std::map<std::string, Camera> cameras;
  for (const auto& [id, c] : v.json().items())
    cameras[id] = parse(JsonView(c, v.file(), v.path() + "." + id, ErrorKind::input));
  return cameras;
}

/// `v`'s member `key` as a view, the object of a record part; none when missing.
std::optional<JsonView> object_field(const JsonView& v, const std::string& key, const std::string& what);

}  // namespace rangecal
