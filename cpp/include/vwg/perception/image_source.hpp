// Where gCamera's images come from: the simulated camera, image files, a video file or a live
// camera — the same generator and the same events whichever it is (paper test 2, device
// independence, for the camera).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "vwg/generator.hpp"

namespace vwg::perception {

class ImageSource {
 public:
  virtual ~ImageSource() = default;
  /// The 8-bit grey image for this frame into `grey`; false when the source has no more (the end
  /// of a list or a video). Throws vwg::Error naming the file or device when it cannot be read.
  virtual bool grab(const FrameInfo& frame, cv::Mat& grey) = 0;
  virtual std::string name() const = 0;
  /// Whether its images depend on nothing but the frame and the world (a simulated camera): then a
  /// run that reads it can be saved and resumed. Files, videos and links are read once, in order.
  virtual bool stateless() const { return false; }
};

/// One image file per frame, in order; none after the last.
class ImageFiles final : public ImageSource {
 public:
  explicit ImageFiles(std::vector<std::string> paths);
  bool grab(const FrameInfo& frame, cv::Mat& grey) override;
  std::string name() const override { return "image files"; }

 private:
  std::vector<std::string> paths_;
  std::size_t next_ = 0;
};

/// A video file (or a camera device when `device` >= 0) through OpenCV's VideoCapture: one image
/// per frame.
class VideoSource final : public ImageSource {
 public:
  explicit VideoSource(const std::string& path);
  explicit VideoSource(int device);
  ~VideoSource() override;
  bool grab(const FrameInfo& frame, cv::Mat& grey) override;
  std::string name() const override { return name_; }

 private:
  struct Capture;
  std::unique_ptr<Capture> capture_;
  std::string name_;
};

/// The latest compressed image (JPEG or PNG bytes) a robot's link received, decoded when a frame
/// asks for it: a frame gets an image only when a new one has come since the last. Images that do
/// not decode are counted and dropped (a link's message may be corrupt; the run goes on).
class ReceivedImages final : public ImageSource {
 public:
  /// From the link's thread: the newest image replaces one not yet taken.
  void push(std::vector<std::uint8_t> encoded);
  bool grab(const FrameInfo& frame, cv::Mat& grey) override;
  std::string name() const override { return "received images"; }
  std::uint64_t received() const;
  std::uint64_t dropped() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::uint8_t> latest_;
  bool fresh_ = false;
  std::uint64_t received_ = 0, dropped_ = 0;
};

/// An 8-bit grey or RGB image as JPEG (`quality` 0..100) or PNG bytes (`format` "jpeg" or "png").
inline constexpr int kDefaultJpegQuality = 90;
std::vector<std::uint8_t> encode_image(const cv::Mat& image, const std::string& format, int quality = kDefaultJpegQuality);

}  // namespace vwg::perception
