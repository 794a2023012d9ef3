// The intersect stage's record (run.json stages.intersect.counts, docs/outputs.md): written and
// read back field for field, the headline figures as check's, a skipped stage as its reason alone,
// and a malformed value named by its field.
#include "pipeline/io/intersect_record.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "config/error.hpp"

namespace rangecal {
namespace {

IntersectRecord example() {
  IntersectRecord r;
  r.joint_covariance = true;
  r.cameras_used = {"cam2", "cam1"};
  r.pick_sigma_px = 0.5;
  r.poles_picked = 17;
  r.poles_triangulated = 16;
  r.unsurveyed_poles = 1;
  r.check = {5, 0.011, 0.012, 0.021, 0.027, 0.041, 0.029, 0.019};
  r.control.n = 10;
  r.control.mean_dR_m = 0.004;  // the rest not computed: null
  r.warnings = 2;
  return r;
}

TEST(IntersectRecord, RoundTripsEveryField) {
  const IntersectRecord r = example();
  const nlohmann::json j = intersect_record_json(r);
  const IntersectRecord back =
      parse_intersect_record(nlohmann::json::parse(j.dump(2)), "run.json", "stages.intersect.counts");
  EXPECT_TRUE(back.skipped.empty());
  EXPECT_TRUE(back.joint_covariance);
  EXPECT_EQ(back.cameras_used, r.cameras_used);
  EXPECT_EQ(back.pick_sigma_px, 0.5);
  EXPECT_EQ(back.poles_picked, 17u);
  EXPECT_EQ(back.poles_triangulated, 16u);
  EXPECT_EQ(back.unsurveyed_poles, 1);
  EXPECT_EQ(back.check.n, 5);
  EXPECT_EQ(back.check.mean_abs_dU_m, 0.021);
  EXPECT_EQ(back.check.rms_dR_m, 0.029);
  EXPECT_EQ(back.control.mean_dR_m, 0.004);
  EXPECT_TRUE(std::isnan(back.control.max_dR_m));
  EXPECT_EQ(back.warnings, 2u);
  EXPECT_EQ(intersect_record_json(back).dump(2), j.dump(2));
  // The headline figures and pole counts are check's and control's.
  EXPECT_EQ(j.at("mean_dR_m"), 0.027);
  EXPECT_EQ(j.at("max_dR_m"), 0.041);
  EXPECT_EQ(j.at("mean_sigma_m"), 0.019);
  EXPECT_EQ(j.at("check_poles"), 5);
  EXPECT_EQ(j.at("control_poles"), 10);
  EXPECT_TRUE(nlohmann::json::parse(j.dump()).at("control").at("max_dR_m").is_null());  // NaN as null
}

TEST(IntersectRecord, ASkippedStageIsItsReasonAlone) {
  IntersectRecord r = example();
  r.skipped = "no \"poles\" in the config";
  const nlohmann::json j = intersect_record_json(r);
  EXPECT_EQ(j, (nlohmann::json{{"skipped", "no \"poles\" in the config"}}));
  const IntersectRecord back = parse_intersect_record(j, "run.json", "stages.intersect.counts");
  EXPECT_EQ(back.skipped, r.skipped);
  EXPECT_EQ(back.poles_picked, 0u);
}

TEST(IntersectRecord, AWrongTypeNamesItsField) {
  nlohmann::json j = intersect_record_json(example());
  j["cameras_used"][1] = 7;
  try {
    parse_intersect_record(j, "/out/run.json", "stages.intersect.counts");
    FAIL() << "a number as a camera id was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "/out/run.json");
    EXPECT_EQ(e.field(), "stages.intersect.counts.cameras_used[1]");
  }
}

}  // namespace
}  // namespace rangecal
