#include "vision/frames/cine_writer.hpp"

#include <algorithm>
#include <cstring>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "vision/frames/cine_format.hpp"

namespace rangecal {
namespace {

template <typename T>
void put_le(std::string& buf, std::size_t at, T v) {
  std::memcpy(&buf[at], &v, sizeof(T));  // little-endian host assumed
}

// Rejects images and times the file cannot hold; returns the stored bytes of one image.
std::size_t checked_image_bytes(const std::string& path, const std::vector<cv::Mat>& images,
                                const std::vector<UtcTime>& times, int sb) {
  if (images.size() != times.size())
    throw_input_error(
        path, 0, "times",
        "got " + std::to_string(times.size()) + " times for " + std::to_string(images.size()) + " images");
  if (images.empty()) throw_input_error(path, 0, "images", "no image to write");
  if (sb != 8 && sb != 10 && sb != 12 && sb != 16)
    throw_input_error(path, 0, "storage_bits", "must be 8, 10, 12 or 16");
  const int w = images[0].cols, h = images[0].rows;
  const int want_type = sb == 8 ? CV_8UC1 : CV_16UC1;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if ((sb == 10 && n % 4) || (sb == 12 && n % 2))
    throw_input_error(path, 0, "images", "pixel count must be a multiple of 4 (P10) or 2 (P12L)");
  for (std::size_t i = 0; i < images.size(); ++i) {
    if (images[i].cols != w || images[i].rows != h || images[i].type() != want_type)
      throw_input_error(path, 0, "images[" + std::to_string(i) + "]",
                        "size or pixel type differs from image 0 / storage");
    if (i > 0 && times[i] <= times[i - 1])
      throw_input_error(path, 0, "times[" + std::to_string(i) + "]", "not strictly increasing");
  }
  return sb == 8 ? n : sb == 16 ? 2 * n : sb == 10 ? n / 4 * 5 : n / 2 * 3;
}

// File layout: headers, tagged blocks, offset table, then {annotation, pixels} per image.
struct CineLayout {
  std::uint32_t count = 0;
  std::size_t image_bytes = 0;
  std::uint32_t off_image_header = cine::kFileHeaderSize;
  std::uint32_t off_setup = 0, off_tags = 0, time_block = 0, exp_block = 0, off_offsets = 0;
  std::uint64_t off_first_image = 0;
  std::uint32_t annotation = 8;  // {AnnotationSize, ImageSize}
  std::uint64_t per_image = 0;
};

CineLayout cine_layout(std::uint32_t count, std::size_t image_bytes) {
  CineLayout l;
  l.count = count;
  l.image_bytes = image_bytes;
  l.off_setup = l.off_image_header + cine::kBitmapHeaderSize;
  l.off_tags = l.off_setup + cine::kSetupWrittenLength;
  l.time_block = 8 + 8 * count;
  l.exp_block = 8 + 4 * count;
  l.off_offsets = l.off_tags + l.time_block + l.exp_block;
  l.off_first_image = l.off_offsets + 8ull * count;
  l.per_image = l.annotation + image_bytes;
  return l;
}

// CINEFILEHEADER, BITMAPINFOHEADER and SETUP (fields we know; the rest zero).
void put_headers(std::string& buf, const CineLayout& l, int w, int h, int sb, const CineWriteOptions& o) {
  buf[0] = 'C';
  buf[1] = 'I';
  put_le<std::uint16_t>(buf, 2, cine::kFileHeaderSize);
  put_le<std::uint16_t>(buf, 4, 0);  // Compression: grey
  put_le<std::uint16_t>(buf, 6, 1);  // Version
  put_le<std::int32_t>(buf, 8, o.first_image_no);
  put_le<std::uint32_t>(buf, 12, l.count);
  put_le<std::int32_t>(buf, 16, o.first_image_no);
  put_le<std::uint32_t>(buf, 20, l.count);
  put_le<std::uint32_t>(buf, 24, l.off_image_header);
  put_le<std::uint32_t>(buf, 28, l.off_setup);
  put_le<std::uint32_t>(buf, 32, l.off_offsets);
  put_le<std::uint64_t>(buf, 36, cine::utc_to_time64(o.trigger_time, o.irig_locked));
  const std::size_t b = l.off_image_header;
  put_le<std::uint32_t>(buf, b + 0, cine::kBitmapHeaderSize);
  put_le<std::int32_t>(buf, b + 4, w);
  put_le<std::int32_t>(buf, b + 8, h);
  put_le<std::uint16_t>(buf, b + 12, 1);
  put_le<std::uint16_t>(buf, b + 14, static_cast<std::uint16_t>(sb == 8 ? 8 : 16));
  put_le<std::uint32_t>(buf, b + 16,
                        sb == 10   ? cine::kBiPacked10
                        : sb == 12 ? cine::kBiPacked12
                                   : cine::kBiRgb);
  put_le<std::uint32_t>(buf, b + 20, static_cast<std::uint32_t>(l.image_bytes));
  const std::size_t s = l.off_setup;
  put_le<std::uint16_t>(buf, s + cine::kSetupFrameRate16,
                        static_cast<std::uint16_t>(std::min<std::uint32_t>(o.frame_rate, 65535)));
  buf[s + cine::kSetupMark] = 'S';
  buf[s + cine::kSetupMark + 1] = 'T';
  put_le<std::uint16_t>(buf, s + cine::kSetupLength, cine::kSetupWrittenLength);
  put_le<std::int32_t>(buf, s + cine::kSetupFlipV, 0);
  put_le<std::uint32_t>(buf, s + cine::kSetupFrameRate, o.frame_rate);
  put_le<std::uint32_t>(buf, s + cine::kSetupCfa, 0);
  put_le<std::uint32_t>(buf, s + cine::kSetupRealBpp,
                        static_cast<std::uint32_t>(o.real_bpp > 0 ? o.real_bpp : sb));
  put_le<std::uint32_t>(buf, s + cine::kSetupShutterNs, static_cast<std::uint32_t>(o.exposure_s * 1e9 + 0.5));
}

// Tagged blocks: TIME64 per image, exposure per image.
void put_tagged_blocks(std::string& buf, const CineLayout& l, const std::vector<UtcTime>& times,
                       const CineWriteOptions& o) {
  std::size_t t = l.off_tags;
  put_le<std::uint32_t>(buf, t, l.time_block);
  put_le<std::uint16_t>(buf, t + 4, cine::kTagTimeOnly);
  for (std::uint32_t i = 0; i < l.count; ++i)
    put_le<std::uint64_t>(buf, t + 8 + 8 * i, cine::utc_to_time64(times[i], o.irig_locked));
  t += l.time_block;
  put_le<std::uint32_t>(buf, t, l.exp_block);
  put_le<std::uint16_t>(buf, t + 4, cine::kTagExposureOnly);
  const double e = std::min(std::max(o.exposure_s, 0.0), 0.999999999);
  for (std::uint32_t i = 0; i < l.count; ++i)
    put_le<std::uint32_t>(buf, t + 8 + 4 * i, static_cast<std::uint32_t>(e * 4294967296.0));
}

// Image `i`'s pixels at dst: plain data bottom-up, packed data top-down as an MSB-first bit stream.
void put_pixels(std::uint8_t* dst, const cv::Mat& img, int sb, const std::string& path, std::uint32_t i) {
  const int w = img.cols, h = img.rows;
  if (sb == 8 || sb == 16) {
    const std::size_t row_bytes = static_cast<std::size_t>(w) * (sb / 8);
    for (int r = 0; r < h; ++r)  // plain data is stored bottom-up
      std::memcpy(dst + row_bytes * static_cast<std::size_t>(h - 1 - r), img.ptr(r), row_bytes);
    return;
  }
  const int max_value = (1 << sb) - 1;
  std::uint64_t acc = 0;
  int nbits = 0;
  std::size_t k = 0;
  for (int r = 0; r < h; ++r) {
    const auto* p = img.ptr<std::uint16_t>(r);
    for (int c = 0; c < w; ++c) {
      if (p[c] > max_value)
        throw_input_error(
            path, 0, "images[" + std::to_string(i) + "]",
            "pixel value " + std::to_string(p[c]) + " does not fit " + std::to_string(sb) + " bits");
      acc = (acc << sb) | p[c];
      nbits += sb;
      while (nbits >= 8) {
        dst[k++] = static_cast<std::uint8_t>(acc >> (nbits - 8));
        nbits -= 8;
      }
    }
  }
}

}  // namespace

void write_cine(const std::string& path, const std::vector<cv::Mat>& images,
                const std::vector<UtcTime>& times, const CineWriteOptions& o) {
  const int sb = o.storage_bits;
  const std::size_t image_bytes = checked_image_bytes(path, images, times, sb);
  const CineLayout l = cine_layout(static_cast<std::uint32_t>(images.size()), image_bytes);
  std::string buf(l.off_first_image + l.per_image * l.count, '\0');
  put_headers(buf, l, images[0].cols, images[0].rows, sb, o);
  put_tagged_blocks(buf, l, times, o);
  // Offsets and images.
  for (std::uint32_t i = 0; i < l.count; ++i) {
    const std::uint64_t off = l.off_first_image + l.per_image * i;
    put_le<std::int64_t>(buf, l.off_offsets + 8ull * i, static_cast<std::int64_t>(off));
    put_le<std::uint32_t>(buf, off, l.annotation);
    put_le<std::uint32_t>(buf, off + 4, static_cast<std::uint32_t>(image_bytes));
    put_pixels(reinterpret_cast<std::uint8_t*>(&buf[off + l.annotation]), images[i], sb, path, i);
  }
  write_file_atomic(path, buf);
}

}  // namespace rangecal
