#include "vwg/perception/camera_generator.hpp"

#include <cmath>

#include "vwg/error.hpp"

namespace vwg::perception {

CameraGenerator::CameraGenerator(std::shared_ptr<ImageSource> source, CameraGeneratorSettings settings,
                                 const Alphabet& alphabet, const std::string& event)
    : source_(std::move(source)), settings_(std::move(settings)), detector_(settings_.detector),
      event_(alphabet.event_type_id(event)) {
  if (!source_) throw SchemaError("camera.source", "no image source");
  const auto& in = settings_.intrinsics;
  for (double v : {in.fx, in.fy}) {
    if (!std::isfinite(v) || v <= 0) throw SchemaError("camera.intrinsics", "expected focal lengths > 0");
  }
  if (!std::isfinite(in.cx) || !std::isfinite(in.cy)) throw SchemaError("camera.intrinsics", "expected a finite centre");
  if (!std::isfinite(settings_.tag_size) || settings_.tag_size <= 0) throw SchemaError("camera.tag_size", "expected metres > 0");
  if (settings_.period < 1) throw SchemaError("camera.period", "expected a number of frames >= 1");
  const auto& fields = alphabet.event_type(event_).fields.params;
  if (fields.size() != 3 || fields[0].kind != ValueKind::Int || fields[1].kind != ValueKind::Real ||
      fields[2].kind != ValueKind::Real) {
    throw SchemaError(event, "gCamera needs the fields (marker: int, dist: real, angle: real)");
  }
}

void CameraGenerator::generate(const FrameInfo& frame, EventList& out) {
  if (frame.frame % static_cast<std::uint64_t>(settings_.period) != 0) return;
  detections_.clear();
  poses_.clear();
  if (!source_->grab(frame, image_)) return;  // no image this frame (the end of a video)
  const std::optional<geometry::Pose2> from = source_->taken_from();
  if (!from) return;  // taken where the robot's poses do not reach: its tags cannot be placed
  if (!image_.isContinuous()) image_ = image_.clone();
  detections_ = detector_.detect(image_.data, image_.cols, image_.rows, static_cast<int>(image_.step));
  for (const TagDetection& d : detections_) {
    const auto it = settings_.tag_sizes.find(d.id);
    const double size = it != settings_.tag_sizes.end() ? it->second : settings_.tag_size;
    const TagPose pose = estimate_pose(d, size, settings_.intrinsics);
    poses_.push_back(pose);
    // The grid is 2D: the distance in the floor's plane (the camera frame's x-z plane).
    const geometry::Polar in_image{std::hypot(pose.translation[0], pose.translation[2]), pose.bearing};
    const geometry::Polar seen = geometry::seen_from(*from, in_image);  // the image may be older than the frame
    const Datum fields[] = {static_cast<std::int64_t>(d.id), seen.dist, seen.bearing};
    out.emit(event_, fields, settings_.robot);
  }
}

void CameraGenerator::save_state(StateWriter&) const {
  if (!source_->stateless()) {
    throw SchemaError(name(), "cannot be saved: its images come from " + source_->name() +
                                  ", read in order (a saved run needs a simulated camera)");
  }
}

}  // namespace vwg::perception
