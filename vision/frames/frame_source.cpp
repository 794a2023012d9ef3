#include "vision/frames/frame_source.hpp"

#include <utility>

#include "config/error.hpp"

namespace rangecal {

FrameSource::FrameSource(FrameSource&&) noexcept = default;
FrameSource& FrameSource::operator=(FrameSource&&) noexcept = default;
FrameSource::~FrameSource() = default;

FrameSource FrameSource::from_timestamps_csv(const std::string& csv_path, const FrameSourceOptions& options) {
  FrameSource s;
  s.origin_ = csv_path;
  s.time_source_ = kTimeSourceCsv;
  s.entries_ = read_frame_timestamps(csv_path).entries;
  s.sensor_w_ = options.width_px;
  s.sensor_h_ = options.height_px;
  s.allow_missing_ = options.allow_missing;
  for (const FrameTimestamp& e : s.entries_) {
    const FrameFormat* format = find_frame_format(e.file);
    if (!format)
      throw_input_error(csv_path, e.line, "file",
                        "'" + e.file + "' is not a supported frame file (" + supported_frame_files() + ")");
    if (s.container_errors_.count(e.file)) continue;
    auto open = s.containers_.find(e.file);
    if (open == s.containers_.end()) {
      try {
        open = s.containers_.emplace(e.file, format->open(e.file)).first;
      } catch (const Error& err) {
        if (!options.allow_missing) throw_input_error(csv_path, e.line, "file", err.what());
        s.container_errors_[e.file] = err.what();
        continue;
      }
    }
    const std::optional<std::int64_t> n = open->second->frame_count();
    if (n && e.frame >= *n && !options.allow_missing)
      throw_input_error(csv_path, e.line, "frame",
                        "frame " + std::to_string(e.frame) + " is beyond the end of '" + e.file + "' (" +
                            std::to_string(*n) + " frames)");
  }
  return s;
}

FrameSource FrameSource::from_cine(const std::string& cine_path, const FrameSourceOptions& options) {
  return from_file_alone(frame_format(".cine"), cine_path, options, std::nullopt);
}

FrameSource FrameSource::from_mraw(const std::string& mraw_path, const FrameSourceOptions& options,
                                   std::optional<double> clock_utc_offset_h) {
  return from_file_alone(frame_format(".mraw"), mraw_path, options, clock_utc_offset_h);
}

FrameSource FrameSource::from_file_alone(const FrameFormat& format, const std::string& path,
                                         const FrameSourceOptions& options,
                                         std::optional<double> clock_utc_offset_h) {
  FrameSource s;
  s.origin_ = path;
  s.time_source_ = format.own_time_source ? format.own_time_source : "";
  s.sensor_w_ = options.width_px;
  s.sensor_h_ = options.height_px;
  std::unique_ptr<FrameContainer> container = format.open(path);
  if (!format.own_time_source)
    throw_input_error(path, 0, "",
                      std::string("the ") + format.name +
                          " format carries no frame times of its own; give a timestamps CSV");
  const std::vector<UtcTime> times = container->own_times(clock_utc_offset_h);
  s.entries_.reserve(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    FrameTimestamp e;
    e.frame = static_cast<std::int64_t>(i);
    e.file = path;
    e.utc = times[i];
    s.entries_.push_back(e);
  }
  s.containers_.emplace(path, std::move(container));
  return s;
}

std::optional<ImageFrame> FrameSource::load(std::size_t i, std::string* skip_reason) const {
  const FrameTimestamp& e = entries_.at(i);
  ImageFrame f;
  f.frame = e.frame;
  f.utc = e.utc;
  FrameDecodeProblem problem;
  const auto open = containers_.find(e.file);
  if (open != containers_.end())
    problem = open->second->decode(e.frame, sensor_w_, sensor_h_, f);
  else if (container_errors_.count(e.file))
    problem.reason = container_errors_.at(e.file);
  else
    problem.reason = "'" + e.file + "' not open";
  if (problem.wrong_size) throw_input_error(origin_, e.line, "file", problem.reason);
  if (!problem.reason.empty()) {
    if (allow_missing_) {
      if (skip_reason) *skip_reason = problem.reason;
      return std::nullopt;
    }
    throw_input_error(origin_, e.line, "file", problem.reason);
  }
  if ((sensor_w_ > 0 && f.image.cols != sensor_w_) || (sensor_h_ > 0 && f.image.rows != sensor_h_))
    throw_input_error(
        origin_, e.line, "file",
        frame_size_mismatch(e.file, e.frame, f.image.cols, f.image.rows, "", sensor_w_, sensor_h_));
  return f;
}

}  // namespace rangecal
