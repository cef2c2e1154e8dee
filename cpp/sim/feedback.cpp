#include "vwg/sim/feedback.hpp"

#include <string>

#include "vwg/error.hpp"

namespace vwg::sim {

void require_fields(const Alphabet& alphabet, EventTypeId id, std::initializer_list<std::pair<const char*, ValueKind>> fields) {
  const EventTypeInfo& info = alphabet.event_type(id);
  std::string expected;
  for (const auto& [name, kind] : fields) {
    expected += (expected.empty() ? "" : ", ") + std::string(name) + ": " + std::string(kind_name(kind));
  }
  bool ok = info.fields.params.size() == fields.size();
  std::size_t i = 0;
  for (const auto& [name, kind] : fields) {
    ok = ok && info.fields.params[i].name == name && info.fields.params[i].kind == kind;
    ++i;
  }
  if (!ok) throw SchemaError(info.name, "the simulator needs the fields (" + expected + ")");
}

OdometryGenerator::OdometryGenerator(std::shared_ptr<PhysicsWorld> world, const Alphabet& alphabet, const std::string& event)
    : world_(std::move(world)), event_(alphabet.event_type_id(event)) {
  require_fields(alphabet, event_, {{"x", ValueKind::Real}, {"y", ValueKind::Real}, {"angle", ValueKind::Real}, {"busy", ValueKind::Bool},
                                     {"commands", ValueKind::Int}});
}

void OdometryGenerator::generate(const FrameInfo&, EventList& out) {
  for (const RobotState& s : world_->robots()) {
    const Datum fields[] = {s.odometry.x, s.odometry.y, s.odometry.theta, s.busy, static_cast<std::int64_t>(s.commands)};
    out.emit(event_, fields, s.id);
  }
}

CollisionGenerator::CollisionGenerator(std::shared_ptr<PhysicsWorld> world, const Alphabet& alphabet, const std::string& event)
    : world_(std::move(world)), event_(alphabet.event_type_id(event)) {
  require_fields(alphabet, event_, {{"other", ValueKind::Int}});
}

void CollisionGenerator::generate(const FrameInfo&, EventList& out) {
  for (const Collision& c : world_->take_collisions()) {
    const Datum fields[] = {static_cast<std::int64_t>(c.other)};
    out.emit(event_, fields, c.robot);
  }
}

}  // namespace vwg::sim
