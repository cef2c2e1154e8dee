#include "vwg/platform/platform.hpp"

#include "vwg/error.hpp"

namespace vwg::platform {

const RobotState& RobotPlatform::robot(int id) const {
  for (const RobotState& s : robots()) {
    if (s.id == id) return s;
  }
  throw SchemaError("robot", "no robot " + std::to_string(id) + " on the " + name() + " platform");
}

}  // namespace vwg::platform
