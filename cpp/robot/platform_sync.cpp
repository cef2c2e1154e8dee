#include "vwg/robot/platform_sync.hpp"

#include <set>
#include <vector>

#include "vwg/error.hpp"

namespace vwg::robot {

PlatformSync::PlatformSync(const Alphabet& alphabet, std::shared_ptr<platform::RobotPlatform> platform, double radius,
                           platform::RobotLimits limits, const std::string& actor)
    : platform_(std::move(platform)), radius_(radius), limits_(limits),
      actor_(alphabet.symbol_id(actor, SymbolKind::Actor)) {
  if (!platform_) throw Error("PlatformSync: no platform");
  const Schema& schema = alphabet.symbol(actor_).schema;
  const int id = schema.index_of("id"), x = schema.index_of("x"), y = schema.index_of("y"),
            angle = schema.index_of("angle");
  if (id < 0 || x < 0 || y < 0 || angle < 0) throw SchemaError(actor, "an actor with the attributes id, x, y and angle");
  id_ = static_cast<std::size_t>(id);
  x_ = static_cast<std::size_t>(x);
  y_ = static_cast<std::size_t>(y);
  angle_ = static_cast<std::size_t>(angle);
}

void PlatformSync::operator()(const FrameRecord& frame) {
  const WorldString& w = frame.after;
  std::set<int> present;
  std::vector<platform::RobotSettings> born;
  std::set<int> known;
  for (const platform::RobotState& s : platform_->robots()) known.insert(s.id);
  for (std::size_t i = 0; i < w.nodes().size(); ++i) {
    const Node& n = w.nodes()[i];
    if (n.kind != NodeKind::Actor || n.symbol != actor_) continue;
    const NodeView v = w.node(i);
    const int id = static_cast<int>(v.value(id_).i);
    present.insert(id);
    if (!known.contains(id)) {
      born.push_back(platform::RobotSettings{id, {v.number(x_), v.number(y_), v.number(angle_)}, radius_, limits_});
    }
  }
  for (const int id : known) {
    if (!present.contains(id)) platform_->remove_robot(id);
  }
  for (const platform::RobotSettings& r : born) platform_->add_robot(r);
}

}  // namespace vwg::robot
