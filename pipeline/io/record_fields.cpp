#include "pipeline/io/record_fields.hpp"

#include <cmath>
#include <limits>

namespace rangecal {

std::size_t count_field(const JsonView& v, const std::string& key, std::size_t fallback) {
  const auto x = v.find(key);
  return x ? static_cast<std::size_t>(x->unsigned_integer("a non-negative integer")) : fallback;
}

std::int64_t integer_field(const JsonView& v, const std::string& key, std::int64_t fallback) {
  const auto x = v.find(key);
  return x ? x->integer("an integer") : fallback;
}

int int_field(const JsonView& v, const std::string& key, int fallback) {
  return static_cast<int>(integer_field(v, key, fallback));
}

double number_field(const JsonView& v, const std::string& key, double fallback) {
  const auto x = v.find(key);
  if (!x) return fallback;
  if (x->json().is_null()) return std::numeric_limits<double>::quiet_NaN();
  // A record not yet written (a stage's own log) holds NaN where run.json's text holds null.
  if (x->json().is_number_float() && std::isnan(x->json().get<double>())) return x->json().get<double>();
  return x->number("a number or null");
}

std::string string_field(const JsonView& v, const std::string& key, const std::string& fallback) {
  const auto x = v.find(key);
  return x ? x->string("a string") : fallback;
}

bool bool_field(const JsonView& v, const std::string& key, bool fallback) {
  const auto x = v.find(key);
  return x ? x->boolean("true or false") : fallback;
}

std::map<std::string, std::size_t> counts_field(const JsonView& v, const std::string& key) {
  std::map<std::string, std::size_t> out;
  const auto x = object_field(v, key, "an object {name: count}");
  if (!x) return out;
  for (const auto& [name, n] : x->json().items())
    out[name] = static_cast<std::size_t>(JsonView(n, v.file(), x->path() + "." + name, ErrorKind::input)
                                             .unsigned_integer("a non-negative integer"));
  return out;
}

std::optional<JsonView> object_field(const JsonView& v, const std::string& key, const std::string& what) {
  const auto x = v.find(key);
  if (x) x->require_object(what);
  return x;
}

}  // namespace rangecal
