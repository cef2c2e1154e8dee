// Defaults once: each default lives in one C++ struct or constant; the structs that describe the
// same thing start from it. Expected values are the documented ones (README, world-file docs).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "vwg/alphabet.hpp"
#include "vwg/engine.hpp"
#include "vwg/error.hpp"
#include "vwg/platform/platform.hpp"
#include "vwg/robot/arobot.hpp"
#include "vwg/robot/decider.hpp"
#include "vwg/sim/camera.hpp"
#include "vwg/sim/depth_camera.hpp"
#include "vwg/sim/physics.hpp"

using namespace vwg;

namespace {

std::string message_of(double dt) {
  try {
    check_dt(dt);
  } catch (const SchemaError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Defaults, OneRobotRadiusForEveryStructThatDescribesARobot) {
  EXPECT_EQ(platform::RobotSettings{}.radius, 0.18);  // the world files' documented default
  EXPECT_EQ(robot::ARobotConfig{}.radius, 0.18);
  EXPECT_EQ(robot::DecisionInput{}.radius, 0.18);
  EXPECT_EQ(sim::RobotShape{}.radius, 0.18);
}

TEST(Defaults, CameraPeriodIsACameraSetting) {
  EXPECT_EQ(sim::CameraSpec{}.period, 3);  // AprilTag detection every third frame
  sim::CameraSpec s;
  s.period = 0;
  try {
    sim::check_settings(s, "camera");
    ADD_FAILURE() << "a period of 0 frames was taken";
  } catch (const SchemaError& e) {
    EXPECT_EQ(e.field(), "camera.period");
  }
}

TEST(Defaults, WallHeightAndObstacleThreshold) {
  EXPECT_EQ(sim::CameraSpec{}.wall_height, 2.5);
  EXPECT_EQ(sim::DepthCameraSpec{}.wall_height, 2.5);
  EXPECT_EQ(sim::PhysicsSettings{}.obstacle_threshold, 50);
  EXPECT_EQ(geometry::kObstacleThreshold, 50);
}

TEST(Defaults, OneRangeOfSecondsPerFrame) {
  EXPECT_EQ(message_of(1e-6), "");
  EXPECT_EQ(message_of(3600.0), "");
  EXPECT_EQ(message_of(0.1), "");
  EXPECT_EQ(message_of(3600.5), "dt: expected a number of seconds from 1e-06 to 3600, got 3600.5");
  EXPECT_EQ(message_of(9e-7), "dt: expected a number of seconds from 1e-06 to 3600, got 9e-07");
  EXPECT_NE(message_of(std::nan("")), "");
  EXPECT_NE(message_of(0.0), "");
  // The engine takes the same range: it used to run a frame of 10,000 s (any dt > 0).
  auto a = std::make_shared<Alphabet>();
  EngineOptions o;
  o.dt = 10000.0;
  EXPECT_THROW(Engine(WorldString(a), {}, nullptr, o), SchemaError);
  o.dt = 3600.0;
  EXPECT_NO_THROW(Engine(WorldString(a), {}, nullptr, o));
}
