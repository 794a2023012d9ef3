#pragma once
// The known sensor geometry a calibration initialiser is given (from the mission config's
// `sensor` block): image size and pixel pitch. Pixels per docs/conventions.md (centre of the top-left pixel
// is (0, 0)), so the image centre is ((width−1)/2, (height−1)/2).
namespace rangecal {

struct SensorGeometry {
  int width_px = 0;
  int height_px = 0;
  double dx_mm = 0;  ///< horizontal pixel pitch (mm)
  double dy_mm = 0;  ///< vertical pixel pitch (mm)
  double center_u_px() const { return 0.5 * (width_px - 1); }
  double center_v_px() const { return 0.5 * (height_px - 1); }
};

}  // namespace rangecal
