// Diagnostics of vwg and of the libraries it wraps (OMPL, ...), routed to one sink. Libraries print
// to the terminal on their own; vwg catches what they say and hands it here, so an application
// decides what is shown (the Python module forwards to the `logging` module, quiet by default).
#pragma once

#include <functional>
#include <string_view>

namespace vwg {

enum class LogLevel { Debug = 10, Info = 20, Warning = 30, Error = 40 };  // Python logging's numbers

/// Receives every message: its level, where it comes from ("ompl", "vwg.plan") and the text.
/// May be called from any thread; calls are not serialized.
using LogSink = std::function<void(LogLevel level, std::string_view source, std::string_view message)>;

/// Replace the sink (an empty one drops messages, the default). Thread-safe.
void set_log_sink(LogSink sink);

/// Send a message to the sink. Thread-safe; the sink runs outside any lock of vwg's.
void log(LogLevel level, std::string_view source, std::string_view message);

}  // namespace vwg
