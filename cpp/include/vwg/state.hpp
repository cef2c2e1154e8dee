// The bytes of a saved run's state (DESIGN.md, "Saved runs"): what a generator, a decider, an actor
// type or a platform keeps outside the world string, written by save_state() and read back by
// load_state(). Numbers are little-endian and doubles keep their bits, so a state read on another
// machine goes on with the same frames. A reader checks every length against what is left: a cut or
// damaged state is a SchemaError naming its part, never a read past the end.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "vwg/error.hpp"

namespace vwg {

static_assert(std::endian::native == std::endian::little, "saved states are little-endian bytes");

class StateWriter {
 public:
  void u8(std::uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void u64(std::uint64_t v) { raw(&v, sizeof v); }
  void i64(std::int64_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void text(std::string_view s) {
    u64(s.size());
    raw(s.data(), s.size());
  }
  /// A vector of plain values (numbers, or structs of numbers without padding), its length first.
  template <class T>
  void pods(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    u64(v.size());
    raw(v.data(), v.size() * sizeof(T));
  }
  void raw(const void* data, std::size_t n) {
    if (n > 0) bytes_.append(static_cast<const char*>(data), n);
  }
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class StateReader {
 public:
  /// `part` names the state in errors ("generator 2 (gLaser)", "decider astar").
  StateReader(std::string_view bytes, std::string part) : bytes_(bytes), part_(std::move(part)) {}

  std::uint8_t u8() {
    std::uint8_t v;
    raw(&v, 1, "a byte");
    return v;
  }
  bool boolean() {
    const std::uint8_t v = u8();
    if (v > 1) fail("expected a flag (0 or 1), found " + std::to_string(v));
    return v == 1;
  }
  std::uint64_t u64() {
    std::uint64_t v;
    raw(&v, sizeof v, "a 64-bit number");
    return v;
  }
  std::int64_t i64() {
    std::int64_t v;
    raw(&v, sizeof v, "a 64-bit number");
    return v;
  }
  double f64() {
    double v;
    raw(&v, sizeof v, "a double");
    return v;
  }
  /// A count of things of `size` bytes each that the rest of the state can hold (so a damaged
  /// length is refused before anything is allocated for it).
  std::size_t count(std::size_t size, const char* what) {
    const std::uint64_t n = u64();
    if (size > 0 && n > left() / size) {
      fail("a length of " + std::to_string(n) + " " + what + " is more than the " + std::to_string(left()) +
           " bytes left");
    }
    return static_cast<std::size_t>(n);
  }
  std::string text() {
    const std::size_t n = count(1, "characters");
    std::string s(n, '\0');
    raw(s.data(), n, "text");
    return s;
  }
  template <class T>
  std::vector<T> pods() {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<T> v(count(sizeof(T), "values"));
    raw(v.data(), v.size() * sizeof(T), "values");
    return v;
  }
  void raw(void* out, std::size_t n, const char* what) {
    if (n > left()) fail(std::string("cut short: expected ") + what + " at byte " + std::to_string(at_));
    if (n > 0) std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  std::size_t left() const { return bytes_.size() - at_; }
  /// Every byte read: a state with bytes after its end is not the one it claims to be.
  void end() const {
    if (left() != 0) fail(std::to_string(left()) + " bytes after the end of the state");
  }
  [[noreturn]] void fail(const std::string& what) const { throw SchemaError(part_, "saved state: " + what); }
  const std::string& part() const { return part_; }
  /// The saved run's simulated time, when the reader knows it: nothing the state holds may make
  /// more time pass (a simulator's journal), so a damaged or forged state cannot ask for years.
  void limit_seconds(double seconds) { max_seconds_ = seconds; }
  double max_seconds() const { return max_seconds_; }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
  std::string part_;
  double max_seconds_ = std::numeric_limits<double>::infinity();
};

}  // namespace vwg
