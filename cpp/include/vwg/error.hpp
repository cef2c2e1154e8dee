// The errors vwg raises. Each says where (source, line, column / field / frame) and what was expected.
#pragma once

#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>

namespace vwg {

/// Base of all vwg errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A value or declaration that does not fit its schema: unknown attribute, wrong type, NaN,
/// duplicate name. `field` names what was wrong (e.g. "ARobot.row").
class SchemaError : public Error {
 public:
  SchemaError(std::string field, const std::string& message)
      : Error(field.empty() ? message : field + ": " + message), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 protected:
  /// For subclasses that word the whole message themselves.
  struct Worded {};
  SchemaError(Worded, std::string field, const std::string& what) : Error(what), field_(std::move(field)) {}

 private:
  std::string field_;
};

/// A bad file a user named (a map, a world): the file, the line and column (1-based, 0 when not
/// known), the field inside it ("map[3]", "width") and what was wrong. Its message reads
/// "path:line:column: field: message", and Python raises it as vwg.errors.WorldFileError.
class FileError : public SchemaError {
 public:
  FileError(std::string path, std::string field, std::string message, std::size_t line = 0, std::size_t column = 0);

  const std::string& path() const { return path_; }
  std::size_t line() const { return line_; }
  std::size_t column() const { return column_; }
  /// What was wrong, without the place.
  const std::string& message() const { return message_; }

 private:
  std::string path_;
  std::size_t line_, column_;
  std::string message_;
};

/// Malformed text: names the source, line and column (1-based, in characters), what was found
/// and what was expected, and shows the line with a caret.
class ParseError : public Error {
 public:
  ParseError(std::string source, std::size_t line, std::size_t column, std::string found,
             std::string expected, std::string line_text);

  const std::string& source() const { return source_; }
  std::size_t line() const { return line_; }
  std::size_t column() const { return column_; }
  const std::string& found() const { return found_; }
  const std::string& expected() const { return expected_; }
  /// The message without the source position and excerpt.
  std::string reason() const;

 private:
  std::string source_;
  std::size_t line_, column_;
  std::string found_, expected_;
};

/// Something failed while running a frame. The world keeps its last complete frame.
/// `stage` is one of "generate", "evolve" (λ), "visualize" (θ), "display" (φ, the backend).
class FrameError : public Error {
 public:
  FrameError(std::uint64_t frame, std::string stage, std::string actor, std::string event,
             std::string where, std::string cause_message, std::exception_ptr cause);

  std::uint64_t frame() const { return frame_; }
  const std::string& stage() const { return stage_; }
  const std::string& actor() const { return actor_; }  ///< text form of the actor, or ""
  const std::string& event() const { return event_; }  ///< text form of the event, or ""
  const std::string& where() const { return where_; }  ///< generator / backend name, position
  const std::string& cause_message() const { return cause_message_; }
  std::exception_ptr cause() const { return cause_; }

 private:
  std::uint64_t frame_;
  std::string stage_, actor_, event_, where_, cause_message_;
  std::exception_ptr cause_;
};

/// What an exception in flight says: its what() or a generic text for foreign exceptions.
std::string describe_exception(const std::exception_ptr& e);

}  // namespace vwg
