#pragma once
// The header of a Photron FASTCAM recording (Photron FASTCAM Viewer, PFV): the camera information
// header saved beside the .mraw frames, in either of PFV's two forms:
//   .cihx  a short preamble (text, NUL padding and a small binary directory), then an XML document
//          <cih>…</cih> (UTF-8), then possibly a binary block; we read the document only;
//   .cih   the older text form, `Key : Value` lines up to a line `END`; `#` lines are comments.
// Fields read (cihx path | cih key), docs/frames_and_detection.md "Photron FASTCAM":
//   width, height   imageDataInfo/resolution/width, height | Image Width, Image Height
//   colour type     imageDataInfo/colorInfo/type | Color Type
//   stored bits     imageDataInfo/colorInfo/bit | Color Bit                 (8, 12 packed, 16)
//   effective bits  imageDataInfo/effectiveBit/depth, side | EffectiveBit Depth, EffectiveBit Side
//   file format     imageFileInfo/fileFormat | File Format                  (must be MRaw)
//   frames          frameInfo/totalFrame, startFrame, recordedFrame, correctTriggerFrame, skipFrame
//                   | Total Frame, Start Frame, Original Total Frame, Correct Trigger Frame, Save Step
//   rate, shutter   recordInfo/recordRate, shutterSpeed, shutterSpeedNsec, triggerTime
//                   | Record Rate(fps), Shutter Speed(s), Shutter Type2(nsec), Trigger Time
//   clock           fileInfo/date, time | Date, Time
//   device, IRIG    deviceInfo/deviceName, irig, irigPhaseLock | Camera Type, IRIG, IRIG Phase Lock
// Values are read, never guessed: the fields the pixels need are required (a missing one is an
// error naming it); the rest are optional (an empty element or value counts as absent). A number
// that is present but malformed is always an error; date and time are checked where they are used
// (photron_header_frame_times), as the pixels do not need them. Colour: `Mono`, or `Raw` from a camera whose
// model code marks it monochrome (the `-M-` of "FASTCAM Nova S16 type 1100K-M-64GB"); colour data is refused.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

enum class PhotronHeaderFormat { cihx, cih };

/// The header fields rangecal reads; photron_field_name gives each one's name in either format.
enum class PhotronField {
  width,
  height,
  color_type,
  color_bit,
  effective_depth,
  effective_side,
  file_format,
  total_frame,
  start_frame,
  recorded_frame,
  correct_trigger_frame,
  skip_frame,
  record_rate,
  shutter_speed,
  shutter_ns,
  trigger_time,
  date,
  time,
  device_name,
  irig,
  irig_phase_lock,
};

/// "imageDataInfo/resolution/width" (cihx) or "Image Width" (cih).
std::string photron_field_name(PhotronHeaderFormat format, PhotronField field);

/// Which end of a 16-bit (or packed 12-bit) container the effective bits occupy.
enum class EffectiveBitSide { lower, higher };

struct PhotronHeader {
  std::string path;  ///< the .cihx / .cih as given, for messages
  PhotronHeaderFormat format = PhotronHeaderFormat::cihx;
  // Required (the pixels need them).
  int width = 0;            ///< px, 1…kPhotronMaxDimension
  int height = 0;           ///< px, 1…kPhotronMaxDimension
  std::string color_type;   ///< "Mono" or "Raw" (monochrome model)
  int color_bit = 0;        ///< stored bits per pixel: 8, 12 (packed) or 16
  int effective_depth = 0;  ///< significant bits, 8 … color_bit
  EffectiveBitSide effective_side = EffectiveBitSide::lower;
  std::int64_t total_frame = 0;  ///< frames in the .mraw, 1…kPhotronMaxFrames
  // Optional.
  std::optional<std::int64_t> start_frame;     ///< camera frame number of the first saved frame (0 = trigger)
  std::optional<std::int64_t> recorded_frame;  ///< frames of the original recording
  std::optional<std::int64_t> correct_trigger_frame;  ///< as written
  std::optional<std::int64_t> skip_frame;  ///< save step: camera frames between saved frames, ≥ 1
  std::optional<double> record_rate_fps;   ///< > 0
  std::optional<double> shutter_s;         ///< exposure, s (from the ns field when given)
  std::string trigger_time;                ///< as written (not interpreted); "" when absent
  std::string date;                        ///< camera clock date as written, e.g. "2023/1/18"
  std::string time;                        ///< camera clock time as written, e.g. "11:56:13"
  std::string device_name;                 ///< e.g. "FASTCAM SA-Z type 2100K-M-64GB"
  std::optional<bool> irig;                ///< camera was IRIG-synchronised
  std::optional<bool> irig_phase_lock;

  /// Bytes of one frame in the .mraw: width·height·color_bit/8 (checked not to overflow when read).
  std::uint64_t frame_bytes() const;
  /// The field's name in this header's format, for messages.
  std::string field(PhotronField f) const { return photron_field_name(format, f); }
};

/// Largest width or height accepted (Photron sensors are at most a few thousand pixels wide); a
/// larger header value is refused before anything is allocated.
constexpr int kPhotronMaxDimension = 65535;
/// Largest frame count accepted (far beyond any camera memory) before the .mraw size check.
constexpr std::int64_t kPhotronMaxFrames = 1'000'000'000;

/// Reads a .cihx or .cih (by extension, case-insensitive). Throws rangecal::Error (input) naming
/// the file and the field: missing file, not a header, malformed XML/lines, a missing required
/// field, a malformed value, an unsupported bit depth, colour or file format.
PhotronHeader read_photron_header(const std::string& path);
/// As read_photron_header from the file's bytes in memory.
PhotronHeader parse_photron_header(const std::string& bytes, const std::string& path,
                                   PhotronHeaderFormat format);

/// The header beside `mraw_path`: the same folder and stem with .cihx (preferred) or .cih (also
/// upper-case extensions). Throws rangecal::Error (input) naming the .mraw when neither exists.
std::string find_photron_header(const std::string& mraw_path);

/// The header clock as a frame-time model, for recordings without a timestamps CSV
/// (docs/frames_and_detection.md "Photron FASTCAM"): the header's date and time are taken as the
/// camera clock at the trigger (camera frame 0), local time without a zone, to the second; saved
/// frame k is camera frame start_frame + k·skip_frame, so
///   utc_k = date·time − clock_utc_offset_h·3600 s + (start_frame + k·skip_frame) / record_rate.
struct PhotronFrameClock {
  UtcTime trigger_utc;           ///< UTC of camera frame 0
  std::int64_t start_frame = 0;  ///< camera frame number of saved frame 0
  std::int64_t skip_frame = 1;   ///< camera frames per saved frame, ≥ 1
  double record_rate_fps = 0;    ///< > 0

  /// UTC of saved frame k (0 ≤ k < total_frame of the header the clock was made from), rounded to
  /// the nearest ns.
  UtcTime frame_time(std::int64_t k) const;
};

/// The frame clock of `header`. `clock_utc_offset_h`: camera clock − UTC in hours (e.g. +2 for a
/// clock on CEST), |h| ≤ 14. Requires date (Y/M/D), time with seconds (h:m:s[.f]), record rate,
/// start frame and save step; otherwise throws rangecal::Error (input) naming the header file and
/// field and telling the user to give a timestamps CSV instead. Frame times are only as good as
/// the camera clock and its whole second.
PhotronFrameClock photron_frame_clock(const PhotronHeader& header, double clock_utc_offset_h);

}  // namespace rangecal
