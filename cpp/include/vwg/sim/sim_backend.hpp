// The simulator as the geometric system G of the case study (paper Table I): α(Robot<id>) makes
// the robot execute the transformations it is displayed under — Rotate<a>(Move<d>(Robot<1>)) turns
// robot 1 by a, then drives d — and end_frame steps the physics for the frame's dt. The same
// string drives a real robot through another backend.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vwg/backend.hpp"
#include "vwg/sim/physics.hpp"

namespace vwg::sim {

/// The names of the case study's symbols, if a world calls them otherwise.
struct MotionSymbols {
  std::string robot = "Robot";    ///< primitive; its first parameter is the robot id
  std::string move = "Move";      ///< transformation; its first parameter is a distance (m)
  std::string rotate = "Rotate";  ///< transformation; its first parameter is an angle (rad)
};

/// Turns α/β/δ calls into motion plans: the transformations around a Robot primitive, from the
/// outermost to the innermost, are the steps of the plan (each in the frame the previous one
/// left the robot in, as nested graphics transformations compose). Other transformations are
/// ignored.
class MotionInterpreter {
 public:
  explicit MotionInterpreter(MotionSymbols symbols = {}) : symbols_(std::move(symbols)) {}
  void begin_frame() { stack_.clear(); }
  void open(const NodeView& t);
  void close(const NodeView& t);
  /// For a Robot primitive: its id and the plan (empty when it is displayed under no motion).
  bool robot(const NodeView& p, int& id, std::vector<MotionStep>& plan) const;
  const MotionSymbols& symbols() const { return symbols_; }

 private:
  MotionSymbols symbols_;
  std::vector<std::optional<MotionStep>> stack_;  // one entry per open scope
};

class SimBackend final : public Backend {
 public:
  explicit SimBackend(std::shared_ptr<PhysicsWorld> world, MotionSymbols symbols = {});
  void begin_frame(const FrameInfo& frame) override;
  void primitive(const NodeView& p) override;
  void open(const NodeView& t) override { motion_.open(t); }
  void close(const NodeView& t) override { motion_.close(t); }
  void end_frame(const FrameInfo& frame) override;
  std::string name() const override { return "sim"; }
  const std::shared_ptr<PhysicsWorld>& world() const { return world_; }

 private:
  std::shared_ptr<PhysicsWorld> world_;
  MotionInterpreter motion_;
};

}  // namespace vwg::sim
