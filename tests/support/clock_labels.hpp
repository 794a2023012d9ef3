#pragma once
// A camera without time code and the lamp it watched, simulated for the clock's tests and benchmark
// (pipeline/steps/camera_clock.hpp): a lamp flying a Lissajous figure 64 m in front of a seed-002
// range camera, its exact track at 5 Hz (stated sd 1 cm), and the camera's labels at a frame rate
// whose nominal times are off by a chosen offset and rate.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "gnss/track/lamp_track.hpp"
#include "pipeline/steps/camera_clock.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal::test {

inline constexpr double kClockStart = 1.8e9;  ///< s: the lamp track's first epoch (UTC seconds)

/// The lamp at UTC second t: 4.5 × 2.0 × 2.6 m Lissajous, 1–5 m/s, climbing and sinking.
Eigen::Vector3d lamp_at(double t);

/// UTC second → UtcTime.
UtcTime utc(double seconds);

/// The exact lamp track from kClockStart for `duration_s`, 5 Hz, sd 1 cm per axis, Q 1.
LampTrack lamp_track(double duration_s);

struct Labels {
  std::vector<ClockObservation> labels;
  std::vector<double> truth_s;  ///< each label's true time
};

/// `n` frames at `fps`; frame k's true time is first_true_s + k/fps·(1 + rate), its nominal time that
/// less `offset_s` with the rate left out, so the clock to find is (offset_s, rate). Labels: the
/// lamp's projection + N(0, noise_px²) per axis, frames whose lamp is outside the image left out.
Labels labels_of(const Camera& cam, double first_true_s, double offset_s, double rate, double fps, int n,
                 double noise_px, std::uint64_t seed);

/// The camera's image size and pixel pitch.
SensorGeometry sensor_of(const Camera& cam);

/// The range camera at (0, 0, 1.5) looking at (0, 64, 7.5), principal point (652, 391), k1 −3.4e-4.
Camera wide_camera();

}  // namespace rangecal::test
