// The motion vocabulary of the case study (paper Table I) on any platform: the transformations
// Move<d> and Rotate<a> around a Robot<id> primitive are a motion command, Rotate<a>(Move<d>(Robot<1>))
// turning robot 1 by a, then driving d; Velocity<v, w>(Robot<1>) holds speed v and turn rate w until
// the next command (a local planner's velocity, given every frame). MotionBackend is the geometric system G of the robots: φ
// sends the commands to the platform, and the end of the frame lets the frame's dt pass on it.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vwg/backend.hpp"
#include "vwg/platform/platform.hpp"

namespace vwg::platform {

/// The names of the case study's symbols, if a world calls them otherwise.
struct MotionSymbols {
  std::string robot = "Robot";    ///< primitive; its first parameter is the robot id
  std::string move = "Move";      ///< transformation; its first parameter is a distance (m)
  std::string rotate = "Rotate";  ///< transformation; its first parameter is an angle (rad)
  std::string velocity = "Velocity";  ///< transformation; its parameters are a speed (m/s) and a turn rate (rad/s)
};

/// Turns α/β/δ calls into motion commands: the transformations around a Robot primitive, from the
/// outermost to the innermost, are the steps (each in the frame the previous one left the robot
/// in, as nested graphics transformations compose). Other transformations are ignored.
class MotionInterpreter {
 public:
  explicit MotionInterpreter(MotionSymbols symbols = {}) : symbols_(std::move(symbols)) {}
  void begin_frame() { stack_.clear(); }
  void open(const NodeView& t);
  void close(const NodeView& t);
  /// For a Robot primitive: its id and the steps (empty when it is displayed under no motion).
  bool robot(const NodeView& p, int& id, std::vector<MotionStep>& steps) const;
  const MotionSymbols& symbols() const { return symbols_; }

 private:
  MotionSymbols symbols_;
  std::vector<std::optional<MotionStep>> stack_;  // one entry per open scope
};

/// φ on a platform: α(Robot<id>) under motions commands the robot; under none it keeps doing what
/// it was doing (Table I: "no action"). end_frame lets the frame's dt pass on the platform.
class MotionBackend final : public Backend {
 public:
  explicit MotionBackend(std::shared_ptr<RobotPlatform> platform, MotionSymbols symbols = {});
  void begin_frame(const FrameInfo& frame) override;
  void primitive(const NodeView& p) override;
  void open(const NodeView& t) override { motion_.open(t); }
  void close(const NodeView& t) override { motion_.close(t); }
  void end_frame(const FrameInfo& frame) override;
  std::string name() const override { return "motion (" + platform_->name() + ")"; }
  const std::shared_ptr<RobotPlatform>& platform() const { return platform_; }

 private:
  std::shared_ptr<RobotPlatform> platform_;
  MotionInterpreter motion_;
};

}  // namespace vwg::platform
