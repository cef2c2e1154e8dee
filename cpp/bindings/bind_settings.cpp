// The settings structs in Python (settings.hpp derives each class from the struct's fields).
#include "settings.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/sim/camera.hpp"
#include "vwg/sim/depth_camera.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/physics.hpp"

namespace vwg::bindings {

void init_settings(py::module_& m) {
  settings::bind<sim::LaserSpec>(m, "LaserSpec", "A planar laser range finder (gLaser).");
  settings::bind<sim::DepthCameraSpec>(m, "DepthCameraSpec",
                                       "A depth camera such as the Kinect (gKinect): its image, optics and noise.");
  settings::bind<sim::CameraSpec>(m, "CameraSpec", "The colour camera that sees the AprilTag markers (gCamera).")
      .def("apriltag_intrinsics", [](const sim::CameraSpec& s) {
        const perception::CameraIntrinsics i = sim::apriltag_intrinsics(s);
        return std::make_tuple(i.fx, i.fy, i.cx, i.cy);
      }, "(fx, fy, cx, cy) of this camera in the AprilTag library's pixel convention, for CameraGenerator.");
  settings::bind<platform::RobotSettings>(m, "RobotSettings",
                                          "A robot as the world file describes it: id, start, size, limits, sensors.");
  settings::bind<sim::NoiseModel>(m, "NoiseModel", "The simulator's motor and odometry noise (0 = exact).");
  settings::bind<sim::PhysicsSettings>(m, "PhysicsSettings", "The Box2D simulator's settings.");
}

}  // namespace vwg::bindings
