// Reading and writing image files (PNG, PGM, BMP, JPEG) through OpenCV, with errors that name the
// file. Colour images are RGB(A) here, not OpenCV's BGR(A).
#pragma once

#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

namespace vwg::sim {

/// The image as stored: 8- or 16-bit, 1, 3 (RGB) or 4 (RGBA) channels. Throws vwg::Error naming
/// the file if it is missing or not an image.
cv::Mat read_image(const std::string& path);

/// Write an 8-bit (or 16-bit PNG/PGM) image with 1, 3 (RGB) or 4 (RGBA) channels; the format
/// follows the extension. Throws vwg::Error naming the file on failure.
void write_image(const std::string& path, const cv::Mat& image);

/// Frames as numbered PNG files in a folder: frame_00001.png, frame_00002.png, ... (an ffmpeg
/// image2 pattern `frame_%05d.png` reads them back). All frames must have the size of the first.
class ImageSequence {
 public:
  /// Creates the folder if needed. Throws vwg::Error naming it when it cannot.
  static constexpr const char* kDefaultPrefix = "frame_";
  static constexpr int kDefaultFirst = 1, kDefaultDigits = 5;
  explicit ImageSequence(std::string directory, std::string prefix = kDefaultPrefix, int first = kDefaultFirst,
                         int digits = kDefaultDigits);
  /// Write the next frame (RGB, CV_8UC3; or grey / RGBA) and return the file's path.
  std::string write(const cv::Mat& rgb);
  /// The path frame number `number` has (number counts from `first`).
  std::string path_of(std::int64_t number) const;
  const std::string& directory() const { return directory_; }  ///< where the files go
  std::int64_t frames() const { return count_; }                ///< written so far

 private:
  std::string directory_, prefix_;
  int first_, digits_;
  std::int64_t count_ = 0;
  cv::Size size_;
  int type_ = -1;
};

}  // namespace vwg::sim
