#include "pipeline/steps/export_check.hpp"

#include <algorithm>

#include "config/number_format.hpp"
#include "pipeline/io/output_paths.hpp"

namespace rangecal {

ExportCheck check_exports(const OpenCvCamera& opencv, const DltCamera& dlt) {
  ExportCheck c;
  c.opencv_fit_max_px = opencv.fit_max_px;
  c.opencv_undistort_max_px = opencv.undistort_max_px;
  c.dlt_only_rms_px = dlt.dlt_only_rms_px;
  c.dlt_only_max_px = dlt.dlt_only_max_px;
  c.dlt_profile_max_px = std::max(dlt.profile_max_px, dlt.undistort_max_px);
  // A NaN fit (a fit that failed) is refused as well: the comparisons are written to be false for it.
  const double opencv_max = std::max(opencv.fit_max_px, opencv.undistort_max_px);
  c.opencv_refused = !(opencv_max <= kUnusableExportPx);
  if (c.opencv_refused)
    c.refused.push_back(std::string(kCameraOpencvYml) + ": OpenCV's model reproduces the camera only to " +
                        format_number("%.3g", opencv_max) + " px");
  else if (opencv_max > kOpenCvWarnPx)
    c.warnings.push_back("OpenCV model reproduces rangecal only to " +
                         format_number("%.6f", opencv.fit_max_px) + " px (cv::projectPoints) and " +
                         format_number("%.6f", opencv.undistort_max_px) +
                         " px (cv::undistortPoints, default iterations)");
  c.dlt_refused = !(c.dlt_profile_max_px <= kUnusableExportPx);
  if (c.dlt_refused)
    c.refused.push_back(std::string(kDltCoefficientsCsv) + ", " + kArgusProfileTxt +
                        ": the DLT-11 + Argus profile reproduce the camera only to " +
                        format_number("%.3g", c.dlt_profile_max_px) + " px");
  else if (c.dlt_profile_max_px > kDltWarnPx)
    c.warnings.push_back("DLT-11 + Argus profile reproduce rangecal only to " +
                         format_number("%.6f", c.dlt_profile_max_px) + " px");
  for (const std::string& r : c.refused) c.warnings.push_back("not written: " + r);
  return c;
}

}  // namespace rangecal
