// The frame renderer: pixel-integrated PSF, background, noise statistics, saturation, hot pixels,
// determinism, file output.
#include <gtest/gtest.h>

#include <cmath>

#include "support/paths.hpp"
#include "vision/frames/frame_renderer.hpp"
#include "vision/frames/frame_source.hpp"

using namespace rangecal;

TEST(FrameRenderer, IntegratedPsfHasExactFluxAndCentroid) {
  for (const double sigma : {0.8, 1.3, 2.0}) {
    cv::Mat f(64, 64, CV_64FC1, cv::Scalar(0));
    const PsfSpot s{30.37, 28.81, sigma, 100.0};
    add_psf_spot(f, s);
    double sum = 0, su = 0, sv = 0;
    for (int v = 0; v < f.rows; ++v)
      for (int u = 0; u < f.cols; ++u) {
        sum += f.at<double>(v, u);
        su += u * f.at<double>(v, u);
        sv += v * f.at<double>(v, u);
      }
    const double flux = 100.0 * 2 * M_PI * sigma * sigma;
    EXPECT_NEAR(sum, flux, 1e-6 * flux);
    // The centroid of a pixel-integrated Gaussian is its centre exactly (a point-sampled one is not).
    EXPECT_NEAR(su / sum, s.u, 1e-6);
    EXPECT_NEAR(sv / sum, s.v, 1e-6);
    // Central pixel value vs the closed form erf product.
    const double k = 1 / (std::sqrt(2.0) * sigma);
    const double ex = 0.5 * (std::erf((30.5 - s.u) * k) - std::erf((29.5 - s.u) * k));
    const double ey = 0.5 * (std::erf((28.5 - s.v) * k) - std::erf((27.5 - s.v) * k));
    EXPECT_NEAR(f.at<double>(28, 30), flux * ex * ey, 1e-9);
  }
}

TEST(FrameRenderer, DeterministicBySeed) {
  FrameRenderSettings st;
  st.width = 200;
  st.height = 100;
  const cv::Mat a = render_frame(st, {{50.2, 40.7, 1.2, 80}}, 5);
  const cv::Mat b = render_frame(st, {{50.2, 40.7, 1.2, 80}}, 5);
  const cv::Mat c = render_frame(st, {{50.2, 40.7, 1.2, 80}}, 6);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.0);
}

TEST(FrameRenderer, BackgroundAndNoiseStatistics) {
  FrameRenderSettings st;
  st.width = 400;
  st.height = 300;
  st.bits = 16;
  st.sky_level = 1000;
  st.sky_gradient_u = 0.5;
  st.sky_gradient_v = -0.25;
  st.read_noise = 4;
  st.gain = 0;
  const cv::Mat m = render_frame(st, {}, 1);
  cv::Mat d;
  m.convertTo(d, CV_64F);
  // Remove the exact model background; what is left is the noise.
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) d.at<double>(v, u) -= 1000 + 0.5 * (u - 200) - 0.25 * (v - 150);
  cv::Scalar mean, sd;
  cv::meanStdDev(d, mean, sd);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  EXPECT_NEAR(sd[0], std::sqrt(16 + 1.0 / 12), 0.08);  // read noise + rounding
  // Shot noise: variance read² + signal/gain.
  st.sky_gradient_u = st.sky_gradient_v = 0;
  st.gain = 2.0;
  const cv::Mat s = render_frame(st, {}, 2);
  cv::meanStdDev(s, mean, sd);
  EXPECT_NEAR(sd[0], std::sqrt(16 + 1000 / 2.0 + 1.0 / 12), 0.3);
}

TEST(FrameRenderer, SaturationHotPixelsAndStaticLights) {
  FrameRenderSettings st;
  st.width = 320;
  st.height = 240;
  st.bits = 8;
  st.hot_pixels = random_hot_pixels(st.width, st.height, 5, 100, 200, 3);
  st.static_lights = {{100.5, 100.5, 1.5, 120}};
  const cv::Mat a = render_frame(st, {{200.3, 120.6, 1.5, 2000}}, 1);
  const cv::Mat b = render_frame(st, {}, 2);
  // The lamp's core is clipped at 255.
  int n_sat = 0;
  for (int v = 115; v < 127; ++v)
    for (int u = 194; u < 207; ++u) n_sat += a.at<std::uint8_t>(v, u) == 255;
  EXPECT_GT(n_sat, 4);
  // Hot pixels and the static light are in place in every frame.
  for (const HotPixel& h : st.hot_pixels) {
    EXPECT_GT(a.at<std::uint8_t>(h.v, h.u), 40 + 80);
    EXPECT_GT(b.at<std::uint8_t>(h.v, h.u), 40 + 80);
  }
  EXPECT_GT(b.at<std::uint8_t>(100, 100), 40 + 60);
}

TEST(FrameRenderer, WritesPngAndTiff) {
  const auto dir = test::scratch_dir("renderer_io");
  FrameRenderSettings st;
  st.width = 96;
  st.height = 64;
  for (const int bits : {8, 16}) {
    st.bits = bits;
    st.sky_level = bits == 8 ? 40 : 4000;
    const cv::Mat m = render_frame(st, {{40.2, 30.1, 1.0, 100}}, 9);
    for (const char* ext : {".png", ".tif"}) {
      const std::string p = (dir / ("f" + std::to_string(bits) + ext)).string();
      write_frame_image(p, m);
      int b = 0;
      const cv::Mat back = decode_image_file(p, &b);
      EXPECT_EQ(b, bits == 8 ? 8 : 16);
      EXPECT_EQ(cv::norm(back, m, cv::NORM_INF), 0.0) << p;
    }
  }
}
