#include "vision/frames/image_decoding.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "config/physical_ranges.hpp"

namespace rangecal {

cv::Mat to_grey_frame(cv::Mat m, int* bits) {
  if (m.empty()) return m;
  if (m.channels() == 3)
    cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
  else if (m.channels() == 4)
    cv::cvtColor(m, m, cv::COLOR_BGRA2GRAY);
  else if (m.channels() != 1)
    return cv::Mat();
  if (m.depth() == CV_8U) {
    *bits = 8;
    return m;
  }
  if (m.depth() == CV_16U) {
    *bits = 16;
    return m;
  }
  return cv::Mat();  // float/signed images are not camera frames
}

std::vector<unsigned char> read_file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return {};
  f.seekg(0, std::ios::end);
  const std::streamoff size = f.tellg();
  if (size <= 0) return {};
  f.seekg(0);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  if (!f.read(reinterpret_cast<char*>(bytes.data()), size)) return {};
  return bytes;
}

namespace {

std::uint32_t big_endian_u32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

// A PNG whose chunk chain (PNG spec §5.3: length, type, data, CRC) does not reach IEND inside the
// file, or whose IHDR declares an image beyond the size limit, is refused before libpng sees it:
// libpng would print "libpng error: …" on the console, and a forged size would allocate gigabytes.
bool png_structure_ok(const std::vector<unsigned char>& b) {
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (b.size() < 8 || !std::equal(kSignature, kSignature + 8, b.begin())) return false;
  std::size_t at = 8;
  bool first = true;
  while (at + 12 <= b.size()) {
    const std::uint32_t len = big_endian_u32(&b[at]);
    const std::string type(reinterpret_cast<const char*>(&b[at + 4]), 4);
    if (len > b.size() - at - 12) return false;
    if (first) {
      if (type != "IHDR" || len != 13) return false;
      const std::uint32_t w = big_endian_u32(&b[at + 8]), h = big_endian_u32(&b[at + 12]);
      if (w == 0 || h == 0 || w > std::uint32_t(ranges::kMaxImageSidePx) ||
          h > std::uint32_t(ranges::kMaxImageSidePx))
        return false;
      first = false;
    }
    if (type == "IEND") return true;
    at += 12 + std::size_t(len);
  }
  return false;
}

std::uint16_t tiff_u16(const unsigned char* p, bool little) {
  return little ? std::uint16_t(p[0] | (p[1] << 8)) : std::uint16_t((p[0] << 8) | p[1]);
}

std::uint32_t tiff_u32(const unsigned char* p, bool little) {
  return little
             ? (std::uint32_t(p[3]) << 24) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[1]) << 8) | p[0]
             : big_endian_u32(p);
}

// ImageWidth (256) and ImageLength (257) of a TIFF's first IFD (TIFF 6.0 §2: 8-byte header, then
// IFD entries of tag, type, count, value; SHORT values sit in the first two bytes of the field).
std::optional<cv::Size> tiff_header_size(const std::vector<unsigned char>& b) {
  if (b.size() < 8) return std::nullopt;
  const bool little = b[0] == 'I' && b[1] == 'I' && b[2] == 42 && b[3] == 0;
  const bool big = b[0] == 'M' && b[1] == 'M' && b[2] == 0 && b[3] == 42;
  if (!little && !big) return std::nullopt;
  const std::uint32_t ifd = tiff_u32(&b[4], little);
  if (ifd > b.size() || b.size() - ifd < 2) return std::nullopt;
  const std::uint16_t n = tiff_u16(&b[ifd], little);
  std::int64_t w = -1, h = -1;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t at = std::size_t(ifd) + 2 + 12 * std::size_t(i);
    if (at + 12 > b.size()) return std::nullopt;
    const std::uint16_t tag = tiff_u16(&b[at], little), type = tiff_u16(&b[at + 2], little);
    if (tag != 256 && tag != 257) continue;
    const std::int64_t v = type == 3 ? tiff_u16(&b[at + 8], little) : tiff_u32(&b[at + 8], little);
    (tag == 256 ? w : h) = v;
  }
  if (w < 0 || h < 0) return std::nullopt;
  return cv::Size(static_cast<int>(std::min<std::int64_t>(w, INT32_MAX)),
                  static_cast<int>(std::min<std::int64_t>(h, INT32_MAX)));
}

}  // namespace

std::optional<cv::Size> image_header_size(const std::vector<unsigned char>& bytes) {
  if (bytes.size() >= 24 && bytes[0] == 0x89 && bytes[1] == 'P' && bytes[12] == 'I' && bytes[13] == 'H')
    return cv::Size(static_cast<int>(std::min<std::uint32_t>(big_endian_u32(&bytes[16]), INT32_MAX)),
                    static_cast<int>(std::min<std::uint32_t>(big_endian_u32(&bytes[20]), INT32_MAX)));
  return tiff_header_size(bytes);
}

cv::Mat decode_image_bytes(const std::vector<unsigned char>& bytes, int* bits) {
  if (bytes.empty()) return cv::Mat();
  if (bytes.size() >= 8 && bytes[0] == 0x89 && !png_structure_ok(bytes)) return cv::Mat();
  return to_grey_frame(cv::imdecode(bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR), bits);
}

cv::Mat decode_image_file(const std::string& path, int* bits) {
  return decode_image_bytes(read_file_bytes(path), bits);
}

}  // namespace rangecal
