#include "vision/calibration/linear_distortion.hpp"

#include <Eigen/SVD>
#include <cmath>

#include "config/error.hpp"

namespace rangecal {

LinearDistortionFit fit_linear_distortion(
    const CameraIntrinsics& intr,
    const std::vector<std::pair<CameraPose, std::vector<PointCorrespondence>>>& views,
    const DistortionTerms& terms) {
  std::vector<int> cols;
  for (int k = 0; k < 7; ++k)
    if (terms[k]) cols.push_back(k);
  std::size_t n = 0;
  for (const auto& v : views) n += v.second.size();
  if (cols.empty()) throw_calibration_error("distortion", "no distortion term selected");
  if (2 * n < cols.size())
    throw_calibration_error("distortion", "too few points: " + std::to_string(n) + " points give " +
                                              std::to_string(2 * n) + " equations for " +
                                              std::to_string(cols.size()) + " distortion terms");
  Eigen::MatrixXd D(2 * n, cols.size());
  Eigen::VectorXd d(2 * n);
  std::size_t row = 0;
  for (const auto& view : views) {
    for (const auto& pc : view.second) {
      const Eigen::Vector3d xc = world_to_camera(view.first, pc.world);
      if (!(xc.z() > 0)) throw_calibration_error("distortion", "a point lies behind the camera");
      const double xu = intr.f_mm * xc.x() / xc.z(), yu = intr.f_mm * xc.y() / xc.z();
      double xd, yd;
      pixel_to_sensor(intr.sx, intr.u0_px, intr.v0_px, intr.dx_mm, intr.dy_mm, pc.pixel.x(), pc.pixel.y(),
                      &xd, &yd);
      const double r2 = xd * xd + yd * yd;
      // ∂Δ/∂(k1 k2 k3 p1 p2 a1 a2) of seed 000 eq. 7 (Δ is linear in the terms): eq. 8's D.
      const double gx[7] = {xd * r2, xd * r2 * r2, xd * r2 * r2 * r2, r2 + 2 * xd * xd, 2 * xd * yd, 0, 0};
      const double gy[7] = {yd * r2, yd * r2 * r2, yd * r2 * r2 * r2, 2 * xd * yd, r2 + 2 * yd * yd, xd, yd};
      for (std::size_t c = 0; c < cols.size(); ++c) D(row, c) = gx[cols[c]], D(row + 1, c) = gy[cols[c]];
      d(row) = xu - xd;
      d(row + 1) = yu - yd;
      row += 2;
    }
  }
  Eigen::VectorXd scale(cols.size());
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const double nn = D.col(c).norm();
    scale(c) = nn > 0 ? 1.0 / nn : 1.0;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(D * scale.asDiagonal(), Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& s = svd.singularValues();
  if (!s.allFinite() || !(s(0) > 0) || s(s.size() - 1) < 1e-10 * s(0))
    throw_calibration_error("distortion",
                            "singular system in the linear distortion fit (seed 000 eq. 8): the "
                            "points do not separate the selected terms");
  const Eigen::VectorXd k = scale.asDiagonal() * svd.solve(d);
  LinearDistortionFit out;
  std::array<double, 7> all{};
  for (std::size_t c = 0; c < cols.size(); ++c) all[cols[c]] = k(c);
  out.dist = Distortion::from_array(all.data());
  out.rms_before_mm = std::sqrt(d.squaredNorm() / d.size());
  out.rms_after_mm = std::sqrt((D * k - d).squaredNorm() / d.size());
  return out;
}

LinearDistortionFit fit_linear_distortion(const Camera& cam, const std::vector<PointCorrespondence>& pts,
                                          const DistortionTerms& terms) {
  return fit_linear_distortion(cam.intr, {{cam.pose, pts}}, terms);
}

}  // namespace rangecal
