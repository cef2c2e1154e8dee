#include "vwg/backend.hpp"

#include <mutex>
#include <string>

#include "vwg/error.hpp"
#include "vwg/registry.hpp"

namespace vwg {

BackendGroup::BackendGroup(std::vector<std::shared_ptr<Backend>> backends) : backends_(std::move(backends)) {
  for (const auto& b : backends_) {
    if (!b) throw Error("BackendGroup: a backend is null");
  }
}
void BackendGroup::begin_frame(const FrameInfo& frame) {
  for (const auto& b : backends_) b->begin_frame(frame);
}
void BackendGroup::primitive(const NodeView& p) {
  for (const auto& b : backends_) b->primitive(p);
}
void BackendGroup::open(const NodeView& t) {
  for (const auto& b : backends_) b->open(t);
}
void BackendGroup::close(const NodeView& t) {
  for (const auto& b : backends_) b->close(t);
}
void BackendGroup::end_frame(const FrameInfo& frame) {
  for (const auto& b : backends_) b->end_frame(frame);
}
std::string BackendGroup::name() const {
  std::string n;
  for (const auto& b : backends_) {
    if (!n.empty()) n += '+';  // (a ?: on char arrays + a string here made GCC 12 warn -Wrestrict wrongly)
    n += b->name();
  }
  return n;
}

void TraceBackend::begin_frame(const FrameInfo& frame) { calls_.push_back("frame " + std::to_string(frame.frame)); }
void TraceBackend::primitive(const NodeView& p) { calls_.push_back("alpha " + to_text(p)); }
void TraceBackend::open(const NodeView& t) { calls_.push_back("beta " + to_text(t)); }
void TraceBackend::close(const NodeView& t) { calls_.push_back("delta " + to_text(t)); }

Registry<Backend>& backends() {
  static Registry<Backend> registry("backend");
  static std::once_flag built_in;
  std::call_once(built_in, [] {
    registry.add("trace", [] { return std::make_shared<TraceBackend>(); });
    registry.add("null", [] { return std::make_shared<NullBackend>(); });
  });
  return registry;
}

}  // namespace vwg
