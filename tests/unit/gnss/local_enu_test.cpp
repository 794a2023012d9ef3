// Site ENU against the GeographicLib CartConvert oracle (external/gnss/oracle) and across the
// .pos variants of the same solutions.
#include "gnss/geodesy/local_enu.hpp"

#include <gtest/gtest.h>

#include <random>

#include "config/csv_table.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

std::string pos_path(const std::string& name) {
  return test::external("gnss/pos/" + name).string();
}

// SOURCE.md §3: the oracle's origin, exactly as printed in the llh file.
const GeodeticOrigin kOrigin{53.282695790, -8.982135671, 87.4012};

std::vector<Eigen::Vector3d> enu_of(const PosFile& f, const LocalEnu& site) {
  std::vector<Eigen::Vector3d> out;
  for (const PosEpoch& e : f.epochs) out.push_back(to_site_enu(f, e, site).enu);
  return out;
}

TEST(LocalEnu, MatchesCartConvertOracleWithinATenthMm) {
  const CsvTable t = read_csv(test::external("gnss/oracle/oracle_enu_cartconvert.csv").string());
  const PosFile f = read_rtklib_pos(pos_path("rover20181009_kin_llh_gpst.pos"));
  const PosFile x = read_rtklib_pos(pos_path("rover20181009_kin_xyz_gpst.pos"));
  const LocalEnu site(kOrigin);
  ASSERT_EQ(t.records.size(), 20u);
  for (const CsvRecord& r : t.records) {
    const auto row = static_cast<std::size_t>(t.integer(r, t.column("data_row_0based")));
    const PosEpoch& e = f.epochs.at(row);
    // The oracle's lat/lon/h are copied from the file: they must be this epoch's.
    ASSERT_DOUBLE_EQ(e.position[0], t.number(r, t.column("lat_deg")));
    const Eigen::Vector3d oracle(t.number(r, t.column("e_m")), t.number(r, t.column("n_m")),
                                 t.number(r, t.column("u_m")));
    EXPECT_LT((to_site_enu(f, e, site).enu - oracle).cwiseAbs().maxCoeff(), 1e-4) << "row " << row;
    const Eigen::Vector3d cc_ecef(t.number(r, t.column("cc_ecef_x_m")), t.number(r, t.column("cc_ecef_y_m")),
                                  t.number(r, t.column("cc_ecef_z_m")));
    EXPECT_LT((geodetic_to_ecef(e.position) - cc_ecef).norm(), 2e-6);
    // The ECEF file's epoch (printed to 0.1 mm) lands on the same ENU within 0.2 mm.
    EXPECT_LT((to_site_enu(x, x.epochs.at(row), site).enu - oracle).norm(), 2e-4) << "row " << row;
  }
}

TEST(LocalEnu, LlhEcefWeekTowDmsAgreeWithinOneMm) {
  const LocalEnu site(kOrigin);
  const auto llh = enu_of(read_rtklib_pos(pos_path("rover20181009_kin_llh_gpst.pos")), site);
  for (const char* name : {"rover20181009_kin_xyz_gpst.pos", "rover20181009_kin_llh_weektow.pos",
                           "rover20181009_kin_dms_gpst.pos", "rover20181009_kin_llh_utc.pos"}) {
    const auto other = enu_of(read_rtklib_pos(pos_path(name)), site);
    ASSERT_EQ(other.size(), llh.size()) << name;
    double worst = 0;
    for (std::size_t i = 0; i < llh.size(); ++i) worst = std::max(worst, (other[i] - llh[i]).norm());
    EXPECT_LT(worst, 1e-3) << name;
  }
}

TEST(LocalEnu, EnuBaselineFileAgreesWithLlhInSiteEnu) {
  const LocalEnu site(kOrigin);
  const auto llh = enu_of(read_rtklib_pos(pos_path("rover20181009_kin_llh_gpst.pos")), site);
  const auto enu = enu_of(read_rtklib_pos(pos_path("rover20181009_kin_enu_gpst.pos")), site);
  ASSERT_EQ(enu.size(), llh.size());
  double worst = 0;
  for (std::size_t i = 0; i < llh.size(); ++i)
    worst = std::max(worst, (enu[i] - llh[i]).cwiseAbs().maxCoeff());
  // Print rounding: baseline 0.05 mm, ref pos 1e-9 deg (0.06 mm) and 0.05 mm, llh 0.06 mm per axis.
  EXPECT_LT(worst, 0.2e-3);
  std::printf("ENU-baseline vs llh: worst axis difference %.3f mm\n", worst * 1e3);
}

TEST(LocalEnu, EcefCovarianceRotatesToTheLlhFilesEnuCovariance) {
  const LocalEnu site(kOrigin);
  const PosFile l = read_rtklib_pos(pos_path("rover20181009_kin_llh_gpst.pos"));
  const PosFile x = read_rtklib_pos(pos_path("rover20181009_kin_xyz_gpst.pos"));
  double worst = 0;
  for (std::size_t i = 0; i < l.epochs.size(); ++i) {
    const EnuFix a = to_site_enu(l, l.epochs[i], site), b = to_site_enu(x, x.epochs[i], site);
    // Both files print each sd or signed-sqrt term v to 0.1 mm (|δv| ≤ 0.05 mm), so each printed
    // covariance entry is off by ≤ 2|v|·0.05 mm + (0.05 mm)²; a rotation mixes the 9 entries with
    // weights ≤ 1. Bound: the sum of both files' entry errors.
    auto bound = [](const Eigen::Matrix3d& c) {
      return (c.cwiseAbs().cwiseSqrt() * 1e-4).sum() + 9 * 2.5e-9;
    };
    const double tol = bound(l.epochs[i].covariance) + bound(x.epochs[i].covariance);
    worst = std::max(worst, (a.cov_enu - b.cov_enu).cwiseAbs().maxCoeff() / tol);
  }
  EXPECT_LT(worst, 1.0);
  std::printf("ECEF vs llh covariance: worst difference %.2f of the print-rounding bound\n", worst);
}

TEST(LocalEnu, RoundTrips) {
  const LocalEnu site(kOrigin);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-5000, 5000);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d enu(d(rng), d(rng), d(rng) / 10);
    EXPECT_LT((site.from_geodetic(site.to_geodetic(enu)) - enu).norm(), 1e-8);
    EXPECT_LT((site.from_ecef(site.to_ecef(enu)) - enu).norm(), 1e-8);
    EXPECT_LT((site.from_ecef(geodetic_to_ecef(site.to_geodetic(enu))) - enu).norm(), 1e-8);
  }
  EXPECT_LT(site.from_geodetic({kOrigin.lat_deg, kOrigin.lon_deg, kOrigin.h_m}).norm(), 1e-9);
}

}  // namespace
}  // namespace rangecal
