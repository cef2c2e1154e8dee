// The settings structs in Python (settings.hpp derives each class from the struct's fields).
#include "settings.hpp"
#include "vwg/engine.hpp"
#include "vwg/robot/arobot.hpp"
#include "vwg/robot/avoidance.hpp"
#include "vwg/robot/localization.hpp"
#include "vwg/sim/registries.hpp"
#include "vwg/sim/overview3d.hpp"
#include "vwg/sim/render2d.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/sim/camera.hpp"
#include "vwg/sim/depth_camera.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/people.hpp"
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
  settings::bind<EngineOptions>(m, "EngineOptions", "A run of the engine: seconds per frame, seed, limits, threads.");
  settings::bind<robot::ARobotConfig>(m, "ARobotConfig",
                                      "The case study's robot actor ARobot: size, clearance, when it has arrived, how far it moves.");
  settings::bind<robot::LocalizationSettings>(m, "LocalizationSettings",
                                              "Monte Carlo localization: particles, the laser's likelihood field, the motion noise.");
  settings::bind<robot::AvoidanceSettings>(m, "AvoidanceSettings",
                                           "Reciprocal avoidance (ORCA) in the robots: horizon, margin, steering.");
  settings::bind<platform::NeighbourSettings>(m, "NeighbourSettings",
                                              "What a robot's laser sees of its neighbours: pieces of a scan, tracked.");
  settings::bind<sim::SocialForceSettings>(m, "SocialForceSettings",
                                           "People who walk: the social force model's strengths, ranges and speeds.");
  settings::bind<sim::OverviewView>(m, "OverviewView", "How the 3D overview is seen: image size, angles, robots, labels.");

  // The one range of seconds per frame, and its check: world files, the command line, records and the
  // engine all take it from here.
  m.attr("MIN_DT") = kMinDt;
  m.attr("MAX_DT") = kMaxDt;
  m.def("check_dt", [](double dt, const std::string& field) { check_dt(dt, field); }, py::arg("dt"),
        py::arg("field") = "dt",
        "Raise vwg.SchemaError naming `field` unless dt is a number of seconds from MIN_DT to MAX_DT (1e-06 to 3600).");

  // The defaults of C++ structs that are not settings classes (those report theirs through fields()),
  // for tests that compare them with what the Python side says. Read from default-constructed structs.
  m.def("struct_defaults", [] {
    py::dict out;
    out["DecisionInput"] = py::dict(py::arg("radius") = robot::DecisionInput{}.radius,
                                    py::arg("step_length") = robot::DecisionInput{}.step_length);
    out["RobotShape"] = py::dict(py::arg("radius") = sim::RobotShape{}.radius);
    out["SensorSetup"] = py::dict(py::arg("seed") = sim::SensorSetup{}.seed);
    out["constants"] = py::dict(py::arg("kDefaultRobotRadius") = platform::kDefaultRobotRadius,
                                py::arg("kDefaultWallHeight") = sim::kDefaultWallHeight,
                                py::arg("kObstacleThreshold") = geometry::kObstacleThreshold,
                                py::arg("kMinDt") = kMinDt, py::arg("kMaxDt") = kMaxDt);
    return out;
  }, "{struct: {field: default}} of C++ structs that are not settings classes, read from default-constructed ones.");
}

}  // namespace vwg::bindings
