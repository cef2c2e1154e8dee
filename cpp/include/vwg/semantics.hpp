// The semantic functions of the system algorithm (paper §II.B.4):
//   evolve    η(w, S)  eq. 8 — every actor takes the events of S it responds to, in order (a fold,
//                              DESIGN.md choice 1);
//   visualize π(w, Z)  eq. 9 — every actor shows itself through θ for the visual events of S
//                              (recursing with π inside scopes, DESIGN.md choice 2);
//   display   φ(v, G)  eq. 7 — α for primitives, β ... δ around each scope, on a backend.
#pragma once

#include <cstdint>

#include "vwg/blob_edit.hpp"
#include "vwg/actor.hpp"
#include "vwg/backend.hpp"
#include "vwg/event.hpp"
#include "vwg/world_string.hpp"

namespace vwg {

/// What the semantic functions need to know about the frame.
struct FrameContext {
  std::uint64_t frame = 0;
  double time = 0.0;
  std::uint64_t seed = 0;  ///< engine seed; per actor-event seeds are derived from it
};

/// η: the next string. Transformations whose scope became empty are removed (t(ε) ∉ L(M)).
/// Errors inside λ are raised as FrameError naming the actor, the event and the frame.
WorldString evolve(const WorldString& w, const EventList& events, const FrameContext& ctx);
/// η as the engine runs it on its own string: λ may write in place into blobs that `w` alone holds
/// (ActorState::edit_blob), so `w` is left changed; `journal` keeps what to put back if the frame
/// fails. Call visualize(w, ...) first: θ reads w as it was. With `threads` > 1, the actors whose
/// behaviours are concurrent() evolve side by side on that many threads; the result is the same.
WorldString evolve_in_place(const WorldString& w, const EventList& events, const FrameContext& ctx,
                            BlobJournal& journal, unsigned threads = 1);

/// π: the displayable string (no actors) for the visual events among `events`.
WorldString visualize(const WorldString& w, const EventList& events, const FrameContext& ctx);

/// φ: run a string with no actors on `backend` (α, β, δ in string order). An actor in `v` is an
/// error: only π's output is displayable.
void display(const WorldString& v, Backend& backend);

}  // namespace vwg
