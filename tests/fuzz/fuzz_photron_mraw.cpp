// libFuzzer target: Photron .mraw frames with their header (PhotronMrawReader). Input layout: one
// byte choosing the header form ('x' → .cihx, anything else → .cih; the reader decides by
// extension), the header bytes, the separator below, then the .mraw bytes; header and frames are
// written to per-process scratch files. Only the first and the last frame are decoded, so a run
// stays fast.
#include <algorithm>
#include <string_view>

#include "fuzz_common.hpp"
#include "vision/frames/photron_mraw_reader.hpp"

namespace {
constexpr std::string_view kSeparator = "\n--rangecal-fuzz-mraw--\n";
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  const bool cihx = all[0] == 'x';
  const std::string_view rest = all.substr(1);
  const std::size_t cut = rest.find(kSeparator);
  const std::string_view header = rest.substr(0, cut);
  const std::string_view mraw =
      cut == std::string_view::npos ? std::string_view() : rest.substr(cut + kSeparator.size());
  static const rangecal::fuzz::ScratchFile header_cihx("rec.cihx"), header_cih("rec.cih"), frames("rec.mraw");
  const std::string& header_path = (cihx ? header_cihx : header_cih).write(header);
  const std::string& mraw_path = frames.write(mraw);
  rangecal::fuzz::expect_parse_or_error([&] {
    const rangecal::PhotronMrawReader reader(mraw_path, header_path);
    if (reader.frame_count() > 0) {
      reader.read_frame(0);
      reader.read_frame(reader.frame_count() - 1);
    }
    reader.read_frame(reader.frame_count());  // out of range: must be an Error
  });
  return 0;
}
