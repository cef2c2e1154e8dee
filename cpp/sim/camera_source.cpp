#include "vwg/sim/camera_source.hpp"

#include "vwg/error.hpp"

namespace vwg::sim {

SimulatedCamera::SimulatedCamera(std::shared_ptr<const PhysicsWorld> world, int robot, std::shared_ptr<CameraRenderer> renderer)
    : world_(std::move(world)), robot_(robot), renderer_(std::move(renderer)) {
  if (!world_ || !renderer_) throw Error("SimulatedCamera: needs a physics world and a camera renderer");
  (void)world_->robot(robot_);  // throws if there is no such robot
}

bool SimulatedCamera::grab(const FrameInfo&, cv::Mat& grey) {
  const RobotState* self = world_->find_robot(robot_);
  if (self == nullptr) {  // out of the string: no body, no picture (and none kept from before)
    grey.release();
    return false;
  }
  others_.clear();
  for (const RobotState& s : world_->robots()) {
    if (s.id != robot_) others_.push_back(RobotShape{s.pose, s.radius, s.id});
  }
  // People are seen as robots are: upright cylinders (their heading does not show).
  for (const PhysicsWorld::Person& p : world_->people()) others_.push_back(RobotShape{{p.x, p.y, 0.0}, p.radius, -p.id});
  renderer_->render(self->pose, others_, grey, PixelFormat::Grey);
  return true;
}

}  // namespace vwg::sim
