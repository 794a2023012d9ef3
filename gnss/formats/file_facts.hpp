#pragma once
// What `rangecal inspect` shows of one input file, whatever its kind: the same fields for every
// kind so that files can be printed and compared side by side. Each format's reader layer fills
// it (gnss/formats/gnss_file_facts.hpp, vision/frames/frame_formats.hpp) from the values its
// reader reads — nothing here is guessed; a fact the format does not carry stays empty.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gnss/time/span_comparison.hpp"
#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct FileFacts {
  std::string path;              ///< as given (for a Photron pair, the .mraw)
  std::string kind;              ///< e.g. "RTKLIB .pos", "Phantom .cine"
  std::uint64_t size_bytes = 0;  ///< of the file (for a Photron pair, the .mraw; the header is a detail)
  std::optional<int> width_px, height_px;  ///< image size (px)
  std::optional<int> bits;                 ///< significant bits per pixel
  std::optional<int> stored_bits;          ///< bits per pixel as stored, when they differ from `bits`
  std::optional<double> rate_hz;           ///< nominal rate: frames, epochs or samples per second
  std::string rate_source;                 ///< where the rate comes from ("header", "median interval")
  /// The file's time system as its header states it, and how it reaches UTC ("GPST (column
  /// header); UTC = GPST − 18 s").
  std::string time_system;
  std::optional<UtcSpan> utc;  ///< first and last time stamp on UTC; none when the file has no time
  /// Counts in the file's own terms ("epochs", "epochs Q=1 (fix)", "frames", "messages ATT").
  std::vector<std::pair<std::string, std::uint64_t>> counts;
  /// Further header facts as label → value ("IRIG", "trigger time", "program").
  std::vector<std::pair<std::string, std::string>> details;
  /// Things a user should know before using the file ("1434 of 1878 epochs are float (Q=2)").
  std::vector<std::string> notes;
};

/// The nominal rate (Hz) of increasing time stamps: 1 / median interval; nullopt for fewer than 2.
std::optional<double> median_rate_hz(const std::vector<UtcTime>& stamps);

/// Size of the file at `path` in bytes; throws rangecal::Error (input) naming it when it is missing.
std::uint64_t file_size_bytes(const std::string& path);

}  // namespace rangecal
