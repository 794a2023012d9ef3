#pragma once
// The field readers the stage records of run.json share (calibrate_record, gnss_record,
// align_record, detect_record, intersect_record; docs/outputs.md): a key that is missing keeps the
// field's default, a value of the wrong type throws rangecal::Error (input) naming the file and the
// field's JSON path. A record's scalar fields are a table of RecordField, its one list of keys,
// which write_fields writes and read_fields reads.
#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "config/json_view.hpp"

namespace rangecal {

/// A non-negative integer; `fallback` when missing.
std::size_t count_field(const JsonView& v, const std::string& key, std::size_t fallback = 0);
/// An integer; `fallback` when missing.
std::int64_t integer_field(const JsonView& v, const std::string& key, std::int64_t fallback = 0);
/// An integer held as int; `fallback` when missing.
int int_field(const JsonView& v, const std::string& key, int fallback = 0);
/// A number, or null read as NaN (non-finite figures are written as null); `fallback` when missing.
double number_field(const JsonView& v, const std::string& key, double fallback = 0);
/// A string; `fallback` when missing.
std::string string_field(const JsonView& v, const std::string& key, const std::string& fallback = "");
/// A boolean; `fallback` when missing.
bool bool_field(const JsonView& v, const std::string& key, bool fallback = false);
/// An object of non-negative integers {name: n}; empty when missing.
std::map<std::string, std::size_t> counts_field(const JsonView& v, const std::string& key);

/// One scalar field of a record `R`: its run.json key and the member that holds it.
template <typename R>
struct RecordField {
  const char* key;
  std::variant<std::size_t R::*, std::int64_t R::*, int R::*, double R::*, std::string R::*, bool R::*>
      member;
};

/// Writes each field of `fields` into the object `*j` under its key (NaN is written as null).
template <typename R, std::size_t N>
void write_fields(const RecordField<R> (&fields)[N], const R& r, nlohmann::json* j) {
  for (const RecordField<R>& f : fields) std::visit([&](auto m) { (*j)[f.key] = r.*m; }, f.member);
}

/// Reads each field of `fields` from the object `v` in the table's order, so that of several wrong
/// values the first listed is the one named; a missing key keeps the member's value.
template <typename R, std::size_t N>
void read_fields(const RecordField<R> (&fields)[N], const JsonView& v, R* r) {
  const auto read = [&v](const char* key, auto* out) {
    using T = std::remove_pointer_t<decltype(out)>;
    if constexpr (std::is_same_v<T, std::size_t>) *out = count_field(v, key, *out);
    if constexpr (std::is_same_v<T, std::int64_t>) *out = integer_field(v, key, *out);
    if constexpr (std::is_same_v<T, int>) *out = int_field(v, key, *out);
    if constexpr (std::is_same_v<T, double>) *out = number_field(v, key, *out);
    if constexpr (std::is_same_v<T, std::string>) *out = string_field(v, key, *out);
    if constexpr (std::is_same_v<T, bool>) *out = bool_field(v, key, *out);
  };
  for (const RecordField<R>& f : fields) std::visit([&](auto m) { read(f.key, &(r->*m)); }, f.member);
}

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
