#pragma once
// PNG and TIFF frame files decoded to the frame layout (image_frame.hpp), and the colour-to-grey
// rule every decoded OpenCV image follows, a video's frames included.
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace rangecal {

/// Any depth/channel layout OpenCV decodes → single-channel CV_8U or CV_16U (colour → grey at the
/// same depth); sets *bits to 8 or 16. Empty Mat for float or signed images, which are not camera
/// frames.
cv::Mat to_grey_frame(cv::Mat m, int* bits);

/// Decodes one PNG/TIFF image to CV_8UC1/CV_16UC1 (colour → grey); sets *bits. Empty Mat when it
/// cannot be decoded.
cv::Mat decode_image_file(const std::string& path, int* bits);
/// The same from the file's bytes.
cv::Mat decode_image_bytes(const std::vector<unsigned char>& bytes, int* bits);

/// Width and height (px) a PNG's IHDR or a TIFF's first IFD declares, read without decoding;
/// nullopt for other files or a header too short to say. Values beyond INT32_MAX are clamped.
std::optional<cv::Size> image_header_size(const std::vector<unsigned char>& bytes);

/// The whole file's bytes; empty when it cannot be read.
std::vector<unsigned char> read_file_bytes(const std::string& path);

}  // namespace rangecal
