#include "vwg/robot/orders.hpp"

#include <limits>

#include "vwg/error.hpp"

namespace vwg::robot {

OrderGenerator::OrderGenerator(const Alphabet& alphabet, const std::string& event)
    : event_(alphabet.event_type_id(event)) {
  require_fields(alphabet, event_, {{"marker", ValueKind::Int}});
}

void OrderGenerator::schedule(std::uint64_t frame, int robot, int marker) {
  const std::lock_guard<std::mutex> lock(mutex_);
  script_.emplace(frame, std::pair{robot, marker});
}

void OrderGenerator::order(int robot, int marker) {
  const std::lock_guard<std::mutex> lock(mutex_);
  live_.emplace_back(robot, marker);
}

bool OrderGenerator::pending(std::uint64_t frame) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return !live_.empty() || script_.upper_bound(frame) != script_.end();
}

std::uint64_t OrderGenerator::given() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return given_;
}

std::map<int, int> OrderGenerator::last() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return last_;
}

void OrderGenerator::generate(const FrameInfo& frame, EventList& out) {
  const std::lock_guard<std::mutex> lock(mutex_);
  auto send = [&](int robot, int marker) {
    const Datum fields[] = {static_cast<std::int64_t>(marker)};
    out.emit(event_, fields, robot);
    last_[robot] = marker;
    ++given_;
  };
  const auto [from, to] = script_.equal_range(frame.frame);
  for (auto it = from; it != to; ++it) send(it->second.first, it->second.second);
  while (!live_.empty()) {
    send(live_.front().first, live_.front().second);
    live_.pop_front();
  }
}

ArrivalCondition::ArrivalCondition(const Alphabet& alphabet, std::shared_ptr<const OrderGenerator> orders,
                                   const std::string& actor)
    : orders_(std::move(orders)), actor_(alphabet.symbol_id(actor, SymbolKind::Actor)) {
  if (!orders_) throw Error("ArrivalCondition: no orders");
  const Schema& schema = alphabet.symbol(actor_).schema;
  const int id = schema.index_of("id"), reached = schema.index_of("reached");
  if (id < 0 || reached < 0) throw SchemaError(actor, "an actor with the attributes id and reached");
  id_ = static_cast<std::size_t>(id);
  reached_ = static_cast<std::size_t>(reached);
}

bool ArrivalCondition::done(const WorldString& w, std::uint64_t frame) {
  if (orders_->given() == 0 || orders_->pending(frame)) return false;
  const std::map<int, int> last = orders_->last();
  std::size_t sent = 0, arrived = 0;
  for (const auto& [robot, marker] : last) sent += marker != kNoObjective;
  for (std::size_t i = 0; i < w.nodes().size(); ++i) {
    const Node& n = w.nodes()[i];
    if (n.kind != NodeKind::Actor || n.symbol != actor_) continue;
    const NodeView v = w.node(i);
    const auto it = last.find(static_cast<int>(v.value(id_).i));
    if (it == last.end() || it->second == kNoObjective) continue;
    if (!v.value(reached_).b) return false;
    ++arrived;
  }
  return arrived == sent;  // a robot that was sent somewhere and has gone has not arrived
}

void OrderGenerator::save_state(StateWriter& out) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  out.u64(script_.size());
  for (const auto& [frame, order] : script_) {
    out.u64(frame);
    out.i64(order.first);
    out.i64(order.second);
  }
  out.u64(live_.size());
  for (const auto& [robot, marker] : live_) {
    out.i64(robot);
    out.i64(marker);
  }
  out.u64(given_);
  out.u64(last_.size());
  for (const auto& [robot, marker] : last_) {
    out.i64(robot);
    out.i64(marker);
  }
}

void OrderGenerator::load_state(StateReader& in) {
  auto read_int = [&] {
    const std::int64_t v = in.i64();
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) in.fail("a robot or marker out of range");
    return static_cast<int>(v);
  };
  std::multimap<std::uint64_t, std::pair<int, int>> script;
  for (std::size_t n = in.count(24, "scripted orders"); n > 0; --n) {
    const std::uint64_t frame = in.u64();
    const int robot = read_int();
    script.emplace(frame, std::pair{robot, read_int()});
  }
  std::deque<std::pair<int, int>> live;
  for (std::size_t n = in.count(16, "orders given"); n > 0; --n) {
    const int robot = read_int();
    live.emplace_back(robot, read_int());
  }
  const std::uint64_t given = in.u64();
  std::map<int, int> last;
  for (std::size_t n = in.count(16, "orders sent"); n > 0; --n) {
    const int robot = read_int();
    last[robot] = read_int();
  }
  in.end();
  const std::lock_guard<std::mutex> lock(mutex_);
  script_ = std::move(script);
  live_ = std::move(live);
  given_ = given;
  last_ = std::move(last);
}

}  // namespace vwg::robot
