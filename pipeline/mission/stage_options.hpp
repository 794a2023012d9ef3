#pragma once
// The mission config mapped onto the option structs of the layers below (gnss, vision, optim take
// their own options and never the config): the one place that knows which config key feeds which
// option. Defaults of keys the config leaves out are the options' own.
#include "pipeline/mission/mission_config.hpp"
#include "vision/camera/sensor_geometry.hpp"
#include "vision/detection/lamp_detector.hpp"
#include "vision/frames/frame_source.hpp"
#include "vision/tracks/image_track.hpp"

namespace rangecal {

/// `cameras[i].sensor` (required frame size) and `cameras[i].frames.allow_missing`.
FrameSourceOptions frame_source_options(const CameraConfig& camera);

/// The camera's frames: its `frames.timestamps` CSV, or its `frames.cine` or `frames.mraw` alone
/// (the .mraw timed by its header and frames.clock_utc_offset_h). Throws
/// rangecal::Error (usage) naming `cameras[].frames` when neither is set.
FrameSource open_camera_frames(const MissionConfig& cfg, const CameraConfig& camera);

/// The sensor a camera's config states (image size, pixel pitch in mm), as the initialisers and the
/// clock take it.
SensorGeometry sensor_geometry(const SensorConfig& sensor);

/// A camera's imported 2-D track (cameras[i].track) with its frames' times as the config gives them
/// (UTC, or nominal when the clock is estimated).
struct CameraTrackInput {
  ImageTrack track;
  std::vector<UtcTime> times;  ///< one per track.points
  std::string time_source;     ///< for run.json: "track timestamps CSV" or "track t0 + frame/fps"
};
/// Reads cameras[i].track (vision/tracks/). Throws rangecal::Error (input) naming the file, line and
/// field.
CameraTrackInput read_camera_track(const CameraConfig& camera);
/// Reads any track config (a camera's track or its target_track) the same way.
CameraTrackInput read_track_input(const TrackConfig& track);

/// `detect.min_snr`; the other detector options at their defaults.
LampDetectorOptions lamp_detector_options(const DetectConfig& detect);

}  // namespace rangecal
