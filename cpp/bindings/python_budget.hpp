// The time a Python part (an actor's λ or θ, a generator, a backend, a decider) may take for one call
// before it is reported: a warning through vwg's log naming the part and the time. Only reported:
// what a frame computes never depends on a clock (the frame log stays the same on any machine).
#pragma once

#include <chrono>
#include <functional>
#include <string>

namespace vwg::bindings {

/// Seconds; 0 turns the reports off.
double python_budget();
void set_python_budget(double seconds);

/// Times the Python call in its scope; `describe` names the part, and is called only for a report.
class PythonCallTimer {
 public:
  explicit PythonCallTimer(std::function<std::string()> describe)
      : describe_(std::move(describe)), start_(std::chrono::steady_clock::now()) {}
  PythonCallTimer(const PythonCallTimer&) = delete;
  PythonCallTimer& operator=(const PythonCallTimer&) = delete;
  ~PythonCallTimer();

 private:
  std::function<std::string()> describe_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace vwg::bindings
