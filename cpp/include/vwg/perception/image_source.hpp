// Where gCamera's images come from: the simulated camera, image files, a video file or a live
// camera — the same generator and the same events whichever it is (paper test 2, device
// independence, for the camera).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "vwg/generator.hpp"
#include "vwg/geometry/pose.hpp"

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
  /// Where the robot was when the image last grabbed was taken, in its frame at this frame (metres
  /// ahead and to the left, radians): a tag seen from there is placed from there. All zeros for a
  /// camera read at the frame; nullopt when that pose is not known (the image is then not searched).
  virtual std::optional<geometry::Pose2> taken_from() { return geometry::Pose2{}; }
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

/// Where a robot was at a time of its link's clock, in its frame at this frame (nullopt: not known).
using Viewpoint = std::function<std::optional<geometry::Pose2>(double stamp)>;

/// The latest compressed image (JPEG or PNG bytes) a robot's link received, decoded when a frame
/// asks for it: a frame gets an image only when a new one has come since the last. Images that do
/// not decode are counted and dropped (a link's message may be corrupt; the run goes on). An image
/// arrives after it was taken, while the robot moves on: with a `viewpoint`, its tags are placed from
/// where the robot was at the image's stamp; an image taken when the viewpoint knows no pose is
/// counted as stale and not searched.
class ReceivedImages final : public ImageSource {
 public:
  explicit ReceivedImages(Viewpoint viewpoint = {}) : viewpoint_(std::move(viewpoint)) {}
  /// From the link's thread: the newest image (taken at `stamp`, the link's clock) replaces one not yet taken.
  void push(std::vector<std::uint8_t> encoded, double stamp);
  bool grab(const FrameInfo& frame, cv::Mat& grey) override;
  std::optional<geometry::Pose2> taken_from() override;
  std::string name() const override { return "received images"; }
  std::uint64_t received() const;
  std::uint64_t dropped() const;
  std::uint64_t stale() const;

 private:
  Viewpoint viewpoint_;
  mutable std::mutex mutex_;
  std::vector<std::uint8_t> latest_;
  double latest_stamp_ = 0.0, grabbed_stamp_ = 0.0;
  bool fresh_ = false;
  std::uint64_t received_ = 0, dropped_ = 0, stale_ = 0;
};

/// An 8-bit grey or RGB image as JPEG (`quality` 0..100) or PNG bytes (`format` "jpeg" or "png").
inline constexpr int kDefaultJpegQuality = 90;
std::vector<std::uint8_t> encode_image(const cv::Mat& image, const std::string& format, int quality = kDefaultJpegQuality);

}  // namespace vwg::perception
