#include "vwg/platform/feedback.hpp"

#include <algorithm>
#include <string>

#include "vwg/error.hpp"

namespace vwg::platform {

OdometryGenerator::OdometryGenerator(std::shared_ptr<RobotPlatform> platform, const Alphabet& alphabet,
                                     const std::string& event, std::vector<int> localized)
    : platform_(std::move(platform)), event_(alphabet.event_type_id(event)), localized_(std::move(localized)) {
  std::sort(localized_.begin(), localized_.end());
  if (!platform_) throw Error("OdometryGenerator: no platform");
  require_fields(alphabet, event_, {{"x", ValueKind::Real}, {"y", ValueKind::Real}, {"angle", ValueKind::Real},
                                    {"busy", ValueKind::Bool}, {"commands", ValueKind::Int}});
}

void OdometryGenerator::generate(const FrameInfo&, EventList& out) {
  for (const RobotState& s : platform_->robots()) {
    if (std::binary_search(localized_.begin(), localized_.end(), s.id)) continue;
    const Datum fields[] = {s.odometry.x, s.odometry.y, s.odometry.theta, s.busy, static_cast<std::int64_t>(s.commands)};
    out.emit(event_, fields, s.id);
  }
}

CollisionGenerator::CollisionGenerator(std::shared_ptr<RobotPlatform> platform, const Alphabet& alphabet,
                                       const std::string& event)
    : platform_(std::move(platform)), event_(alphabet.event_type_id(event)) {
  if (!platform_) throw Error("CollisionGenerator: no platform");
  require_fields(alphabet, event_, {{"other", ValueKind::Int}});
}

void CollisionGenerator::generate(const FrameInfo&, EventList& out) {
  for (const Collision& c : platform_->take_collisions()) {
    const Datum fields[] = {static_cast<std::int64_t>(c.other)};
    out.emit(event_, fields, c.robot);
  }
}

}  // namespace vwg::platform
