#include "config/json_format.hpp"

namespace rangecal {
namespace {

// Strings from bad input may hold bytes that are not UTF-8: they become U+FFFD instead of making
// nlohmann throw (type_error 316) half way through an output file.
std::string dump_scalar(const nlohmann::ordered_json& j) {
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

bool is_scalar(const nlohmann::ordered_json& j) {
  return !j.is_array() && !j.is_object();
}

bool all_scalars(const nlohmann::ordered_json& j) {
  for (const auto& e : j)
    if (!is_scalar(e)) return false;
  return true;
}

std::string one_line(const nlohmann::ordered_json& a) {
  std::string s = "[";
  for (std::size_t i = 0; i < a.size(); ++i) s += (i ? ", " : "") + dump_scalar(a[i]);
  return s + "]";
}

void emit(const nlohmann::ordered_json& j, int indent, std::string& out) {
  const std::string pad(indent, ' '), inner(indent + 2, ' ');
  if (j.is_object()) {
    if (j.empty()) {
      out += "{}";
      return;
    }
    out += "{\n";
    std::size_t i = 0;
    for (auto it = j.begin(); it != j.end(); ++it, ++i) {
      out += inner + dump_scalar(nlohmann::ordered_json(it.key())) + ": ";
      emit(it.value(), indent + 2, out);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += pad + "}";
  } else if (j.is_array()) {
    if (all_scalars(j)) {
      out += one_line(j);
      return;
    }
    out += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      out += inner;
      emit(j[i], indent + 2, out);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += pad + "]";
  } else {
    out += dump_scalar(j);
  }
}

}  // namespace

std::string dump_json_compact_arrays(const nlohmann::ordered_json& j) {
  std::string out;
  emit(j, 0, out);
  out += "\n";
  return out;
}

}  // namespace rangecal
