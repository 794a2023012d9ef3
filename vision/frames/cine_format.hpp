#pragma once
// Phantom .cine layout constants and the TIME64 ↔ UTC conversion shared by cine_reader and
// cine_writer. Layout as implemented (all little-endian; see docs/frames_and_detection.md):
//   CINEFILEHEADER (44 bytes) at 0: "CI", HeaderSize, Compression, Version, FirstMovieImage,
//     TotalImageCount, FirstImageNo, ImageCount, OffImageHeader, OffSetup, OffImageOffsets,
//     TriggerTime (TIME64).
//   BITMAPINFOHEADER (40 bytes) at OffImageHeader: biSize, biWidth, biHeight, biPlanes,
//     biBitCount, biCompression (0 plain, 256 packed 10-bit, 1024 packed 12-bit), biSizeImage, …
//   SETUP at OffSetup: Mark "ST" at +140, Length (uint16) at +142; fields read below.
//   Tagged information blocks from OffSetup + Length up to OffImageOffsets: {uint32 size,
//     uint16 type, uint16 reserved, payload}; type 1002 = one TIME64 per saved image, 1003 = one
//     uint32 exposure (0.32 fixed-point seconds) per saved image.
//   ImageCount int64 image offsets at OffImageOffsets; each image starts with an annotation
//     {uint32 AnnotationSize, …, uint32 ImageSize (last 4 bytes)} and its pixels follow at
//     offset + AnnotationSize.
#include <cstdint>

#include "gnss/time/utc_time.hpp"

namespace rangecal::cine {

constexpr std::uint32_t kFileHeaderSize = 44;
constexpr std::uint32_t kBitmapHeaderSize = 40;
// SETUP field offsets (bytes from OffSetup) as the Phantom SDK's packed SETUP struct lays them out.
constexpr std::uint32_t kSetupFrameRate16 = 0;        // uint16, legacy frame rate
constexpr std::uint32_t kSetupMark = 140;             // "ST"
constexpr std::uint32_t kSetupLength = 142;           // uint16, bytes in SETUP
constexpr std::uint32_t kSetupFlipV = 760;            // int32 BOOL, image stored flipped vertically
constexpr std::uint32_t kSetupFrameRate = 768;        // uint32, frames per second
constexpr std::uint32_t kSetupCfa = 808;              // uint32, colour filter array code (0 = grey)
constexpr std::uint32_t kSetupRealBpp = 896;          // uint32, significant bits of the sensor data
constexpr std::uint32_t kSetupShutterNs = 1568;       // uint32, exposure in ns
constexpr std::uint32_t kSetupMinLength = 1572;       // we need the fields above
constexpr std::uint16_t kSetupWrittenLength = 10384;  // what current Phantom software writes

constexpr std::uint16_t kTagTimeOnly = 1002;
constexpr std::uint16_t kTagExposureOnly = 1003;

constexpr std::uint32_t kBiRgb = 0;
constexpr std::uint32_t kBiPacked10 = 256;
constexpr std::uint32_t kBiPacked12 = 1024;

/// A TIME64 split into UTC and the IRIG flag. TIME64 is 32.32 fixed-point seconds since
/// 1970-01-01 UTC: low 32 bits the fraction, high 32 bits the seconds; the fraction's lowest bit
/// is not time but the IRIG-synchronised flag (Phantom SDK), so the time resolution is 2⁻³¹ s.
struct Time64 {
  UtcTime utc;
  bool irig_locked = false;
};

/// TIME64 (raw 64-bit value) → UTC ns (rounded to nearest ns) and IRIG flag.
inline Time64 time64_to_utc(std::uint64_t raw) {
  const std::uint64_t seconds = raw >> 32;
  const std::uint64_t fraction = raw & 0xFFFFFFFFull;
  const std::uint64_t frac_ns = ((fraction & ~1ull) * 1'000'000'000ull + (1ull << 31)) >> 32;
  return {UtcTime{static_cast<std::int64_t>(seconds) * kNsPerSecond + static_cast<std::int64_t>(frac_ns)},
          (fraction & 1ull) != 0};
}

/// UTC (must lie in 1970…2106) → TIME64 with the IRIG flag. The fraction is the even value
/// nearest to ns·2³²/10⁹, so time64_to_utc(utc_to_time64(t)) == t exactly (error ≤ 0.24 ns).
inline std::uint64_t utc_to_time64(UtcTime t, bool irig_locked) {
  const std::uint64_t seconds = static_cast<std::uint64_t>(t.ns / kNsPerSecond);
  const std::uint64_t ns = static_cast<std::uint64_t>(t.ns % kNsPerSecond);
  std::uint64_t half = ((ns << 31) + 500'000'000ull) / 1'000'000'000ull;  // nearest in 2⁻³¹ s units
  std::uint64_t fraction = half << 1;
  if (fraction > 0xFFFFFFFEull) fraction = 0xFFFFFFFEull;
  return (seconds << 32) | fraction | (irig_locked ? 1ull : 0ull);
}

}  // namespace rangecal::cine
