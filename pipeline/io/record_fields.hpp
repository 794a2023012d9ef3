#pragma once
// The field readers the stage records of run.json share (calibrate_record, gnss_record,
// align_record, detect_record, intersect_record; docs/outputs.md): a key that is missing keeps the
// field's default, a value of the wrong type throws rangecal::Error (input) naming the file and the
// field's JSON path.
#include <cstddef>
#include <cstdint>
#include <map>
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

/// `v`'s member `key` as a view, the object of a record part; none when missing.
std::optional<JsonView> object_field(const JsonView& v, const std::string& key, const std::string& what);

}  // namespace rangecal
