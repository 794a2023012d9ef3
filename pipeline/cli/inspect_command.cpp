// `rangecal inspect FILE… [--json]` (docs/cli.md "rangecal inspect"): each file's kind, size,
// dimensions and bit depth, rate, time system, UTC span, counts and flags; with several files their
// spans side by side, a coarse timeline and each pair's overlap or gap with its likely cause. The
// facts come from pipeline/steps/file_inspection (each format's own layer gathers them); this file
// only prints them.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/steps/file_inspection.hpp"

namespace rangecal {

namespace {

constexpr int kTimelineColumns = 60;

std::string inspect_row(const std::string& label, const std::string& value) {
  return fmt::format("  {:<36} {}\n", label, value);
}

// 2775328 → "2,775,328".
std::string grouped(std::uint64_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

std::string dimensions(const FileFacts& f) {
  std::string s;
  if (f.width_px && f.height_px)
    s = std::to_string(*f.width_px) + " x " + std::to_string(*f.height_px) + " px";
  if (f.bits) {
    s += (s.empty() ? "" : ", ") + std::to_string(*f.bits) + " bits";
    if (f.stored_bits) s += " (" + std::to_string(*f.stored_bits) + " stored)";
  }
  return s;
}

std::string file_text(const FileFacts& f) {
  std::string s = f.path + "\n";
  s += inspect_row("kind", f.kind);
  s += inspect_row("size", grouped(f.size_bytes) + " bytes");
  if (const std::string d = dimensions(f); !d.empty()) s += inspect_row("dimensions", d);
  if (f.rate_hz) s += inspect_row("rate", format_number("%.6g", *f.rate_hz) + " Hz, " + f.rate_source);
  if (!f.time_system.empty()) s += inspect_row("time system", f.time_system);
  if (f.utc) {
    s += inspect_row("UTC first", format_iso8601_utc(f.utc->first, 6));
    s += inspect_row("UTC last", format_iso8601_utc(f.utc->last, 6));
    s += inspect_row("duration", format_number("%.6f", f.utc->duration_s()) + " s");
  } else {
    s += inspect_row("UTC span", "none");
  }
  for (const auto& [what, n] : f.counts) s += inspect_row(what, grouped(n));
  for (const auto& [label, value] : f.details) s += inspect_row(label, value);
  for (const std::string& n : f.notes) s += "  note: " + n + "\n";
  return s;
}

// One line per file over the union of the spans: '#' where the file has time stamps.
std::string timeline_text(const std::vector<FileFacts>& files) {
  std::vector<std::size_t> timed;
  for (std::size_t i = 0; i < files.size(); ++i)
    if (files[i].utc) timed.push_back(i);
  if (timed.size() < 2) return "";
  UtcTime lo = files[timed[0]].utc->first, hi = files[timed[0]].utc->last;
  for (std::size_t i : timed) lo = std::min(lo, files[i].utc->first), hi = std::max(hi, files[i].utc->last);
  const double total = std::max(seconds_between(lo, hi), 1e-9);
  std::string s = "time spans (UTC)\n";
  s += fmt::format("  {:<3} {:<26} {:<26} {:>16}  {}\n", "#", "first", "last", "duration (s)", "file");
  for (std::size_t i : timed) {
    const UtcSpan& u = *files[i].utc;
    s += fmt::format("  {:<3} {:<26} {:<26} {:>16.3f}  {}\n", i + 1, format_iso8601_utc(u.first, 3),
                     format_iso8601_utc(u.last, 3), u.duration_s(), files[i].path);
  }
  s += "timeline " + format_iso8601_utc(lo, 0) + " .. " + format_iso8601_utc(hi, 0) +
       ", one column = " + format_number("%.6g", total / kTimelineColumns) + " s\n";
  for (std::size_t i : timed) {
    const UtcSpan& u = *files[i].utc;
    const auto col = [&](UtcTime t) {
      return std::clamp(static_cast<int>(seconds_between(lo, t) / total * kTimelineColumns), 0,
                        kTimelineColumns - 1);
    };
    std::string line(kTimelineColumns, '.');
    for (int c = col(u.first); c <= col(u.last); ++c) line[static_cast<std::size_t>(c)] = '#';
    s += fmt::format("  {:<3} |{}|\n", i + 1, line);
  }
  return s;
}

std::string comparisons_text(const std::vector<FileSpanComparison>& cmp) {
  if (cmp.empty()) return "";
  std::string s = "overlap\n";
  for (const FileSpanComparison& c : cmp)
    s += "  " + std::to_string(c.a + 1) + " vs " + std::to_string(c.b + 1) + ": " +
         describe_span_comparison(c.comparison, "file " + std::to_string(c.b + 1),
                                  "file " + std::to_string(c.a + 1)) +
         "\n";
  return s;
}

nlohmann::ordered_json file_json(const FileFacts& f) {
  nlohmann::ordered_json j;
  j["path"] = f.path;
  j["kind"] = f.kind;
  j["size_bytes"] = f.size_bytes;
  j["width_px"] = f.width_px ? nlohmann::ordered_json(*f.width_px) : nullptr;
  j["height_px"] = f.height_px ? nlohmann::ordered_json(*f.height_px) : nullptr;
  j["bits"] = f.bits ? nlohmann::ordered_json(*f.bits) : nullptr;
  j["stored_bits"] = f.stored_bits ? nlohmann::ordered_json(*f.stored_bits) : nullptr;
  j["rate_hz"] = f.rate_hz ? nlohmann::ordered_json(*f.rate_hz) : nullptr;
  j["rate_source"] = f.rate_source;
  j["time_system"] = f.time_system;
  if (f.utc)
    j["utc"] = {{"first", format_iso8601_utc(f.utc->first)},
                {"last", format_iso8601_utc(f.utc->last)},
                {"duration_s", f.utc->duration_s()}};
  else
    j["utc"] = nullptr;
  j["counts"] = nlohmann::ordered_json::object();
  for (const auto& [what, n] : f.counts) j["counts"][what] = n;
  j["details"] = nlohmann::ordered_json::object();
  for (const auto& [label, value] : f.details) j["details"][label] = value;
  j["notes"] = f.notes;
  return j;
}

std::string inspect_json(const std::vector<FileFacts>& files, const std::vector<FileSpanComparison>& cmp,
                         const std::vector<std::string>& errors) {
  nlohmann::ordered_json j;
  j["files"] = nlohmann::ordered_json::array();
  for (const FileFacts& f : files) j["files"].push_back(file_json(f));
  j["comparisons"] = nlohmann::ordered_json::array();
  for (const FileSpanComparison& c : cmp) {
    const SpanComparison& s = c.comparison;
    j["comparisons"].push_back({{"a", files[c.a].path},
                                {"b", files[c.b].path},
                                {"relation", to_string(s.relation)},
                                {"likely_cause", likely_cause(s)},
                                {"overlap_s", s.overlap_s},
                                {"gap_s", s.gap_s},
                                {"offset_min_s", s.offset_min_s},
                                {"offset_max_s", s.offset_max_s},
                                {"cause_offset_s", s.cause_offset_s}});
  }
  j["errors"] = errors;
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace

void add_inspect_command(CLI::App& app, const CliContext& ctx) {
  struct Args {
    std::vector<std::string> files;
    bool json = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "inspect",
      "Show each file's kind, size, dimensions, rate, time system, UTC span and counts; with several "
      "files, their spans side by side and their overlap");
  sub->add_option("FILE", args->files, "Input files (.pos .ulg .bin .cine .mraw/.cihx/.cih, CSVs, video)")
      ->required();
  sub->add_flag("--json", args->json, "Print JSON instead of the table");
  sub->callback([args, &ctx]() {
    // Every file is read; a bad one does not hide the others' facts, and the exit code says it.
    std::vector<FileFacts> files;
    std::vector<Error> errors;
    for (const std::string& p : distinct_recordings(args->files)) {
      try {
        files.push_back(inspect_input_file(p));
      } catch (const Error& e) {
        errors.push_back(e);
      }
    }
    const std::vector<FileSpanComparison> cmp = compare_file_spans(files);
    if (args->json) {
      std::vector<std::string> messages;
      for (const Error& e : errors) messages.push_back(e.what());
      std::cout << inspect_json(files, cmp, messages) << std::flush;
    } else if (!ctx.quiet) {
      std::string out;
      for (const FileFacts& f : files) out += file_text(f) + "\n";
      out += timeline_text(files);
      out += comparisons_text(cmp);
      std::cout << out << std::flush;
    }
    if (errors.empty()) return;
    for (std::size_t i = 0; i + 1 < errors.size(); ++i)
      std::cerr << "rangecal: error: " << errors[i].what() << "\n";
    throw errors.back();
  });
}

}  // namespace rangecal
