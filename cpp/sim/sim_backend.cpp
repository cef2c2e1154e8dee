#include "vwg/sim/sim_backend.hpp"

#include <cmath>

#include "vwg/error.hpp"

namespace vwg::sim {

void MotionInterpreter::open(const NodeView& t) {
  const std::string& name = t.info().name;
  if (name == symbols_.move || name == symbols_.rotate) {
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

bool MotionInterpreter::robot(const NodeView& p, int& id, std::vector<MotionStep>& plan) const {
  if (p.info().name != symbols_.robot) return false;
  if (p.value_count() < 1) throw SchemaError(symbols_.robot, "needs the robot id as first parameter");
  id = static_cast<int>(p.number(0));
  plan.clear();
  for (const auto& step : stack_) {
    if (step) plan.push_back(*step);
  }
  return true;
}

SimBackend::SimBackend(std::shared_ptr<PhysicsWorld> world, MotionSymbols symbols)
    : world_(std::move(world)), motion_(std::move(symbols)) {
  if (!world_) throw Error("SimBackend: no physics world");
}

void SimBackend::begin_frame(const FrameInfo&) { motion_.begin_frame(); }

void SimBackend::primitive(const NodeView& p) {
  int id = 0;
  std::vector<MotionStep> plan;
  // A robot displayed under no motion keeps doing what it was doing (Table I: "no action").
  if (motion_.robot(p, id, plan) && !plan.empty()) world_->command(id, std::move(plan));
}

void SimBackend::end_frame(const FrameInfo& frame) { world_->advance(frame.dt); }

}  // namespace vwg::sim
