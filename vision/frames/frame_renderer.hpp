#pragma once
// Synthetic camera frames for tests and the simulator (docs/simulator.md): the one place that renders a
// lamp. Model of a frame, in DN:
//   sky(u, v)   = sky_level + sky_gradient_u·(u − W/2) + sky_gradient_v·(v − H/2)
//   spot(u, v)  = F·Ex(u)·Ey(v),  F = peak·2πσ²,  Ex(u) = ½[erf((u+½−u0)/(√2σ)) − erf((u−½−u0)/(√2σ))]
//                 (a Gaussian PSF integrated over each pixel, not point-sampled)
//   hot pixels  add a fixed excess at fixed positions (the same in every frame)
//   noise       Gaussian with variance read_noise² + signal/gain (signal-dependent "shot" part
//               only when gain > 0), from a seeded generator: the same seed gives the same frame
//   output      rounded, clipped to [0, 2^bits − 1] (saturation), CV_8UC1 or CV_16UC1
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "config/deterministic_random.hpp"

namespace rangecal {

/// A Gaussian spot: the lamp or a distractor light. `peak` is the amplitude of the continuous
/// Gaussian at its centre (DN above the sky); pixel values are its integral over each pixel.
struct PsfSpot {
  double u = 0, v = 0;    ///< centre (px, docs/conventions.md convention)
  double sigma_px = 1.2;  ///< PSF standard deviation (px)
  double peak = 100;      ///< DN
};

struct HotPixel {
  int u = 0, v = 0;
  double excess = 1000;  ///< DN added to the pixel (clipped at saturation)
};

struct FrameRenderSettings {
  int width = 1280, height = 800;
  int bits = 8;                   ///< 8 → CV_8UC1; 9…16 → CV_16UC1 with values < 2^bits
  double sky_level = 40;          ///< DN at the image centre
  double sky_gradient_u = 0.01;   ///< DN per px
  double sky_gradient_v = -0.02;  ///< DN per px
  double read_noise = 2.0;        ///< DN (1σ)
  double gain = 0;                ///< e⁻ per DN for shot noise; 0 = no signal-dependent noise
  std::vector<HotPixel> hot_pixels;
  std::vector<PsfSpot> static_lights;  ///< distractors that stay in place (e.g. a lamp on a mast)
};

/// Renders one frame with the given spots (usually the lamp, or none). Deterministic in `seed`.
cv::Mat render_frame(const FrameRenderSettings& settings, const std::vector<PsfSpot>& spots,
                     std::uint64_t seed);

/// Adds F·Ex·Ey of `spot` (pixel-integrated Gaussian) to a CV_64FC1 image, within ±(5σ+1) px.
void add_psf_spot(cv::Mat& image_f64, const PsfSpot& spot);

/// `n` hot pixels at positions drawn from `seed` (away from the border), excess in [lo, hi] DN.
std::vector<HotPixel> random_hot_pixels(int width, int height, int n, double lo, double hi,
                                        std::uint64_t seed);

/// Writes a frame as PNG or TIFF (by extension). Throws rangecal::Error (input) on failure.
void write_frame_image(const std::string& path, const cv::Mat& image);

}  // namespace rangecal
