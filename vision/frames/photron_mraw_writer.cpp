#include "vision/frames/photron_mraw_writer.hpp"

#include <cmath>
#include <filesystem>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"

namespace rangecal {
namespace {

// Text for an XML element: plain printable text (UTF-8 allowed), with the markup characters
// escaped; control bytes are refused so the header stays a text document.
std::string xml_text(const std::string& path, const char* field, const std::string& s) {
  std::string out;
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20) throw_input_error(path, 0, field, "control character in the text");
    if (ch == '&')
      out += "&amp;";
    else if (ch == '<')
      out += "&lt;";
    else if (ch == '>')
      out += "&gt;";
    else
      out.push_back(ch);
  }
  return out;
}

std::string number_text(double v) {
  return fmt::format("{:.17g}", v);
}

}  // namespace

std::string write_photron_mraw(const std::string& mraw_path, const std::vector<cv::Mat>& images,
                               const PhotronWriteOptions& o) {
  const int sb = o.storage_bits;
  if (sb != 8 && sb != 12 && sb != 16) throw_input_error(mraw_path, 0, "storage_bits", "must be 8, 12 or 16");
  const int depth = o.effective_depth > 0 ? o.effective_depth : sb;
  if (depth < 8 || depth > sb)
    throw_input_error(mraw_path, 0, "effective_depth", "must be 8…" + std::to_string(sb) + " bits");
  if (images.empty()) throw_input_error(mraw_path, 0, "images", "no image to write");
  const int w = images[0].cols, h = images[0].rows;
  if (w < 1 || h < 1 || w > kPhotronMaxDimension || h > kPhotronMaxDimension)
    throw_input_error(mraw_path, 0, "images", "image size out of range");
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (sb == 12 && n % 2 != 0)
    throw_input_error(mraw_path, 0, "images", "12-bit packed frames need an even pixel count");
  if (o.skip_frame < 1) throw_input_error(mraw_path, 0, "skip_frame", "must be at least 1");
  const int want_type = sb == 8 ? CV_8UC1 : CV_16UC1;
  const int shift = o.effective_side == EffectiveBitSide::higher ? sb - depth : 0;
  const unsigned max_value = (1u << depth) - 1;
  const std::size_t frame_bytes = n * static_cast<std::size_t>(sb) / 8;

  std::string data(frame_bytes * images.size(), '\0');
  for (std::size_t i = 0; i < images.size(); ++i) {
    const cv::Mat& img = images[i];
    const std::string field = "images[" + std::to_string(i) + "]";
    if (img.cols != w || img.rows != h || img.type() != want_type)
      throw_input_error(mraw_path, 0, field, "size or pixel type differs from image 0 / the storage bits");
    auto* dst = reinterpret_cast<std::uint8_t*>(&data[frame_bytes * i]);
    std::size_t k = 0;
    std::uint16_t pending = 0;  // first pixel of a 12-bit pair
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c, ++k) {
        const unsigned v = sb == 8 ? img.at<std::uint8_t>(r, c) : img.at<std::uint16_t>(r, c);
        if (v > max_value)
          throw_input_error(
              mraw_path, 0, field,
              "pixel value " + std::to_string(v) + " does not fit " + std::to_string(depth) + " bits");
        const auto s = static_cast<std::uint16_t>(v << shift);
        if (sb == 8) {
          dst[k] = static_cast<std::uint8_t>(s);
        } else if (sb == 16) {
          dst[2 * k] = static_cast<std::uint8_t>(s & 0xFF);  // little-endian
          dst[2 * k + 1] = static_cast<std::uint8_t>(s >> 8);
        } else if (k % 2 == 0) {
          pending = s;
        } else {  // two pixels in three bytes, most significant bit first
          std::uint8_t* b = dst + k / 2 * 3;
          b[0] = static_cast<std::uint8_t>(pending >> 4);
          b[1] = static_cast<std::uint8_t>(((pending & 0x0F) << 4) | (s >> 8));
          b[2] = static_cast<std::uint8_t>(s & 0xFF);
        }
      }
    }
  }

  const std::string hp = std::filesystem::path(mraw_path).replace_extension(".cihx").string();
  const std::string nl = "\r\n";  // PFV writes CRLF
  std::string x = "Photron FASTCAM camera information header (written by rangecal)" + nl;
  x += "<?xml version=\"1.0\" encoding=\"utf-8\"?>" + nl + "<cih>" + nl;
  x += "    <fileInfo>" + nl + "        <version>1.0</version>" + nl;
  if (!o.date.empty()) x += "        <date>" + xml_text(hp, "date", o.date) + "</date>" + nl;
  if (!o.time.empty()) x += "        <time>" + xml_text(hp, "time", o.time) + "</time>" + nl;
  x += "    </fileInfo>" + nl;
  const std::string res = "<resolution><width>" + std::to_string(w) + "</width><height>" + std::to_string(h) +
                          "</height></resolution>";
  x += "    <imageFileInfo>" + nl + "        <fileFormat>MRaw</fileFormat>" + nl + "        " + res + nl +
       "    </imageFileInfo>" + nl;
  x += "    <imageDataInfo>" + nl + "        " + res + nl;
  x += "        <colorInfo><type>" + xml_text(hp, "color_type", o.color_type) + "</type><bit>" +
       std::to_string(sb) + "</bit></colorInfo>" + nl;
  x += "        <effectiveBit><depth>" + std::to_string(depth) + "</depth><side>" +
       (o.effective_side == EffectiveBitSide::higher ? "Higher" : "Lower") + "</side></effectiveBit>" + nl;
  x += "    </imageDataInfo>" + nl;
  const std::string count = std::to_string(images.size());
  x += "    <frameInfo>" + nl + "        <recordedFrame>" + count + "</recordedFrame>" + nl +
       "        <totalFrame>" + count + "</totalFrame>" + nl + "        <startFrame>" +
       std::to_string(o.start_frame) + "</startFrame>" + nl + "        <skipFrame>" +
       std::to_string(o.skip_frame) + "</skipFrame>" + nl + "    </frameInfo>" + nl;
  x += "    <recordInfo>" + nl;
  if (o.record_rate_fps > 0)
    x += "        <recordRate>" + number_text(o.record_rate_fps) + "</recordRate>" + nl;
  if (o.shutter_s > 0)
    x += "        <shutterSpeedNsec>" + std::to_string(std::llround(o.shutter_s * 1e9)) +
         "</shutterSpeedNsec>" + nl;
  x += "    </recordInfo>" + nl + "    <deviceInfo>" + nl;
  if (!o.device_name.empty())
    x += "        <deviceName>" + xml_text(hp, "device_name", o.device_name) + "</deviceName>" + nl;
  x += std::string("        <irig>") + (o.irig ? "1" : "0") + "</irig>" + nl + "    </deviceInfo>" + nl;
  x += "</cih>" + nl;

  write_file_atomic(mraw_path, data);
  write_file_atomic(hp, x);
  return hp;
}

}  // namespace rangecal
