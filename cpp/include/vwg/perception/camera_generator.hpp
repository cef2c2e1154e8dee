// gCamera (paper Table II): each frame, an image from the robot's camera; for every AprilTag found,
// eCamera<marker, dist, angle> addressed to the robot — the tag id, the horizontal distance to it
// (metres) and its bearing (radians, counter-clockwise from the optical axis). Markers identify
// rooms (§III.A); ARobot marks the marker's cell in its grid (eq. 12).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "vwg/alphabet.hpp"
#include "vwg/generator.hpp"
#include "vwg/perception/apriltag.hpp"
#include "vwg/perception/image_source.hpp"

namespace vwg::perception {

struct CameraGeneratorSettings {
  int robot = 1;
  CameraIntrinsics intrinsics;     ///< in the AprilTag library's pixel convention (centres at +0.5)
  double tag_size = 0.3;           ///< edge of a tag's black square, metres
  std::map<int, double> tag_sizes; ///< per tag id, when they differ
  AprilTagSettings detector;
  int period = 1;  ///< look every `period` frames (detection costs milliseconds; real robots run it at a few Hz)
};

class CameraGenerator final : public Generator {
 public:
  CameraGenerator(std::shared_ptr<ImageSource> source, CameraGeneratorSettings settings, const Alphabet& alphabet,
                  const std::string& event = "eCamera");
  void generate(const FrameInfo& frame, EventList& out) override;
  std::string name() const override { return "gCamera(" + std::to_string(settings_.robot) + ", " + source_->name() + ")"; }
  /// Nothing of its own (the period is counted in frames); refused when its images come from a
  /// source read in order (files, a video, a link).
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override { in.end(); }

  const cv::Mat& image() const { return image_; }  ///< the last image (grey)
  const std::vector<TagDetection>& detections() const { return detections_; }
  const std::vector<TagPose>& poses() const { return poses_; }
  int robot() const { return settings_.robot; }

 private:
  std::shared_ptr<ImageSource> source_;
  CameraGeneratorSettings settings_;
  AprilTagDetector detector_;
  EventTypeId event_;
  cv::Mat image_;
  std::vector<TagDetection> detections_;
  std::vector<TagPose> poses_;
};

}  // namespace vwg::perception
