#include "vision/frames/cine_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <opencv2/imgproc.hpp>

#include "config/error.hpp"
#include "config/physical_ranges.hpp"
#include "vision/frames/cine_format.hpp"
#include "vision/frames/positional_read.hpp"

namespace rangecal {
namespace {

template <typename T>
T get_le(const std::uint8_t* p) {
  T v{};
  std::memcpy(&v, p, sizeof(T));  // little-endian host assumed (x86-64, aarch64)
  return v;
}

[[noreturn]] void bad(const std::string& path, const std::string& field, const std::string& reason) {
  throw_input_error(path, 0, field, reason);
}

// Packed 10-bit: 4 pixels in 5 bytes, bit stream most significant bit first.
void unpack10(const std::uint8_t* src, std::uint16_t* dst, std::size_t n_pixels) {
  std::size_t i = 0;
  for (; i + 4 <= n_pixels; i += 4, src += 5) {
    dst[i] = static_cast<std::uint16_t>((src[0] << 2) | (src[1] >> 6));
    dst[i + 1] = static_cast<std::uint16_t>(((src[1] & 0x3F) << 4) | (src[2] >> 4));
    dst[i + 2] = static_cast<std::uint16_t>(((src[2] & 0x0F) << 6) | (src[3] >> 2));
    dst[i + 3] = static_cast<std::uint16_t>(((src[3] & 0x03) << 8) | src[4]);
  }
}

// Packed 12-bit: 2 pixels in 3 bytes, MSB first.
void unpack12(const std::uint8_t* src, std::uint16_t* dst, std::size_t n_pixels) {
  std::size_t i = 0;
  for (; i + 2 <= n_pixels; i += 2, src += 3) {
    dst[i] = static_cast<std::uint16_t>((src[0] << 4) | (src[1] >> 4));
    dst[i + 1] = static_cast<std::uint16_t>(((src[1] & 0x0F) << 8) | src[2]);
  }
}

// CINEFILEHEADER (44 bytes at offset 0): counts, offsets of the other headers, trigger time.
CineHeader read_file_header(int fd, const std::string& path, std::uint64_t file_size) {
  std::uint8_t h[cine::kFileHeaderSize];
  if (!pread_all(fd, h, sizeof h, 0)) bad(path, "CINEFILEHEADER", "file shorter than the 44-byte header");
  if (h[0] != 'C' || h[1] != 'I')
    bad(path, "CINEFILEHEADER.Type", "not a Phantom .cine file (no 'CI' signature)");
  CineHeader c;
  c.header_size = get_le<std::uint16_t>(h + 2);
  c.compression = get_le<std::uint16_t>(h + 4);
  c.version = get_le<std::uint16_t>(h + 6);
  c.first_movie_image = get_le<std::int32_t>(h + 8);
  c.total_image_count = get_le<std::uint32_t>(h + 12);
  c.first_image_no = get_le<std::int32_t>(h + 16);
  c.image_count = get_le<std::uint32_t>(h + 20);
  c.off_image_header = get_le<std::uint32_t>(h + 24);
  c.off_setup = get_le<std::uint32_t>(h + 28);
  c.off_image_offsets = get_le<std::uint32_t>(h + 32);
  const cine::Time64 trig = cine::time64_to_utc(get_le<std::uint64_t>(h + 36));
  c.trigger_time = trig.utc;
  c.trigger_irig_locked = trig.irig_locked;
  if (c.header_size < cine::kFileHeaderSize) bad(path, "CINEFILEHEADER.Headersize", "smaller than 44");
  if (c.version != 1) bad(path, "CINEFILEHEADER.Version", "unsupported version " + std::to_string(c.version));
  if (c.compression == 1) bad(path, "CINEFILEHEADER.Compression", "JPEG-compressed .cine is not supported");
  if (c.compression > 2)
    bad(path, "CINEFILEHEADER.Compression", "unknown value " + std::to_string(c.compression));
  if (c.off_image_header + cine::kBitmapHeaderSize > file_size)
    bad(path, "CINEFILEHEADER.OffImageHeader", "points past the end of the file");
  if (c.off_setup + cine::kSetupMinLength > file_size)
    bad(path, "CINEFILEHEADER.OffSetup", "points past the end of the file");
  if (static_cast<std::uint64_t>(c.off_image_offsets) + 8ull * c.image_count > file_size)
    bad(path, "CINEFILEHEADER.OffImageOffsets", "image offset table runs past the end of the file");
  return c;
}

// BITMAPINFOHEADER at OffImageHeader: image size and pixel format.
void read_bitmap_header(int fd, const std::string& path, CineHeader& c) {
  std::uint8_t b[cine::kBitmapHeaderSize];
  if (!pread_all(fd, b, sizeof b, c.off_image_header)) bad(path, "BITMAPINFOHEADER", "truncated");
  c.bi_width = get_le<std::int32_t>(b + 4);
  c.bi_height = get_le<std::int32_t>(b + 8);
  c.bi_bit_count = get_le<std::uint16_t>(b + 14);
  c.bi_compression = get_le<std::uint32_t>(b + 16);
  c.bi_size_image = get_le<std::uint32_t>(b + 20);
  // biHeight is signed (negative: rows stored top-down); compare before negating it.
  if (c.bi_width <= 0 || c.bi_width > ranges::kMaxImageSidePx)
    bad(path, "BITMAPINFOHEADER.biWidth",
        std::to_string(c.bi_width) + " is outside [1, " + std::to_string(ranges::kMaxImageSidePx) + "] px");
  if (c.bi_height == 0 || c.bi_height < -ranges::kMaxImageSidePx || c.bi_height > ranges::kMaxImageSidePx)
    bad(path, "BITMAPINFOHEADER.biHeight",
        std::to_string(c.bi_height) + " is outside ±[1, " + std::to_string(ranges::kMaxImageSidePx) + "] px");
  if (c.bi_bit_count != 8 && c.bi_bit_count != 16 && c.bi_bit_count != 24 && c.bi_bit_count != 48)
    bad(path, "BITMAPINFOHEADER.biBitCount",
        "unsupported bit count " + std::to_string(c.bi_bit_count) + " (expected 8, 16, 24 or 48)");
  // biSizeImage is the bytes of one image: fewer than the pixels need is a damaged header, whose
  // frames could only be read short (packed 10-bit: 5 bytes per 4 pixels, 12-bit: 3 per 2).
  const std::uint64_t n = static_cast<std::uint64_t>(c.width()) * static_cast<std::uint64_t>(c.height());
  const std::uint64_t need = c.bi_compression == cine::kBiPacked10   ? (n * 10 + 7) / 8
                             : c.bi_compression == cine::kBiPacked12 ? (n * 12 + 7) / 8
                                                                     : n * (c.bi_bit_count / 8);
  if (c.bi_size_image < need)
    bad(path, "BITMAPINFOHEADER.biSizeImage",
        std::to_string(c.bi_size_image) + " bytes is less than one image of " + std::to_string(c.width()) +
            " x " + std::to_string(c.height()) + " px needs (" + std::to_string(need) + " bytes at " +
            (c.bi_compression == cine::kBiPacked10   ? std::string("10 packed bits")
             : c.bi_compression == cine::kBiPacked12 ? std::string("12 packed bits")
                                                     : std::to_string(c.bi_bit_count / 8) + " byte(s)") +
            " per pixel)");
}

// SETUP at OffSetup: the fields the reader uses (row flip, rate, colour filter, bits, shutter).
void read_setup(int fd, const std::string& path, CineHeader& c) {
  std::vector<std::uint8_t> s(cine::kSetupMinLength);
  if (!pread_all(fd, s.data(), s.size(), c.off_setup)) bad(path, "SETUP", "truncated");
  if (s[cine::kSetupMark] != 'S' || s[cine::kSetupMark + 1] != 'T')
    bad(path, "SETUP.Mark", "missing 'ST' mark (file too old or damaged)");
  c.setup_length = get_le<std::uint16_t>(s.data() + cine::kSetupLength);
  if (c.setup_length < cine::kSetupMinLength)
    bad(path, "SETUP.Length", "SETUP block too short (" + std::to_string(c.setup_length) + " bytes)");
  c.flip_v = get_le<std::int32_t>(s.data() + cine::kSetupFlipV) != 0;
  c.frame_rate = get_le<std::uint32_t>(s.data() + cine::kSetupFrameRate);
  c.cfa = get_le<std::uint32_t>(s.data() + cine::kSetupCfa);
  c.real_bpp = get_le<std::uint32_t>(s.data() + cine::kSetupRealBpp);
  c.shutter_ns = get_le<std::uint32_t>(s.data() + cine::kSetupShutterNs);
}

struct PixelLayout {
  int bits = 8;
  bool stored_bottom_up = true;
};

// Pixel format → significant bits and the stored row order.
PixelLayout pixel_layout(const std::string& path, const CineHeader& c) {
  PixelLayout l;
  bool packed = false;
  if (c.bi_compression == cine::kBiRgb) {
    if (c.bi_bit_count == 8 || c.bi_bit_count == 24) {
      l.bits = 8;
    } else if (c.bi_bit_count == 16 || c.bi_bit_count == 48) {
      l.bits = (c.real_bpp >= 8 && c.real_bpp <= 16) ? static_cast<int>(c.real_bpp) : 16;
    } else {
      bad(path, "BITMAPINFOHEADER.biBitCount", "unsupported bit count " + std::to_string(c.bi_bit_count));
    }
  } else if (c.bi_compression == cine::kBiPacked10) {
    l.bits = 10;
    packed = true;
  } else if (c.bi_compression == cine::kBiPacked12) {
    l.bits = 12;
    packed = true;
  } else {
    bad(path, "BITMAPINFOHEADER.biCompression", "unsupported value " + std::to_string(c.bi_compression));
  }
  // Plain data is stored bottom-up (BMP) and packed data top-down; bFlipV and a negative
  // biHeight each invert the order (as FFmpeg's cinedec and pims treat them).
  l.stored_bottom_up = !packed;
  if (c.flip_v) l.stored_bottom_up = !l.stored_bottom_up;
  if (c.bi_height < 0) l.stored_bottom_up = !l.stored_bottom_up;
  return l;
}

struct TaggedBlocks {
  std::vector<UtcTime> times;
  std::vector<bool> irig;
  std::vector<double> exposures;
};

// Tagged information blocks between the SETUP and the offset table: TIME64 (1002) and exposure (1003).
TaggedBlocks read_tagged_blocks(int fd, const std::string& path, const CineHeader& c) {
  TaggedBlocks t;
  std::uint64_t pos = static_cast<std::uint64_t>(c.off_setup) + c.setup_length;
  while (pos + 8 <= c.off_image_offsets) {
    std::uint8_t tb[8];
    if (!pread_all(fd, tb, 8, pos)) bad(path, "tagged block", "truncated");
    const std::uint32_t size = get_le<std::uint32_t>(tb);
    const std::uint16_t type = get_le<std::uint16_t>(tb + 4);
    if (size < 8 || pos + size > c.off_image_offsets) break;  // end of the tagged area
    const std::uint32_t payload = size - 8;
    if (type == cine::kTagTimeOnly) {
      if (payload != 8ull * c.image_count)
        bad(path, "tagged block 1002 (TimeOnly)",
            "holds " + std::to_string(payload / 8) + " time stamps for " + std::to_string(c.image_count) +
                " images");
      std::vector<std::uint8_t> buf(payload);
      if (!pread_all(fd, buf.data(), payload, pos + 8)) bad(path, "tagged block 1002", "truncated");
      t.times.resize(c.image_count);
      t.irig.resize(c.image_count);
      for (std::uint32_t i = 0; i < c.image_count; ++i) {
        const cine::Time64 ti = cine::time64_to_utc(get_le<std::uint64_t>(buf.data() + 8 * i));
        t.times[i] = ti.utc;
        t.irig[i] = ti.irig_locked;
      }
    } else if (type == cine::kTagExposureOnly && payload == 4ull * c.image_count) {
      std::vector<std::uint8_t> buf(payload);
      if (!pread_all(fd, buf.data(), payload, pos + 8)) bad(path, "tagged block 1003", "truncated");
      t.exposures.resize(c.image_count);
      for (std::uint32_t i = 0; i < c.image_count; ++i)
        t.exposures[i] = get_le<std::uint32_t>(buf.data() + 4 * i) * (1.0 / 4294967296.0);
    }
    pos += size;
  }
  return t;
}

// The image offset table at OffImageOffsets: one 64-bit file offset per saved image.
std::vector<std::uint64_t> read_image_offsets(int fd, const std::string& path, const CineHeader& c,
                                              std::uint64_t file_size) {
  std::vector<std::uint64_t> offsets(c.image_count);
  if (c.image_count > 0) {
    std::vector<std::uint8_t> buf(8ull * c.image_count);
    if (!pread_all(fd, buf.data(), buf.size(), c.off_image_offsets)) bad(path, "image offsets", "truncated");
    for (std::uint32_t i = 0; i < c.image_count; ++i) {
      const std::int64_t o = get_le<std::int64_t>(buf.data() + 8 * i);
      if (o < 0 || static_cast<std::uint64_t>(o) + 8 > file_size)
        bad(path, "image offsets[" + std::to_string(i) + "]", "points past the end of the file");
      offsets[i] = static_cast<std::uint64_t>(o);
    }
  }
  return offsets;
}

}  // namespace

CineReader::CineReader(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) bad(path, "", std::string("cannot open .cine file: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    ::close(fd_);
    fd_ = -1;
    bad(path, "", "cannot stat .cine file");
  }
  file_size_ = static_cast<std::uint64_t>(st.st_size);
  try {
    header_ = read_file_header(fd_, path, file_size_);
    read_bitmap_header(fd_, path, header_);
    read_setup(fd_, path, header_);
    const PixelLayout layout = pixel_layout(path, header_);
    bits_ = layout.bits;
    stored_bottom_up_ = layout.stored_bottom_up;
    TaggedBlocks tagged = read_tagged_blocks(fd_, path, header_);
    times_ = std::move(tagged.times);
    irig_ = std::move(tagged.irig);
    exposures_ = std::move(tagged.exposures);
    offsets_ = read_image_offsets(fd_, path, header_, file_size_);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

CineReader::~CineReader() {
  if (fd_ >= 0) ::close(fd_);
}

std::optional<double> CineReader::exposure_s(std::size_t index) const {
  if (exposures_.empty()) return std::nullopt;
  return exposures_.at(index);
}

cv::Mat CineReader::read_image(std::size_t index) const {
  if (index >= offsets_.size())
    throw_input_error(path_, 0, "frame",
                      "image index " + std::to_string(index) + " out of range (file holds " +
                          std::to_string(offsets_.size()) + ")");
  const std::string field = "image " + std::to_string(index);
  const std::uint64_t off = offsets_[index];
  std::uint8_t ann[4];
  if (!pread_all(fd_, ann, 4, off)) throw_input_error(path_, 0, field, "annotation header truncated");
  const std::uint32_t ann_size = get_le<std::uint32_t>(ann);
  if (ann_size < 8 || off + ann_size > file_size_)
    throw_input_error(path_, 0, field, "bad annotation size " + std::to_string(ann_size));
  std::uint8_t isz[4];
  if (!pread_all(fd_, isz, 4, off + ann_size - 4)) throw_input_error(path_, 0, field, "truncated");
  const std::uint32_t image_size = get_le<std::uint32_t>(isz);

  const int w = header_.width(), h = header_.height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::size_t need = 0;
  const auto bc = header_.bi_bit_count;
  if (header_.bi_compression == cine::kBiPacked10) {
    if (n % 4 != 0) throw_input_error(path_, 0, field, "packed 10-bit image size not a multiple of 4 pixels");
    need = n / 4 * 5;
  } else if (header_.bi_compression == cine::kBiPacked12) {
    if (n % 2 != 0) throw_input_error(path_, 0, field, "packed 12-bit image size not a multiple of 2 pixels");
    need = n / 2 * 3;
  } else {
    need = n * (bc / 8);
  }
  if (image_size < need)
    throw_input_error(
        path_, 0, field,
        "ImageSize " + std::to_string(image_size) + " < " + std::to_string(need) + " bytes needed");
  if (off + ann_size + need > file_size_)
    throw_input_error(path_, 0, field, "pixel data runs past the end of the file");

  std::vector<std::uint8_t> raw(need);
  if (!pread_all(fd_, raw.data(), need, off + ann_size)) throw_input_error(path_, 0, field, "read error");

  cv::Mat img;
  if (header_.bi_compression == cine::kBiPacked10) {
    img.create(h, w, CV_16UC1);
    unpack10(raw.data(), img.ptr<std::uint16_t>(), n);
  } else if (header_.bi_compression == cine::kBiPacked12) {
    img.create(h, w, CV_16UC1);
    unpack12(raw.data(), img.ptr<std::uint16_t>(), n);
  } else if (bc == 8) {
    img = cv::Mat(h, w, CV_8UC1, raw.data()).clone();
  } else if (bc == 16) {
    img = cv::Mat(h, w, CV_16UC1, raw.data()).clone();
  } else if (bc == 24) {
    cv::cvtColor(cv::Mat(h, w, CV_8UC3, raw.data()), img, cv::COLOR_BGR2GRAY);
  } else {  // 48
    cv::cvtColor(cv::Mat(h, w, CV_16UC3, raw.data()), img, cv::COLOR_BGR2GRAY);
  }
  if (stored_bottom_up_) cv::flip(img, img, 0);
  return img;
}

}  // namespace rangecal
