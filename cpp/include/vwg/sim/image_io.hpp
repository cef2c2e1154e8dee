// Reading and writing image files (PNG, PGM, BMP, JPEG) through OpenCV, with errors that name the
// file. Colour images are RGB(A) here, not OpenCV's BGR(A).
#pragma once

#include <string>

#include <opencv2/core.hpp>

namespace vwg::sim {

/// The image as stored: 8- or 16-bit, 1, 3 (RGB) or 4 (RGBA) channels. Throws vwg::Error naming
/// the file if it is missing or not an image.
cv::Mat read_image(const std::string& path);

/// Write an 8-bit (or 16-bit PNG/PGM) image with 1, 3 (RGB) or 4 (RGBA) channels; the format
/// follows the extension. Throws vwg::Error naming the file on failure.
void write_image(const std::string& path, const cv::Mat& image);

}  // namespace vwg::sim
