#include "vwg/backend.hpp"

#include <string>

namespace vwg {

void TraceBackend::begin_frame(const FrameInfo& frame) { calls_.push_back("frame " + std::to_string(frame.frame)); }
void TraceBackend::primitive(const NodeView& p) { calls_.push_back("alpha " + to_text(p)); }
void TraceBackend::open(const NodeView& t) { calls_.push_back("beta " + to_text(t)); }
void TraceBackend::close(const NodeView& t) { calls_.push_back("delta " + to_text(t)); }

}  // namespace vwg
