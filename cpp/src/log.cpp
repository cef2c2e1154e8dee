#include "vwg/log.hpp"

#include <memory>
#include <mutex>
#include <utility>

namespace vwg {

namespace {

std::mutex& sink_mutex() {
  static std::mutex m;
  return m;
}

// Shared so that a message being delivered keeps its sink alive while another thread replaces it.
std::shared_ptr<const LogSink>& sink_slot() {
  static std::shared_ptr<const LogSink> sink;
  return sink;
}

}  // namespace

void set_log_sink(LogSink sink) {
  auto next = sink ? std::make_shared<const LogSink>(std::move(sink)) : nullptr;
  const std::lock_guard<std::mutex> lock(sink_mutex());
  sink_slot() = std::move(next);
}

void log(LogLevel level, std::string_view source, std::string_view message) {
  std::shared_ptr<const LogSink> sink;
  {
    const std::lock_guard<std::mutex> lock(sink_mutex());
    sink = sink_slot();
  }
  if (sink) (*sink)(level, source, message);
}

}  // namespace vwg
