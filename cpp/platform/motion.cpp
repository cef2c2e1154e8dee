#include "vwg/platform/motion.hpp"

#include <cmath>

#include "vwg/error.hpp"

namespace vwg::platform {

void MotionInterpreter::open(const NodeView& t) {
  const std::string& name = t.info().name;
  if (name == symbols_.velocity) {
    if (t.value_count() < 2) throw SchemaError(name, "needs a speed and a turn rate as its parameters");
    stack_.push_back(MotionStep{MotionStep::Steer, t.number(0), t.number(1)});
  } else if (name == symbols_.move || name == symbols_.rotate) {
    if (t.value_count() < 1) throw SchemaError(name, "needs its amount as first parameter");
    const double amount = t.number(0);
    stack_.push_back(MotionStep{name == symbols_.move ? MotionStep::Drive : MotionStep::Turn, amount});
  } else {
    stack_.push_back(std::nullopt);  // not a motion: keeps the scopes balanced
  }
}

void MotionInterpreter::close(const NodeView&) {
  if (!stack_.empty()) stack_.pop_back();
}

bool MotionInterpreter::robot(const NodeView& p, int& id, std::vector<MotionStep>& steps) const {
  if (p.info().name != symbols_.robot) return false;
  if (p.value_count() < 1) throw SchemaError(symbols_.robot, "needs the robot id as first parameter");
  id = static_cast<int>(p.number(0));
  steps.clear();
  for (const auto& step : stack_) {
    if (step) steps.push_back(*step);
  }
  return true;
}

MotionBackend::MotionBackend(std::shared_ptr<RobotPlatform> platform, MotionSymbols symbols)
    : platform_(std::move(platform)), motion_(std::move(symbols)) {
  if (!platform_) throw Error("MotionBackend: no platform");
}

void MotionBackend::begin_frame(const FrameInfo&) { motion_.begin_frame(); }

void MotionBackend::primitive(const NodeView& p) {
  int id = 0;
  std::vector<MotionStep> steps;
  if (motion_.robot(p, id, steps) && !steps.empty()) platform_->command(id, std::move(steps));
}

void MotionBackend::end_frame(const FrameInfo& frame) { platform_->advance(frame.dt); }

}  // namespace vwg::platform
