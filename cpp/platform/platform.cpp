#include "vwg/platform/platform.hpp"

#include <cmath>
#include <string>

#include "vwg/error.hpp"
#include "vwg/text.hpp"

namespace vwg::platform {

void check_settings(const RobotSettings& r, const std::string& owner) {
  if (r.id < 1) throw SchemaError(owner + ".id", "expected an id >= 1, got " + std::to_string(r.id));
  if (!std::isfinite(r.start.x) || !std::isfinite(r.start.y) || !std::isfinite(r.start.theta)) {
    throw SchemaError(owner + ".start", "expected finite x, y, yaw");
  }
  // Box2D holds these as float, and asserts (aborting the process) on what a float cannot hold.
  if (std::abs(r.start.x) > kMaxCoordinate || std::abs(r.start.y) > kMaxCoordinate) {
    throw SchemaError(owner + ".start", "expected x and y within ±" + format_real(kMaxCoordinate) + " m, got (" +
                                            format_real(r.start.x) + ", " + format_real(r.start.y) + ")");
  }
  if (std::abs(r.start.theta) > kMaxAngle) {
    throw SchemaError(owner + ".start", "expected a yaw within ±" + format_real(kMaxAngle) + " rad, got " +
                                            format_real(r.start.theta));
  }
  auto positive = [&](double v, const char* field, double most) {
    if (!std::isfinite(v) || v <= 0.0 || v > most) {
      throw SchemaError(owner + "." + field, "expected a finite number > 0 and <= " + format_real(most) + ", got " + format_real(v));
    }
  };
  positive(r.radius, "radius", 100.0);
  positive(r.limits.max_speed, "max_speed", 1000.0);
  positive(r.limits.max_turn_rate, "max_turn_rate", 1000.0);
  positive(r.limits.max_accel, "max_accel", 1e4);
  positive(r.limits.max_turn_accel, "max_turn_accel", 1e4);
  for (std::size_t i = 0; i < r.sensors.size(); ++i) {
    const std::string where = owner + ".sensors[" + std::to_string(i) + "]";
    if (r.sensors[i].empty()) throw SchemaError(where, "expected a sensor's name");
    for (std::size_t j = 0; j < i; ++j) {
      if (r.sensors[j] == r.sensors[i]) throw SchemaError(where, "sensor '" + r.sensors[i] + "' listed twice");
    }
  }
}

const RobotState& RobotPlatform::robot(int id) const {
  if (const RobotState* s = find_robot(id)) return *s;
  throw SchemaError("robot", "no robot " + std::to_string(id) + " on the " + name() + " platform");
}

const RobotState* RobotPlatform::find_robot(int id) const {
  for (const RobotState& s : robots()) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

void RobotPlatform::save_state(StateWriter&) const {
  throw SchemaError("platform " + name(), "cannot be saved: a run on it cannot be resumed (a real robot's state is "
                                          "the robot itself; the simulator's can be)");
}

void RobotPlatform::load_state(StateReader& in) { in.fail("the platform " + name() + " cannot load a saved state"); }

}  // namespace vwg::platform
