#include "vwg/error.hpp"

#include <string>

namespace vwg {

namespace {
std::string parse_message(const std::string& source, std::size_t line, std::size_t column,
                          const std::string& found, const std::string& expected,
                          const std::string& line_text) {
  std::string m = source + ":" + std::to_string(line) + ":" + std::to_string(column) + ": found " + found +
                  "; expected " + expected;
  if (!line_text.empty()) {
    m += "\n    " + line_text + "\n    ";
    // The caret sits under the column (columns count characters; the excerpt is the same line).
    m += std::string(column > 0 ? column - 1 : 0, ' ') + "^";
  }
  return m;
}
}  // namespace

ParseError::ParseError(std::string source, std::size_t line, std::size_t column, std::string found,
                       std::string expected, std::string line_text)
    : Error(parse_message(source, line, column, found, expected, line_text)),
      source_(std::move(source)), line_(line), column_(column), found_(std::move(found)),
      expected_(std::move(expected)) {}

namespace {
std::string file_message(const std::string& path, const std::string& field, const std::string& message,
                         std::size_t line, std::size_t column) {
  std::string out = path;
  if (line > 0) {
    out += ':';
    out += std::to_string(line);
    if (column > 0) {
      out += ':';
      out += std::to_string(column);
    }
  }
  out += ": ";
  if (!field.empty()) {
    out += field;
    out += ": ";
  }
  out += message;
  return out;
}
}  // namespace

FileError::FileError(std::string path, std::string field, std::string message, std::size_t line, std::size_t column)
    : SchemaError(Worded{}, field, file_message(path, field, message, line, column)), path_(std::move(path)),
      line_(line), column_(column), message_(std::move(message)) {}

std::string ParseError::reason() const { return "found " + found_ + "; expected " + expected_; }

namespace {
std::string frame_message(std::uint64_t frame, const std::string& stage, const std::string& actor,
                          const std::string& event, const std::string& where,
                          const std::string& cause) {
  std::string m = "frame " + std::to_string(frame) + ", " + stage;
  if (!actor.empty()) m += " of actor " + actor;
  if (!event.empty()) m += " for event " + event;
  if (!where.empty()) m += " (" + where + ")";
  return m + ": " + cause;
}
}  // namespace

FrameError::FrameError(std::uint64_t frame, std::string stage, std::string actor, std::string event,
                       std::string where, std::string cause_message, std::exception_ptr cause)
    : Error(frame_message(frame, stage, actor, event, where, cause_message)), frame_(frame),
      stage_(std::move(stage)), actor_(std::move(actor)), event_(std::move(event)),
      where_(std::move(where)), cause_message_(std::move(cause_message)), cause_(std::move(cause)) {}

std::string describe_exception(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::exception& ex) {
    return ex.what();
  } catch (...) {
    return "unknown exception";
  }
}

}  // namespace vwg
