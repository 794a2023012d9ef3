#include "vision/frames/frame_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "config/error.hpp"

namespace rangecal {

void add_psf_spot(cv::Mat& img, const PsfSpot& s) {
  CV_Assert(img.type() == CV_64FC1);
  const double sig = s.sigma_px;
  const double flux = s.peak * 2.0 * M_PI * sig * sig;
  const int r = static_cast<int>(std::ceil(5.0 * sig)) + 1;
  const int u_lo = std::max(0, static_cast<int>(std::floor(s.u)) - r);
  const int u_hi = std::min(img.cols - 1, static_cast<int>(std::floor(s.u)) + r + 1);
  const int v_lo = std::max(0, static_cast<int>(std::floor(s.v)) - r);
  const int v_hi = std::min(img.rows - 1, static_cast<int>(std::floor(s.v)) + r + 1);
  if (u_lo > u_hi || v_lo > v_hi) return;
  const double k = 1.0 / (std::sqrt(2.0) * sig);
  std::vector<double> ex(static_cast<std::size_t>(u_hi - u_lo + 1));
  for (int u = u_lo; u <= u_hi; ++u)
    ex[static_cast<std::size_t>(u - u_lo)] =
        0.5 * (std::erf((u + 0.5 - s.u) * k) - std::erf((u - 0.5 - s.u) * k));
  for (int v = v_lo; v <= v_hi; ++v) {
    const double ey = 0.5 * (std::erf((v + 0.5 - s.v) * k) - std::erf((v - 0.5 - s.v) * k));
    double* row = img.ptr<double>(v);
    for (int u = u_lo; u <= u_hi; ++u) row[u] += flux * ey * ex[static_cast<std::size_t>(u - u_lo)];
  }
}

cv::Mat render_frame(const FrameRenderSettings& st, const std::vector<PsfSpot>& spots, std::uint64_t seed) {
  CV_Assert(st.width > 0 && st.height > 0 && st.bits >= 8 && st.bits <= 16);
  cv::Mat f(st.height, st.width, CV_64FC1);
  const double cu = 0.5 * st.width, cv_ = 0.5 * st.height;
  for (int v = 0; v < st.height; ++v) {
    double* row = f.ptr<double>(v);
    const double base = st.sky_level + st.sky_gradient_v * (v - cv_);
    for (int u = 0; u < st.width; ++u) row[u] = base + st.sky_gradient_u * (u - cu);
  }
  for (const PsfSpot& s : st.static_lights) add_psf_spot(f, s);
  for (const PsfSpot& s : spots) add_psf_spot(f, s);
  for (const HotPixel& h : st.hot_pixels)
    if (h.u >= 0 && h.u < st.width && h.v >= 0 && h.v < st.height) f.at<double>(h.v, h.u) += h.excess;

  const double max_value = std::ldexp(1.0, st.bits) - 1.0;
  cv::Mat out(st.height, st.width, st.bits == 8 ? CV_8UC1 : CV_16UC1);
  RenderRandom rng(seed);
  const double rn2 = st.read_noise * st.read_noise;
  const double inv_gain = st.gain > 0 ? 1.0 / st.gain : 0.0;
  for (int v = 0; v < st.height; ++v) {
    const double* in = f.ptr<double>(v);
    for (int u = 0; u < st.width; ++u) {
      const double signal = in[u];
      const double sd = std::sqrt(rn2 + std::max(signal, 0.0) * inv_gain);
      const double x = std::clamp(std::nearbyint(signal + sd * rng.normal()), 0.0, max_value);
      if (st.bits == 8)
        out.ptr<std::uint8_t>(v)[u] = static_cast<std::uint8_t>(x);
      else
        out.ptr<std::uint16_t>(v)[u] = static_cast<std::uint16_t>(x);
    }
  }
  return out;
}

std::vector<HotPixel> random_hot_pixels(int width, int height, int n, double lo, double hi,
                                        std::uint64_t seed) {
  RenderRandom rng(seed);
  std::vector<HotPixel> out;
  for (int i = 0; i < n; ++i) {
    HotPixel h;
    h.u = 4 + static_cast<int>(rng.uniform() * (width - 8));
    h.v = 4 + static_cast<int>(rng.uniform() * (height - 8));
    h.excess = lo + (hi - lo) * rng.uniform();
    out.push_back(h);
  }
  return out;
}

void write_frame_image(const std::string& path, const cv::Mat& image) {
  std::error_code ec;
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  bool ok = false;
  try {
    ok = cv::imwrite(path, image);
  } catch (const cv::Exception& e) {
    throw_input_error(path, 0, "", std::string("cannot write image: ") + e.what());
  }
  if (!ok) throw_input_error(path, 0, "", "cannot write image (unsupported extension or unwritable folder)");
}

}  // namespace rangecal
