#include "support/pole_field.hpp"

#include <gtest/gtest.h>

#include "support/synthetic_camera.hpp"

namespace rangecal::test {

std::vector<Camera> pole_field_cameras() {
  return {range_camera_at("cam1", {-45, -45, 1.5}, kPoleFieldAim),
          range_camera_at("cam2", {45, -45, 1.8}, kPoleFieldAim),
          range_camera_at("cam3", {0, 64, 2.0}, kPoleFieldAim)};
}

std::vector<SurveyedPole> pole_field_truth() {
  const struct {
    const char* id;
    PoleRole role;
    double e, n, u;
  } t[] = {{"A1", PoleRole::check, -3.0, -2.0, 3.5},  {"A2", PoleRole::check, 2.5, -1.0, 4.2},
           {"A3", PoleRole::check, 0.0, 2.0, 4.8},    {"A4", PoleRole::check, -1.5, 3.0, 3.9},
           {"A5", PoleRole::check, 3.0, 2.5, 4.4},    {"A6", PoleRole::check, 1.0, -3.0, 3.6},
           {"C1", PoleRole::control, -2.0, 0.0, 4.1}, {"C2", PoleRole::control, 2.0, 1.0, 3.8}};
  std::vector<SurveyedPole> v;
  for (const auto& p : t) v.push_back({p.id, p.role, {p.e, p.n, p.u}, 0});
  return v;
}

std::vector<IntersectCamera> pole_field_views(const std::vector<SurveyedPole>& poles) {
  std::vector<IntersectCamera> out;
  for (const Camera& c : pole_field_cameras()) {
    IntersectCamera ic;
    ic.id = c.id;
    ic.camera = c;
    EXPECT_NEAR((c.pose.center() - kPoleFieldAim).norm(), 64, 1.5);
    for (const SurveyedPole& p : poles) {
      PolePick pick;
      pick.id = p.id;
      EXPECT_TRUE(project(c, p.enu, &pick.uv));
      EXPECT_TRUE(pick.uv.x() > 20 && pick.uv.x() < 1260 && pick.uv.y() > 20 && pick.uv.y() < 780)
          << c.id << " " << p.id << " " << pick.uv.transpose();
      ic.picks.push_back(pick);
    }
    out.push_back(ic);
  }
  return out;
}

}  // namespace rangecal::test
