#include "vision/frames/photron_mraw_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "config/error.hpp"
#include "vision/frames/positional_read.hpp"

namespace rangecal {
namespace {

// Packed 12-bit (Photron MRaw 12 bit): two pixels in three bytes, most significant bit first.
void mraw_unpack12(const std::uint8_t* src, std::uint16_t* dst, std::size_t n_pixels) {
  for (std::size_t i = 0; i + 2 <= n_pixels; i += 2, src += 3) {
    dst[i] = static_cast<std::uint16_t>((src[0] << 4) | (src[1] >> 4));
    dst[i + 1] = static_cast<std::uint16_t>(((src[1] & 0x0F) << 8) | src[2]);
  }
}

std::string frames_text(std::int64_t n) {
  return std::to_string(n) + (n == 1 ? " frame" : " frames");
}

}  // namespace

PhotronMrawReader::PhotronMrawReader(const std::string& mraw_path) : path_(mraw_path) {
  open(find_photron_header(mraw_path));
}

PhotronMrawReader::PhotronMrawReader(const std::string& mraw_path, const std::string& header_path)
    : path_(mraw_path) {
  open(header_path);
}

void PhotronMrawReader::open(const std::string& header_path) {
  header_ = read_photron_header(header_path);
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0)
    throw_input_error(path_, 0, "", std::string("cannot open the .mraw file: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd_);
    fd_ = -1;
    throw_input_error(path_, 0, "", "not a regular file");
  }
  // The header describes the file's size exactly: frames × width × height × bits / 8, computed in
  // 64 bits with an overflow check (width, height and frames are bounded by the header reader).
  const std::uint64_t actual = static_cast<std::uint64_t>(st.st_size);
  std::uint64_t expected = 0;
  const bool overflow = __builtin_mul_overflow(header_.frame_bytes(),
                                               static_cast<std::uint64_t>(header_.total_frame), &expected);
  if (overflow || actual != expected) {
    ::close(fd_);
    fd_ = -1;
    throw_input_error(path_, 0, "size",
                      "the .mraw holds " + std::to_string(actual) + " bytes; its header " + header_.path +
                          " describes " + std::to_string(header_.width) + "x" +
                          std::to_string(header_.height) + " px x " + std::to_string(header_.color_bit) +
                          " bit x " + frames_text(header_.total_frame) + " = " +
                          (overflow ? std::string("more than 2^64") : std::to_string(expected)) + " bytes");
  }
}

PhotronMrawReader::~PhotronMrawReader() {
  if (fd_ >= 0) ::close(fd_);
}

ImageFrame PhotronMrawReader::read_frame(std::int64_t index) const {
  const PhotronHeader& h = header_;
  if (index < 0 || index >= h.total_frame)
    throw_input_error(path_, 0, "frame",
                      "frame index " + std::to_string(index) + " is out of range (the file holds " +
                          frames_text(h.total_frame) + ", 0…" + std::to_string(h.total_frame - 1) + ")");
  const std::uint64_t bytes = h.frame_bytes();
  const std::uint64_t offset = bytes * static_cast<std::uint64_t>(index);  // < file size: checked at open
  const std::size_t n = static_cast<std::size_t>(h.width) * static_cast<std::size_t>(h.height);
  ImageFrame f;
  f.frame = index;
  f.bits = h.effective_depth;
  bool ok = false;
  if (h.color_bit == 8) {
    f.image.create(h.height, h.width, CV_8UC1);
    ok = pread_all(fd_, f.image.data, bytes, offset);
  } else if (h.color_bit == 16) {
    f.image.create(h.height, h.width, CV_16UC1);
    ok = pread_all(fd_, f.image.data, bytes, offset);  // little-endian uint16, as the host (x86-64, aarch64)
  } else {
    std::vector<std::uint8_t> raw(bytes);
    ok = pread_all(fd_, raw.data(), bytes, offset);
    if (ok) {
      f.image.create(h.height, h.width, CV_16UC1);
      mraw_unpack12(raw.data(), f.image.ptr<std::uint16_t>(), n);
    }
  }
  if (!ok)
    throw_input_error(path_, 0, "frame " + std::to_string(index),
                      "read error (the file changed or shrank after it was opened)");
  // Effective bits on the higher side of the container: shift down so values are in
  // [0, 2^effective − 1] (PFV's EffectiveBit Side = Higher). 8-bit data has 8 effective bits (the
  // header reader refuses fewer), so only the 12- and 16-bit containers can need it.
  const int shift = h.effective_side == EffectiveBitSide::higher ? h.color_bit - h.effective_depth : 0;
  if (shift > 0) {
    auto* p = f.image.ptr<std::uint16_t>();
    for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::uint16_t>(p[i] >> shift);
  }
  return f;
}

}  // namespace rangecal
