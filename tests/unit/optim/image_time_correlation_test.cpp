// A camera's image residuals correlated in time (optim/network/image_time_correlation.hpp), on two
// cameras watching a lamp that moves slowly: the variance inflation F of AR(1) centroid errors
// against its value written out here, the larger of 1 + 2 Σ_{k≤K} (1 − k/(K+1)) φ^k and
// (1 + φ)/(1 − φ); white errors give 1; a slow
// error of the lamp's own position (a PPK error the point absorbs) gives 1 however correlated it is;
// a gap in the track joins no pairs; too few epochs or untimed points are not measured.
#include "optim/network/image_time_correlation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "support/synthetic_camera.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {
namespace {

/// Two cameras 40 m apart looking at a lamp that drifts across the scene; at each epoch i the
/// residuals are `error(i, camera)` (px). σ 1 px each.
struct TwoCameras {
  NetworkResult result;
  std::vector<NetworkPoint> points;
  std::vector<NetworkObservation> observations;

  template <typename Error>
  TwoCameras(const std::vector<double>& t, Error error) {
    const Camera cams[2] = {test::generic_camera({-20, -50, 2}, {0, 0, 10}),
                            test::generic_camera({20, -50, 2}, {0, 0, 10})};
    result.cameras.resize(2);
    result.camera_observations.resize(2);
    for (int c = 0; c < 2; ++c) {
      result.cameras[c].calibration.camera = cams[c];
      result.cameras[c].details.pixel_sigma_px = 1;
    }
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double s = static_cast<double>(i) / static_cast<double>(t.size());
      NetworkPoint p;
      p.time_s = t[i];
      points.push_back(p);
      NetworkPointResult pr;
      pr.enu = Eigen::Vector3d(-8 + 16 * s, 4 * std::sin(6 * s), 6 + 8 * s);
      pr.used = true;
      result.points.push_back(pr);
      for (std::size_t c = 0; c < 2; ++c) {
        NetworkObservation o;
        o.camera = c, o.point = i;
        result.camera_observations[c].push_back(observations.size());
        observations.push_back(o);
        result.cameras[c].residual_px.push_back(error(i, c, cams[c], pr.enu));
        result.cameras[c].outlier.push_back(false);
      }
    }
  }

  double factor(std::size_t c) const { return image_time_correlation(result, points, observations)[c]; }
};

std::vector<double> ar1(double phi, std::size_t n, std::mt19937* rng) {
  std::normal_distribution<double> g(0, 1);
  std::vector<double> x(n);
  x[0] = g(*rng) / std::sqrt(1 - phi * phi);
  for (std::size_t i = 1; i < n; ++i) x[i] = phi * x[i - 1] + g(*rng);
  return x;
}

/// The larger of the window's and the AR(1)'s inflation (image_time_correlation.hpp) for an AR(1) of φ.
double expected_ar1_factor(double phi) {
  double f = 1;
  for (int k = 1; k <= kCorrelationLags; ++k) f += 2 * (1 - k / (kCorrelationLags + 1.0)) * std::pow(phi, k);
  return std::max(f, (1 + phi) / (1 - phi));
}

std::vector<double> times(std::size_t n, double step) {
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = 100 + step * static_cast<double>(i);
  return t;
}

TEST(ImageTimeCorrelation, Ar1CentroidErrorsGiveTheirWindowedInflation) {
  std::mt19937 rng(7);
  const std::size_t n = 4000;
  for (double phi : {0.6, 0.8, 0.9}) {
    std::vector<std::vector<double>> e;
    for (int k = 0; k < 4; ++k) e.push_back(ar1(phi, n, &rng));
    const TwoCameras cams(times(n, 0.2),
                          [&](std::size_t i, std::size_t c, const Camera&, const Eigen::Vector3d&) {
                            return Eigen::Vector2d(e[2 * c][i], e[2 * c + 1][i]);
                          });
    const double expected = expected_ar1_factor(phi);
    for (std::size_t c = 0; c < 2; ++c)
      EXPECT_NEAR(cams.factor(c), expected, 0.15 * expected) << "phi " << phi;
  }
}

TEST(ImageTimeCorrelation, WhiteCentroidErrorsAreNotInflated) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  int inflated = 0;
  for (int run = 0; run < 50; ++run) {
    const TwoCameras cams(times(kCorrelationMinResiduals * 2, 0.1),
                          [&](std::size_t, std::size_t, const Camera&, const Eigen::Vector3d&) {
                            return Eigen::Vector2d(g(rng), g(rng));
                          });
    inflated += (cams.factor(0) != 1 ? 1 : 0) + (cams.factor(1) != 1 ? 1 : 0);
  }
  EXPECT_LE(inflated, 2);  // of 100: the floor is three of the estimate's sd at this n
}

TEST(ImageTimeCorrelation, ASlowErrorOfTheLampsPositionIsNotTheImages) {
  // The adjusted point off the true one by a slow walk δX (a PPK error the point took in): every
  // camera's residual is the projection of δX — along the point's own directions — plus white noise.
  std::mt19937 rng(13);
  std::normal_distribution<double> g(0, 0.3);
  const std::size_t n = 2000;
  std::vector<std::vector<double>> walk;
  for (int a = 0; a < 3; ++a) walk.push_back(ar1(0.99, n, &rng));
  const TwoCameras cams(
      times(n, 0.2), [&](std::size_t i, std::size_t, const Camera& cam, const Eigen::Vector3d& X) {
        const Eigen::Vector3d dX = 0.05 * Eigen::Vector3d(walk[0][i], walk[1][i], walk[2][i]);
        Eigen::Vector2d at, off;
        EXPECT_TRUE(project(cam, X, &at) && project(cam, X - dX, &off));
        return Eigen::Vector2d(at - off + Eigen::Vector2d(g(rng), g(rng)));
      });
  EXPECT_EQ(cams.factor(0), 1);
  EXPECT_EQ(cams.factor(1), 1);
}

TEST(ImageTimeCorrelation, AGapJoinsNoPairs) {
  // 20 blocks of 20 epochs, each camera's v error a constant of alternating sign per block, opposite
  // in the two cameras (no move of the lamp explains it), plus white noise: inside a block every
  // lag-k pair is positively correlated, across blocks negatively. With the blocks 60 s apart no
  // pair crosses a gap; with the same residuals back to back, pairs across the sign changes do.
  std::mt19937 rng(17);
  std::normal_distribution<double> g(0, 0.5);
  std::vector<Eigen::Vector2d> e;
  for (int i = 0; i < 800; ++i) e.emplace_back(g(rng), g(rng));
  const auto error = [&](std::size_t i, std::size_t c, const Camera&, const Eigen::Vector3d&) {
    const double sign = (i / 20) % 2 ? 1.0 : -1.0;
    return Eigen::Vector2d(e[2 * i + c].x(), (c ? -sign : sign) + e[2 * i + c].y());
  };
  std::vector<double> gapped, joined;
  for (int block = 0; block < 20; ++block)
    for (int i = 0; i < 20; ++i) {
      gapped.push_back(block * 60.0 + i * 0.2);
      joined.push_back((block * 20 + i) * 0.2);
    }
  const double f_gapped = TwoCameras(gapped, error).factor(0);
  const double f_joined = TwoCameras(joined, error).factor(0);
  EXPECT_GT(f_gapped, 5);
  EXPECT_GT(f_gapped, 2 * f_joined);
}

TEST(ImageTimeCorrelation, TooFewOrUntimedEpochsAreNotMeasured) {
  std::mt19937 rng(5);
  const std::size_t few = kCorrelationMinResiduals - 1;
  std::vector<double> e = ar1(0.95, 4 * 400, &rng);
  const auto error = [&](std::size_t i, std::size_t c, const Camera&, const Eigen::Vector3d&) {
    return Eigen::Vector2d(e[4 * i + 2 * c], e[4 * i + 2 * c + 1]);
  };
  const TwoCameras short_track(times(few, 0.2), error);
  EXPECT_EQ(short_track.factor(0), 1);
  TwoCameras poles(times(400, 0.2), error);
  for (NetworkPoint& p : poles.points) p.time_s = std::nan("");
  EXPECT_EQ(poles.factor(0), 1);
}

}  // namespace
}  // namespace rangecal
