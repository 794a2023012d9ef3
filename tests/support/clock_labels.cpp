#include "support/clock_labels.hpp"

#include <cmath>

#include "config/deterministic_random.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal::test {

Eigen::Vector3d lamp_at(double t) {
  const double s = t - kClockStart;
  return {4.5 * std::sin(0.45 * s), 64 + 2.0 * std::sin(0.13 * s), 7.5 + 2.6 * std::sin(0.31 * s + 0.4)};
}

UtcTime utc(double seconds) {
  return UtcTime{std::llround(seconds * 1e9)};
}

LampTrack lamp_track(double duration_s) {
  LampTrack track;
  for (double t = kClockStart; t <= kClockStart + duration_s + 1e-9; t += 0.2) {
    LampEpoch e;
    e.utc = utc(t);
    e.enu = lamp_at(t);
    e.sd_enu = Eigen::Vector3d::Constant(0.01);
    e.quality = 1;
    track.epochs.push_back(e);
  }
  return track;
}

// `n` frames at `fps`; frame k's true time is first_true_s + k/fps·(1 + rate); its nominal time is
// that less `offset_s` with the rate left out, so the clock to find is (offset_s, rate).
Labels labels_of(const Camera& cam, double first_true_s, double offset_s, double rate, double fps, int n,
                 double noise_px, std::uint64_t seed) {
  DeterministicRandom rng(seed);
  Labels out;
  for (int k = 0; k < n; ++k) {
    const double nominal = first_true_s - offset_s + k / fps;
    const double truth = first_true_s + (1 + rate) * k / fps;
    Eigen::Vector2d uv;
    if (!project(cam, lamp_at(truth), &uv)) continue;
    uv += noise_px * Eigen::Vector2d(rng.normal(), rng.normal());
    if (uv.x() < 0 || uv.y() < 0 || uv.x() > cam.intr.width_px - 1 || uv.y() > cam.intr.height_px - 1)
      continue;
    out.labels.push_back({k, utc(nominal), uv});
    out.truth_s.push_back(truth);
  }
  return out;
}

SensorGeometry sensor_of(const Camera& cam) {
  SensorGeometry s;
  s.width_px = cam.intr.width_px;
  s.height_px = cam.intr.height_px;
  s.dx_mm = cam.intr.dx_mm;
  s.dy_mm = cam.intr.dy_mm;
  return s;
}

Camera wide_camera() {
  return test::range_camera_at("cam", Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(0, 64, 7.5), -3.4e-4,
                               Eigen::Vector2d(652.0, 391.0));
}

}  // namespace rangecal::test
