// The simulated camera as gCamera's image source: the first-person view from a robot's true pose
// in the physics world, other robots included.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vwg/perception/image_source.hpp"
#include "vwg/sim/camera.hpp"
#include "vwg/sim/physics.hpp"

namespace vwg::sim {

class SimulatedCamera final : public perception::ImageSource {
 public:
  SimulatedCamera(std::shared_ptr<const PhysicsWorld> world, int robot, std::shared_ptr<CameraRenderer> renderer);
  bool grab(const FrameInfo& frame, cv::Mat& grey) override;
  std::string name() const override { return "simulated camera"; }
  bool stateless() const override { return true; }  // renders the platform's world as it is
  const CameraRenderer& renderer() const { return *renderer_; }

 private:
  std::shared_ptr<const PhysicsWorld> world_;
  int robot_;
  std::shared_ptr<CameraRenderer> renderer_;
  std::vector<RobotShape> others_;
};

}  // namespace vwg::sim
