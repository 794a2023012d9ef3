#include "vision/camera/opencv_distortion_fit.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rangecal {
namespace {

constexpr int kMaxCoefficients = 12;
/// Power of the normalised radius each coefficient multiplies (OpenCV order k1 k2 p1 p2 k3 k4 k5
/// k6 s1 s2 s3 s4): in coordinates scaled by 1/s a coefficient c becomes c·s^power, all O(1).
constexpr int kPower[kMaxCoefficients] = {2, 4, 1, 1, 6, 2, 4, 6, 1, 3, 1, 3};

// OpenCV's forward distortion of a normalised point, coefficients c[12] (header's formula).
template <typename T>
void distort_normalised(const T* c, const T& x, const T& y, T* xd, T* yd) {
  const T r2 = x * x + y * y;
  const T num = T(1) + ((c[4] * r2 + c[1]) * r2 + c[0]) * r2;
  const T den = T(1) + ((c[7] * r2 + c[6]) * r2 + c[5]) * r2;
  const T ratio = num / den;
  *xd = x * ratio + T(2) * c[2] * x * y + c[3] * (r2 + T(2) * x * x) + c[8] * r2 + c[9] * r2 * r2;
  *yd = y * ratio + c[2] * (r2 + T(2) * y * y) + T(2) * c[3] * x * y + c[10] * r2 + c[11] * r2 * r2;
}

// cv::undistortPoints' fixed-point iteration on a distorted normalised point (OpenCV 4
// modules/calib3d/src/undistort.dispatch.cpp, cvUndistortPointsInternal, COUNT criterion).
template <typename T>
void undistort_normalised(const T* c, const T& x0, const T& y0, int iterations, T* xu, T* yu) {
  T x = x0, y = y0;
  for (int j = 0; j < iterations; ++j) {
    const T r2 = x * x + y * y;
    const T icdist =
        (T(1) + ((c[7] * r2 + c[6]) * r2 + c[5]) * r2) / (T(1) + ((c[4] * r2 + c[1]) * r2 + c[0]) * r2);
    if (scalar_value(icdist) < 0) {  // OpenCV gives up and returns the distorted point
      x = x0;
      y = y0;
      break;
    }
    const T dx = T(2) * c[2] * x * y + c[3] * (r2 + T(2) * x * x) + c[8] * r2 + c[9] * r2 * r2;
    const T dy = c[2] * (r2 + T(2) * y * y) + T(2) * c[3] * x * y + c[10] * r2 + c[11] * r2 * r2;
    const T xn = (x0 - dx) * icdist, yn = (y0 - dy) * icdist;
    x = xn;
    y = yn;
  }
  *xu = x;
  *yu = y;
}

std::array<double, kMaxCoefficients> padded(const std::vector<double>& c) {
  std::array<double, kMaxCoefficients> a{};
  for (std::size_t i = 0; i < c.size() && i < a.size(); ++i) a[i] = c[i];
  return a;
}

/// Both directions' pixel residuals at one sample. Parameters: intr = fx, fy, cx, cy (px);
/// scaled = the 12 coefficients in coordinates scaled by 1/scale; affine = a, b of A.
struct BothDirections {
  DistortionSample s;
  double scale;
  bool equal_focal;
  int iterations;
  double project_weight;
  double undistort_weight;

  template <typename T>
  bool operator()(const T* intr, const T* scaled, const T* affine, T* r) const {
    T c[kMaxCoefficients];
    for (int i = 0; i < kMaxCoefficients; ++i) c[i] = scaled[i] / T(std::pow(scale, kPower[i]));
    const T fx = intr[0], fy = equal_focal ? intr[0] : intr[1];
    const T xa = affine[0] * T(s.normalised.x()) + affine[1] * T(s.normalised.y());
    const T ya = T(s.normalised.y());
    T xd, yd;
    distort_normalised(c, xa, ya, &xd, &yd);
    r[0] = (fx * xd + intr[2] - T(s.pixel.x())) * T(project_weight);
    r[1] = (fy * yd + intr[3] - T(s.pixel.y())) * T(project_weight);
    T xu, yu;
    undistort_normalised(c, (T(s.pixel.x()) - intr[2]) / fx, (T(s.pixel.y()) - intr[3]) / fy, iterations, &xu,
                         &yu);
    r[2] = (xu - xa) * fx * T(undistort_weight);
    r[3] = (yu - ya) * fy * T(undistort_weight);
    return true;
  }
};

struct Errors {
  double project_max = 0, project_rms = 0, undistort_max = 0, undistort_rms = 0;
  double worst() const { return std::max(project_max, undistort_max); }
};

/// The two directions' errors (px) at one sample.
std::pair<double, double> sample_errors(const DistortionSample& s, const OpenCvDistortionModel& m,
                                        const Eigen::Matrix2d& A, int iterations) {
  const Eigen::Vector2d xa = A * s.normalised;
  const Eigen::Vector2d xu = opencv_undistort_point(m, s.pixel, iterations);
  return {(opencv_distort(m, xa) - s.pixel).norm(),
          std::hypot((xu.x() - xa.x()) * m.fx, (xu.y() - xa.y()) * m.fy)};
}

Errors evaluate(const std::vector<DistortionSample>& samples, const OpenCvDistortionModel& m,
                const Eigen::Matrix2d& A, int iterations) {
  Errors e;
  double sp = 0, su = 0;
  for (const DistortionSample& s : samples) {
    const auto [ep, eu] = sample_errors(s, m, A, iterations);
    // A NaN (a model that failed) must count as the worst, not vanish in std::max.
    e.project_max = std::isfinite(ep) ? std::max(e.project_max, ep) : std::numeric_limits<double>::infinity();
    e.undistort_max =
        std::isfinite(eu) ? std::max(e.undistort_max, eu) : std::numeric_limits<double>::infinity();
    sp += ep * ep;
    su += eu * eu;
  }
  e.project_rms = std::sqrt(sp / samples.size());
  e.undistort_rms = std::sqrt(su / samples.size());
  return e;
}

/// Per-sample weights of the two directions' residuals.
struct SampleWeights {
  std::vector<double> project, undistort;
};

void solve(const std::vector<DistortionSample>& samples, const SampleWeights& w, double scale,
           const OpenCvFitOptions& o, int n_coeffs, double* intr, double* scaled, double* affine) {
  ceres::Problem problem;
  for (std::size_t i = 0; i < samples.size(); ++i)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BothDirections, 4, 4, kMaxCoefficients, 2>(new BothDirections{
            samples[i], scale, o.equal_focal, o.undistort_iterations, w.project[i], w.undistort[i]}),
        nullptr, intr, scaled, affine);
  if (o.equal_focal) problem.SetManifold(intr, new ceres::SubsetManifold(4, {1}));
  if (n_coeffs < kMaxCoefficients) {
    std::vector<int> fixed;
    for (int i = n_coeffs; i < kMaxCoefficients; ++i) fixed.push_back(i);
    problem.SetManifold(scaled, new ceres::SubsetManifold(kMaxCoefficients, fixed));
  }
  if (!o.free_affine) problem.SetParameterBlockConstant(affine);
  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::DENSE_QR;
  opt.max_num_iterations = 300;
  opt.function_tolerance = 1e-16;
  opt.gradient_tolerance = 1e-20;
  opt.parameter_tolerance = 1e-16;
  opt.num_threads = 1;  // deterministic
  opt.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(opt, &problem, &summary);
}

}  // namespace

Eigen::Vector2d opencv_distort(const OpenCvDistortionModel& m, const Eigen::Vector2d& x) {
  const auto c = padded(m.coefficients);
  double xd, yd;
  distort_normalised(c.data(), x.x(), x.y(), &xd, &yd);
  return {m.fx * xd + m.cx, m.fy * yd + m.cy};
}

Eigen::Vector2d opencv_undistort_point(const OpenCvDistortionModel& m, const Eigen::Vector2d& pixel,
                                       int iterations) {
  const auto c = padded(m.coefficients);
  double x, y;
  undistort_normalised(c.data(), (pixel.x() - m.cx) / m.fx, (pixel.y() - m.cy) / m.fy, iterations, &x, &y);
  return {x, y};
}

std::vector<DistortionSample> image_grid_samples(const Camera& cam, int nu, int nv, double offset) {
  const CameraIntrinsics& in = cam.intr;
  std::vector<DistortionSample> g;
  g.reserve(static_cast<std::size_t>(nu) * nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double fu = std::min(1.0, (i + offset) / (nu - 1)), fv = std::min(1.0, (j + offset) / (nv - 1));
      const Eigen::Vector2d uv(-0.5 + fu * in.width_px, -0.5 + fv * in.height_px);
      g.push_back({pixel_to_undistorted_sensor(in, uv) / in.f_mm, uv});
    }
  return g;
}

OpenCvFit fit_opencv_distortion(const std::vector<DistortionSample>& fit_samples,
                                const std::vector<DistortionSample>& eval_samples,
                                const OpenCvDistortionModel& initial, const OpenCvFitOptions& options) {
  double scale = 0;
  for (const DistortionSample& s : fit_samples) scale = std::max(scale, s.normalised.norm());
  if (!(scale > 0)) scale = 1;
  double intr[4] = {initial.fx, options.equal_focal ? initial.fx : initial.fy, initial.cx, initial.cy};
  double scaled[kMaxCoefficients];
  const auto c0 = padded(initial.coefficients);
  for (int i = 0; i < kMaxCoefficients; ++i) scaled[i] = c0[i] * std::pow(scale, kPower[i]);
  double affine[2] = {1, 0};

  const auto model_of = [&](const double* in, const double* sc, int n) {
    OpenCvDistortionModel m;
    m.fx = in[0];
    m.fy = options.equal_focal ? in[0] : in[1];
    m.cx = in[2];
    m.cy = in[3];
    m.coefficients.assign(n, 0.0);
    for (int i = 0; i < n; ++i) m.coefficients[i] = sc[i] / std::pow(scale, kPower[i]);
    return m;
  };
  const auto affine_of = [](const double* a) {
    Eigen::Matrix2d A;
    A << a[0], a[1], 0, 1;
    return A;
  };

  OpenCvFit best;
  Errors best_err;
  best_err.project_max = best_err.undistort_max = std::numeric_limits<double>::infinity();
  for (const int n : options.layouts) {
    // Each richer layout starts from the best so far, its extra coefficients at zero.
    double in2[4], sc2[kMaxCoefficients], af2[2];
    std::copy(intr, intr + 4, in2);
    std::copy(scaled, scaled + kMaxCoefficients, sc2);
    std::copy(affine, affine + 2, af2);
    for (int i = n; i < kMaxCoefficients; ++i) sc2[i] = 0;
    SampleWeights w{std::vector<double>(fit_samples.size(), 1.0),
                    std::vector<double>(fit_samples.size(), options.undistort_weight)};
    // Least squares, then Lawson's reweighting towards the least maximum error (each sample's
    // squared weight multiplied by its error relative to the largest), keeping the best round.
    for (int round = 0; round <= options.minimax_rounds; ++round) {
      solve(fit_samples, w, scale, options, n, in2, sc2, af2);
      const OpenCvDistortionModel m = model_of(in2, sc2, n);
      const Errors e = evaluate(eval_samples, m, affine_of(af2), options.undistort_iterations);
      if (e.worst() < best_err.worst()) {
        best_err = e;
        best.model = m;
        best.affine = affine_of(af2);
        std::copy(in2, in2 + 4, intr);
        std::copy(sc2, sc2 + kMaxCoefficients, scaled);
        std::copy(af2, af2 + 2, affine);
      }
      if (round == options.minimax_rounds) break;
      double worst = 0;
      std::vector<std::pair<double, double>> errs;
      for (const DistortionSample& s : fit_samples) {
        errs.push_back(sample_errors(s, m, affine_of(af2), options.undistort_iterations));
        worst = std::max({worst, errs.back().first, errs.back().second});
      }
      if (!(worst > 0) || !std::isfinite(worst)) break;
      for (std::size_t i = 0; i < fit_samples.size(); ++i) {
        w.project[i] *= std::sqrt(std::max(errs[i].first / worst, 1e-3));
        if (options.undistort_weight > 0) w.undistort[i] *= std::sqrt(std::max(errs[i].second / worst, 1e-3));
      }
    }
    if (best_err.worst() <= options.tolerance_px) break;
  }
  best.project_max_px = best_err.project_max;
  best.project_rms_px = best_err.project_rms;
  best.undistort_max_px = best_err.undistort_max;
  best.undistort_rms_px = best_err.undistort_rms;
  best.points = static_cast<int>(eval_samples.size());
  return best;
}

}  // namespace rangecal
