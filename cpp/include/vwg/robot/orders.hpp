// gObjective, the users' orders (paper Table II), and the stop condition of the case study: a run
// is done when every robot that was sent somewhere is there (or had its task interrupted) and no
// order is still to come.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "vwg/alphabet.hpp"
#include "vwg/engine.hpp"
#include "vwg/generator.hpp"

namespace vwg::robot {

/// The marker of an eObjective that interrupts the robot's task (the supervisor "can interrupt the
/// current task or begin a new task", paper §III): the robot stops and waits for its next order.
inline constexpr int kNoObjective = -1;

/// eObjective<to=robot, marker> events: a timed script (orders at given frames), and orders given
/// while running (any thread: from a stream of user input, a web page, an API) for the next frame.
class OrderGenerator final : public Generator {
 public:
  explicit OrderGenerator(const Alphabet& alphabet, const std::string& event = "eObjective");
  /// Send `robot` to the room of `marker` at `frame`.
  void schedule(std::uint64_t frame, int robot, int marker);
  /// Send `robot` to the room of `marker` at the next frame (thread-safe).
  void order(int robot, int marker);
  /// Interrupt `robot`'s task at the next frame: eObjective<marker = kNoObjective> (thread-safe).
  void cancel(int robot) { order(robot, kNoObjective); }
  /// Whether orders are still to come after `frame` (scripted later, or given and not yet sent).
  bool pending(std::uint64_t frame) const;
  /// Orders sent so far.
  std::uint64_t given() const;
  /// Robot -> the marker of the last order it was sent (kNoObjective: its task was interrupted).
  std::map<int, int> last() const;

  void generate(const FrameInfo& frame, EventList& out) override;
  std::string name() const override { return "gObjective"; }
  /// The script still to come, the orders given and not yet sent, and what was sent so far.
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;

 private:
  EventTypeId event_;
  mutable std::mutex mutex_;  // order() may come from another thread
  std::multimap<std::uint64_t, std::pair<int, int>> script_;
  std::deque<std::pair<int, int>> live_;
  std::uint64_t given_ = 0;
  std::map<int, int> last_;
};

/// Done when at least one order was sent, none is still to come, and every robot whose last order
/// sent it somewhere says it reached it (its `reached` attribute, decided with the world's goal
/// tolerance); a robot whose task was interrupted is not waited for.
class ArrivalCondition final : public StopCondition {
 public:
  ArrivalCondition(const Alphabet& alphabet, std::shared_ptr<const OrderGenerator> orders,
                   const std::string& actor = "ARobot");
  bool done(const WorldString& w, std::uint64_t frame) override;

 private:
  std::shared_ptr<const OrderGenerator> orders_;
  SymbolId actor_;
  std::size_t id_, reached_;  // attribute indices
};

}  // namespace vwg::robot
