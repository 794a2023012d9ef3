#include "pipeline/mission/stage_options.hpp"

#include "config/error.hpp"
#include "vision/tracks/track_formats.hpp"
#include "vision/tracks/track_frame_times.hpp"

namespace rangecal {

FrameSourceOptions frame_source_options(const CameraConfig& camera) {
  FrameSourceOptions o;
  o.width_px = camera.sensor.width_px;
  o.height_px = camera.sensor.height_px;
  o.allow_missing = camera.frames.allow_missing;
  return o;
}

FrameSource open_camera_frames(const MissionConfig& cfg, const CameraConfig& camera) {
  const FrameSourceOptions o = frame_source_options(camera);
  if (!camera.frames.timestamps.empty()) return FrameSource::from_timestamps_csv(camera.frames.timestamps, o);
  if (!camera.frames.cine.empty()) return FrameSource::from_cine(camera.frames.cine, o);
  if (!camera.frames.mraw.empty())
    return FrameSource::from_mraw(camera.frames.mraw, o, camera.frames.clock_utc_offset_h);
  throw_config_error(cfg.config_path, "cameras[" + camera.id + "].frames",
                     "none of `timestamps`, `cine` or `mraw` is set");
}

SensorGeometry sensor_geometry(const SensorConfig& sensor) {
  SensorGeometry g;
  g.width_px = sensor.width_px;
  g.height_px = sensor.height_px;
  g.dx_mm = sensor.pixel_size_um[0] * 1e-3;
  g.dy_mm = sensor.pixel_size_um[1] * 1e-3;
  return g;
}

CameraTrackInput read_camera_track(const CameraConfig& camera) {
  return read_track_input(*camera.track);
}

CameraTrackInput read_track_input(const TrackConfig& tc) {
  CameraTrackInput in;
  in.track = read_image_track(tc.file, tc.format, tc.read);
  if (!tc.timestamps.empty()) {
    in.times = track_times_from_csv(in.track, tc.timestamps);
    in.time_source = "track timestamps CSV";
  } else {
    in.times = track_times_from_rate(in.track, *tc.t0_utc, tc.t0_frame, tc.fps);
    in.time_source = "track t0 + frame/fps";
  }
  return in;
}

LampDetectorOptions lamp_detector_options(const DetectConfig& detect) {
  LampDetectorOptions o;
  o.min_snr = detect.min_snr;
  return o;
}

}  // namespace rangecal
