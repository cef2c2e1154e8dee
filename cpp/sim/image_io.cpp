#include "vwg/sim/image_io.hpp"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vwg/error.hpp"

namespace vwg::sim {

cv::Mat read_image(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path + ": image file not found");
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw Error(path + ": cannot read the image (" + e.msg + ")");
  }
  if (image.empty()) throw Error(path + ": not an image OpenCV can read (PNG, PGM, BMP, JPEG...)");
  if (image.depth() != CV_8U && image.depth() != CV_16U) throw Error(path + ": only 8- and 16-bit images are supported");
  if (image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2RGB);
  if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2RGBA);
  return image;
}

void write_image(const std::string& path, const cv::Mat& image) {
  // A new matrix for the conversion: `out = image` would share the caller's pixels and cvtColor
  // would then reorder them in place.
  cv::Mat out;
  if (image.channels() == 3) {
    cv::cvtColor(image, out, cv::COLOR_RGB2BGR);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, out, cv::COLOR_RGBA2BGRA);
  } else {
    out = image;
  }
  bool ok = false;
  try {
    ok = cv::imwrite(path, out);
  } catch (const cv::Exception& e) {
    throw Error(path + ": cannot write the image (" + e.msg + ")");
  }
  if (!ok) throw Error(path + ": cannot write the image (unknown extension or unwritable place)");
}

}  // namespace vwg::sim
