#include "config/csv_table.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/physical_ranges.hpp"
#include "config/text_encoding.hpp"
#include "config/utf8_check.hpp"

namespace rangecal {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string> split_trim(std::string_view line, char sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = line.find(sep, start);
    out.emplace_back(
        trim(line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start)));
    if (pos == std::string_view::npos) break;
    start = pos + 1;
  }
  return out;
}

std::optional<double> parse_double(std::string_view s) {
  s = trim(s);
  if (s.empty()) return std::nullopt;
  // std::from_chars for double is in libstdc++ 11+; it neither accepts a leading '+' nor skips blanks.
  if (s.front() == '+') s.remove_prefix(1);
  double v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<std::int64_t> parse_int64(std::string_view s) {
  s = trim(s);
  if (s.empty()) return std::nullopt;
  if (s.front() == '+') s.remove_prefix(1);
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string read_file_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw_input_error(path, 0, "", "cannot open file (missing or unreadable)");
  std::ostringstream ss;
  ss << f.rdbuf();
  if (f.bad()) throw_input_error(path, 0, "", "read error");
  return ss.str();
}

CsvTable parse_csv(const std::string& file_text, const std::string& path) {
  const std::string_view text = strip_utf8_bom(file_text);
  CsvTable t;
  t.path = path;
  long line_no = 0;
  std::size_t pos = 0;
  bool have_header = false;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    const std::string_view tl = trim(line);
    if (tl.empty() || tl.front() == '#') continue;
    require_utf8(tl, path, line_no, "");
    auto fields = split_trim(tl, ',');
    if (!have_header) {
      t.header = std::move(fields);
      t.header_line = line_no;
      have_header = true;
      continue;
    }
    if (fields.size() != t.header.size()) {
      throw_input_error(
          path, line_no, "",
          "expected " + std::to_string(t.header.size()) + " comma-separated fields (" +
              [&] {
                std::string h;
                for (std::size_t i = 0; i < t.header.size(); ++i) h += (i ? "," : "") + t.header[i];
                return h;
              }() +
              "), found " + std::to_string(fields.size()));
    }
    t.records.push_back(CsvRecord{line_no, std::move(fields)});
  }
  if (!have_header) throw_input_error(path, 0, "", "file is empty (no header line)");
  return t;
}

CsvTable read_csv(const std::string& path) {
  return parse_csv(read_file_text(path), path);
}

std::optional<std::size_t> CsvTable::find_column(const std::string& name) const {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  return std::nullopt;
}

std::size_t CsvTable::column(const std::string& name) const {
  if (auto c = find_column(name)) return *c;
  std::string h;
  for (std::size_t i = 0; i < header.size(); ++i) h += (i ? "," : "") + header[i];
  throw_input_error(path, 1, name, "header lacks this column (header is '" + h + "')");
}

const std::string& CsvTable::text(const CsvRecord& r, std::size_t col) const {
  return r.fields.at(col);
}

double CsvTable::number(const CsvRecord& r, std::size_t col) const {
  const auto v = parse_double(r.fields.at(col));
  if (!v) throw_input_error(path, r.line, header.at(col), "'" + r.fields[col] + "' is not a finite number");
  return *v;
}

double CsvTable::number_in(const CsvRecord& r, std::size_t col, double lo, double hi,
                           const std::string& what) const {
  const double v = number(r, col);
  if (v < lo || v > hi) {
    throw_input_error(path, r.line, header.at(col),
                      "'" + r.fields[col] + "' is outside " + fmt::format("[{:.10g}, {:.10g}]", lo, hi) +
                          " (" + what + ")");
  }
  return v;
}

std::array<double, 3> CsvTable::site_enu(const CsvRecord& r, std::size_t ce, std::size_t cn,
                                         std::size_t cu) const {
  const double w = ranges::kSiteHalfWidthM, h = ranges::kSiteHalfHeightM;
  return {number_in(r, ce, -w, w, "site ENU, m"), number_in(r, cn, -w, w, "site ENU, m"),
          number_in(r, cu, -h, h, "site ENU, m")};
}

std::int64_t CsvTable::integer(const CsvRecord& r, std::size_t col) const {
  const auto v = parse_int64(r.fields.at(col));
  if (!v) throw_input_error(path, r.line, header.at(col), "'" + r.fields[col] + "' is not an integer");
  return *v;
}

}  // namespace rangecal
