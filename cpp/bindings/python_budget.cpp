#include "python_budget.hpp"

#include <atomic>
#include <cmath>
#include <cstdio>

#include "vwg/log.hpp"

namespace vwg::bindings {

namespace {
std::atomic<double> g_budget{1.0};
}  // namespace

double python_budget() { return g_budget.load(std::memory_order_relaxed); }

void set_python_budget(double seconds) { g_budget.store(seconds, std::memory_order_relaxed); }

PythonCallTimer::~PythonCallTimer() {
  const double budget = python_budget();
  if (!(budget > 0)) return;
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (took <= budget) return;
  try {
    char buf[96];
    std::snprintf(buf, sizeof buf, " took %.3f s, over the budget of %.3f s for one call", took, budget);
    log(LogLevel::Warning, "python", describe_() + buf);
  } catch (...) {
    // A report must never turn into a failure of the frame (a destructor does not throw).
  }
}

}  // namespace vwg::bindings
