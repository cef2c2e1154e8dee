// The geometric system G (paper eq. 1-2): where α, β and δ act. A backend receives the displayable
// string of each frame through display() (φ, eq. 7) between begin_frame and end_frame.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vwg/generator.hpp"
#include "vwg/world_string.hpp"

namespace vwg {

class Backend {
 public:
  virtual ~Backend() = default;
  virtual void begin_frame(const FrameInfo& frame) { (void)frame; }
  /// α(p): run a primitive.
  virtual void primitive(const NodeView& p) = 0;
  /// β(t): a transformation's scope opens.
  virtual void open(const NodeView& t) = 0;
  /// δ(t): the scope of `t` closes (`t` is the transformation that opened it).
  virtual void close(const NodeView& t) = 0;
  virtual void end_frame(const FrameInfo& frame) { (void)frame; }
  virtual std::string name() const { return "backend"; }
};

/// Does nothing: for measuring evolution alone.
class NullBackend final : public Backend {
 public:
  void primitive(const NodeView&) override {}
  void open(const NodeView&) override {}
  void close(const NodeView&) override {}
  std::string name() const override { return "null"; }
};

/// Several backends as one: every call goes to each, in the order given (e.g. the simulator
/// first, then a renderer that draws what it did).
class BackendGroup final : public Backend {
 public:
  explicit BackendGroup(std::vector<std::shared_ptr<Backend>> backends);
  void begin_frame(const FrameInfo& frame) override;
  void primitive(const NodeView& p) override;
  void open(const NodeView& t) override;
  void close(const NodeView& t) override;
  void end_frame(const FrameInfo& frame) override;
  std::string name() const override;
  const std::vector<std::shared_ptr<Backend>>& backends() const { return backends_; }

 private:
  std::vector<std::shared_ptr<Backend>> backends_;
};

/// Records every call as text: "alpha Robot<1>", "beta Move<0.5>", "delta Move<0.5>", and
/// "frame 3" at each begin_frame. For tests and for seeing what φ does.
class TraceBackend final : public Backend {
 public:
  void begin_frame(const FrameInfo& frame) override;
  void primitive(const NodeView& p) override;
  void open(const NodeView& t) override;
  void close(const NodeView& t) override;
  std::string name() const override { return "trace"; }

  const std::vector<std::string>& calls() const { return calls_; }
  void clear() { calls_.clear(); }

 private:
  std::vector<std::string> calls_;
};

}  // namespace vwg
