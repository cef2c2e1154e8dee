#include "vwg/semantics.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "src/parallel.hpp"
#include "vwg/error.hpp"
#include "vwg/random.hpp"
#include "vwg/text.hpp"

namespace vwg {

namespace {

/// For each actor type, the positions in S of the events it receives (type in H, and visual for
/// π), computed once per type per call; and for one actor, those of its events that are for every
/// actor merged with those addressed to its id, so an actor never scans the events addressed to
/// the others (a hundred robots, each with 180 laser events a frame). Once a type is prepared,
/// its lookups only read, so actors evolving on several threads share one routing.
class EventRouting {
 public:
  EventRouting(const EventList& events, bool visual_only) : events_(events), visual_only_(visual_only) {}

  const std::vector<std::uint32_t>& for_type(const SymbolInfo& info) { return index(info).all; }

  /// Whether any event for the actor with `id` is at position `first` of S or later (what
  /// for_actor would list from there, without merging the lists).
  bool any_from(const SymbolInfo& info, const std::optional<std::int64_t>& id, std::uint32_t first) {
    const TypeIndex& t = index(info);
    auto reaches_first = [first](const std::vector<std::uint32_t>& v) { return !v.empty() && v.back() >= first; };
    if (reaches_first(t.untargeted)) return true;
    if (!id) return false;
    const auto addressed = t.by_target.find(*id);
    return addressed != t.by_target.end() && reaches_first(addressed->second);
  }

  /// The positions of the events for the actor with `id`, in S order: one of the index's lists,
  /// or `scratch` when two lists have to be merged. Only reads once the type's index is built.
  const std::vector<std::uint32_t>& for_actor(const SymbolInfo& info, const std::optional<std::int64_t>& id,
                                              std::vector<std::uint32_t>& scratch) {
    const TypeIndex& t = index(info);
    if (!id) return t.untargeted;
    const auto addressed = t.by_target.find(*id);
    if (addressed == t.by_target.end()) return t.untargeted;
    if (t.untargeted.empty()) return addressed->second;
    scratch.clear();
    scratch.reserve(t.untargeted.size() + addressed->second.size());
    std::merge(t.untargeted.begin(), t.untargeted.end(), addressed->second.begin(), addressed->second.end(),
               std::back_inserter(scratch));
    return scratch;
  }

 private:
  struct TypeIndex {
    std::vector<std::uint32_t> all, untargeted;
    std::unordered_map<std::int64_t, std::vector<std::uint32_t>> by_target;
  };

  const TypeIndex& index(const SymbolInfo& info) {
    if (const auto found = types_.find(info.id); found != types_.end()) return found->second;
    TypeIndex& t = types_[info.id];  // node-based: references stay valid
    const Alphabet& A = events_.alphabet();
    // Events come in batches (a robot's laser scan, all to one robot), and batches addressed to
    // one actor in runs: its list is looked up once a run.
    std::int64_t last_target = kNoTarget;
    std::vector<std::uint32_t>* last_list = nullptr;
    for (std::size_t b = 0; b < events_.batch_count(); ++b) {
      const EventList::Batch& batch = events_.batch(b);
      if (!info.responds.contains(batch.type)) continue;
      if (visual_only_ && !A.event_type(batch.type).visual) continue;
      std::vector<std::uint32_t>* list = &t.untargeted;
      if (batch.target != kNoTarget) {
        if (!last_list || batch.target != last_target) last_target = batch.target, last_list = &t.by_target[last_target];
        list = last_list;
      }
      for (std::uint32_t pos = batch.first_event; pos < batch.first_event + batch.count; ++pos) {
        t.all.push_back(pos);
        list->push_back(pos);
      }
    }
    return t;
  }

  const EventList& events_;
  bool visual_only_;
  std::unordered_map<SymbolId, TypeIndex> types_;
};

bool reaches(const EventView& e, const std::optional<std::int64_t>& actor_id) {
  return !e.has_target() || (actor_id && *actor_id == e.target());
}

[[noreturn]] void rethrow_in_frame(const FrameContext& ctx, const char* stage, std::string actor,
                                   std::string event, std::string where) {
  const std::exception_ptr cause = std::current_exception();
  try {
    throw;
  } catch (const FrameError&) {
    throw;  // already located (an inner replacement's actor)
  } catch (...) {
  }
  throw FrameError(ctx.frame, stage, std::move(actor), std::move(event), std::move(where),
                   describe_exception(cause), cause);
}

// --- η ----------------------------------------------------------------------------------------

class Evolver {
 public:
  Evolver(const EventList& events, const FrameContext& ctx, BlobJournal* journal = nullptr, unsigned threads = 1)
      : events_(events), ctx_(ctx), routing_(events, false), journal_(journal), threads_(threads) {}

  WorldString run(const WorldString& w) {
    StringBuilder out(w.alphabet_ptr());
    out.reserve(w.nodes().size() + 16, w.store().size() + 16, w.store().chars_size() + 64);
    if (w.actor_count() == 0) {
      out.append_range(w, 0, w.nodes().size());
    } else {
      if (threads_ > 1) evolve_concurrent(w);
      walk(w, 0, out, 0);
      apply_batches(w.alphabet(), out);
    }
    return out.finish();
  }

 private:
  struct Level {
    explicit Level(std::shared_ptr<const Alphabet> a) : replacement(std::move(a)) {}
    ActorState state;
    Replacement replacement;
    std::vector<std::uint32_t> scratch, scratch_other;  // merged event positions (EventRouting::for_actor)
  };
  struct BatchMember {
    std::size_t node;           // index in the output
    std::uint32_t first_event;  // the member receives events from this position of S on
  };
  /// λ of one actor of w, run on the pool before the walk: its state after its events, or the
  /// string it replaced itself with and where in S that string's actors take over.
  struct Evolved {
    explicit Evolved(std::shared_ptr<const Alphabet> a) : level(std::move(a)) {}
    std::size_t node = 0;
    Level level;
    std::optional<WorldString> replaced;
    std::uint32_t resume = 0;
    BlobJournal journal;
    std::exception_ptr error;
  };

  /// Append η(w, S[first_event:]) to `out`.
  void walk(const WorldString& w, std::uint32_t first_event, StringBuilder& out, std::size_t depth) {
    const auto nodes = w.nodes();
    std::size_t run = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (nodes[i].kind != NodeKind::Actor) continue;
      out.append_range(w, run, i);
      evolve_actor(w, i, first_event, out, depth);
      run = i + 1;
    }
    out.append_range(w, run, nodes.size());
  }

  Level& level(std::size_t depth, const std::shared_ptr<const Alphabet>& ptr) {
    while (levels_.size() <= depth) levels_.push_back(std::make_unique<Level>(ptr));
    return *levels_[depth];
  }

  std::optional<std::int64_t> id_of(const WorldString& w, std::size_t i, const SymbolInfo& info) const {
    if (info.id_attribute < 0) return std::nullopt;
    return w.node(i).value(static_cast<std::size_t>(info.id_attribute)).i;
  }

  /// The actors of the engine's own string whose behaviours may run side by side (concurrent(),
  /// not batched) and that have events: λ for each on the pool, into slots in string order.
  /// walk() then takes their results in string order, and runs the others (a Python actor, say)
  /// itself, so the string and the first error are those of the one-thread fold.
  void evolve_concurrent(const WorldString& w) {
    const auto nodes = w.nodes();
    std::vector<std::size_t> chosen;
    std::vector<std::int64_t> ids;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (nodes[i].kind != NodeKind::Actor) continue;
      const SymbolInfo& info = w.alphabet().symbol(nodes[i].symbol);
      if (!info.behavior || info.behavior->batched() || !info.behavior->concurrent()) continue;
      const std::optional<std::int64_t> id = id_of(w, i, info);
      if (!routing_.any_from(info, id, 0)) continue;
      chosen.push_back(i);
      if (id) ids.push_back(*id);
    }
    if (chosen.size() < 2) return;
    // Two actors with the same id may share what their behaviours keep per id (two actor types
    // can share a decider): such a string runs on one thread.
    std::sort(ids.begin(), ids.end());
    if (std::adjacent_find(ids.begin(), ids.end()) != ids.end()) return;
    evolved_.clear();
    evolved_.reserve(chosen.size());
    for (std::size_t i : chosen) {
      evolved_.push_back(std::make_unique<Evolved>(w.alphabet_ptr()));
      evolved_.back()->node = i;
    }
    parallel_for(chosen.size(), threads_, [&](std::size_t k) {
      Evolved& e = *evolved_[k];
      try {
        lambda(w, e.node, 0, 0, e.level, journal_ ? &e.journal : nullptr, e.replaced, e.resume);
      } catch (...) {
        e.error = std::current_exception();
      }
    });
    // Their in-place edits are undone with the frame's if it fails, reached by the walk or not
    // (each blob edited in place belongs to one actor, so the order of the records is free).
    if (journal_) {
      for (auto& e : evolved_) journal_->absorb(std::move(e->journal));
    }
  }

  /// λ for actor i of w over the events of S from `first_event` on, in `L.state`; if it replaced
  /// itself, `replaced` is the string, whose actors take the events from `resume` on. Edits in
  /// place (journaled in `journal`) when given one.
  void lambda(const WorldString& w, std::size_t i, std::uint32_t first_event, std::size_t depth, Level& L,
              BlobJournal* journal, std::optional<WorldString>& replaced, std::uint32_t& resume) {
    const SymbolInfo& info = w.alphabet().symbol(w.nodes()[i].symbol);
    std::optional<std::int64_t> id = id_of(w, i, info);
    const std::vector<std::uint32_t>* relevant = &routing_.for_actor(info, id, L.scratch);
    auto it = std::lower_bound(relevant->begin(), relevant->end(), first_event);
    ActorState& state = L.state;
    if (journal) {
      state.load_in_place(w, i, *journal);
    } else {
      state.load(w, i);
    }
    while (it != relevant->end()) {
      const EventView e = events_[*it];
      const EvolutionContext ectx{ctx_.frame, ctx_.time, derive_seed(derive_seed(ctx_.seed, ctx_.frame, depth), i, *it)};
      // A run of events of one type for a behaviour that takes them a run at a time.
      auto run_end = it + 1;
      if (info.behavior->takes_runs(e.type())) {
        while (run_end != relevant->end() && events_[*run_end].type() == e.type()) ++run_end;
      }
      try {
        if (run_end - it > 1) {
          info.behavior->evolve_run(state, events_, std::span<const std::uint32_t>(&*it, static_cast<std::size_t>(run_end - it)),
                                    ectx, L.replacement);
          if (L.replacement.replaced() || state.id() != id) {
            L.replacement.finish();
            throw Error("λ over a run of events (evolve_run) must keep the actor one actor with the same id");
          }
          it = run_end;
          continue;
        }
        info.behavior->evolve(state, e, ectx, L.replacement);
      } catch (...) {
        rethrow_in_frame(ctx_, "evolve", to_text(w.node(i)), to_text(e), "string position " + std::to_string(i));
      }
      if (L.replacement.replaced()) {
        // The actors of the returned string take the remaining events (DESIGN.md choice 1).
        replaced.emplace(L.replacement.finish());
        resume = *it + 1;
        return;
      }
      // An actor that changes its own id from now on receives the events addressed to the new one.
      if (const std::optional<std::int64_t> now = state.id(); now != id) {
        const std::uint32_t done = *it;
        id = now;
        // Merged lists go to the other scratch, since `relevant` may be the one in use.
        relevant = &routing_.for_actor(info, id, relevant == &L.scratch ? L.scratch_other : L.scratch);
        it = std::upper_bound(relevant->begin(), relevant->end(), done);
      } else {
        ++it;
      }
    }
  }

  void evolve_actor(const WorldString& w, std::size_t i, std::uint32_t first_event, StringBuilder& out,
                    std::size_t depth) {
    if (depth == 0 && next_evolved_ < evolved_.size() && evolved_[next_evolved_]->node == i) {
      Evolved& e = *evolved_[next_evolved_++];
      if (e.error) std::rethrow_exception(e.error);
      if (e.replaced) {
        walk(*e.replaced, e.resume, out, depth + 1);
      } else {
        out.actor(e.level.state);
      }
      return;
    }
    const SymbolInfo& info = w.alphabet().symbol(w.nodes()[i].symbol);
    if (!info.behavior || !routing_.any_from(info, id_of(w, i, info), first_event)) {
      out.append_node(w, i);  // no event in H reaches it: unchanged (eq. 4, last case)
      return;
    }
    if (info.behavior->batched()) {
      out.append_node(w, i);
      batches_[info.id].push_back(BatchMember{out.node_count() - 1, first_event});
      return;
    }
    // Only the actors of the engine's own string (depth 0) are edited in place: a replacement
    // string made this frame is not the engine's.
    Level& L = level(depth, w.alphabet_ptr());
    std::optional<WorldString> replaced;
    std::uint32_t resume = 0;
    lambda(w, i, first_event, depth, L, depth == 0 ? journal_ : nullptr, replaced, resume);
    if (replaced) {
      walk(*replaced, resume, out, depth + 1);
      return;
    }
    out.actor(L.state);
  }

  /// Batch λ: for each batched actor type, the events it receives in S order, each over all the
  /// members it reaches, on columns of the members' numeric attributes.
  void apply_batches(const Alphabet& A, StringBuilder& out) {
    for (auto& [symbol, members] : batches_) {
      const SymbolInfo& info = A.symbol(symbol);
      const auto& relevant = routing_.for_type(info);
      const std::size_t nattr = info.schema.params.size();
      ActorBatch all;
      all.symbol = symbol;
      all.count = members.size();
      all.ints.resize(nattr);
      all.reals.resize(nattr);
      all.bools.resize(nattr);
      for (std::size_t j = 0; j < nattr; ++j) {
        switch (info.schema.params[j].kind) {
          case ValueKind::Int: all.ints[j] = std::make_shared<std::vector<std::int64_t>>(members.size()); break;
          case ValueKind::Real: all.reals[j] = std::make_shared<std::vector<double>>(members.size()); break;
          case ValueKind::Bool: all.bools[j] = std::make_shared<std::vector<std::uint8_t>>(members.size()); break;
          default: break;
        }
      }
      for (std::size_t m = 0; m < members.size(); ++m) {
        for (std::size_t j = 0; j < nattr; ++j) {
          const Value& v = out.value(members[m].node, j);
          if (all.ints[j]) (*all.ints[j])[m] = v.i;
          if (all.reals[j]) (*all.reals[j])[m] = v.r;
          if (all.bools[j]) (*all.bools[j])[m] = v.b;
        }
      }
      const int id_attr = info.id_attribute;
      for (std::uint32_t idx : relevant) {
        const EventView e = events_[idx];
        std::vector<std::size_t> rows;
        for (std::size_t m = 0; m < members.size(); ++m) {
          if (members[m].first_event > idx) continue;
          if (e.has_target() && (id_attr < 0 || (*all.ints[static_cast<std::size_t>(id_attr)])[m] != e.target())) continue;
          rows.push_back(m);
        }
        if (rows.empty()) continue;
        const EvolutionContext ectx{ctx_.frame, ctx_.time, derive_seed(derive_seed(ctx_.seed, ctx_.frame, 1u << 20), symbol, idx)};
        const std::string where = std::to_string(rows.size()) + " actors in a batch";
        try {
          if (rows.size() == members.size()) {
            info.behavior->evolve_batch(all, e, ectx);
          } else {
            ActorBatch sub = gather(all, rows);
            info.behavior->evolve_batch(sub, e, ectx);
            scatter(sub, rows, all);
          }
          check_finite(info, all);
        } catch (...) {
          rethrow_in_frame(ctx_, "evolve", info.name, to_text(e), where);
        }
      }
      for (std::size_t m = 0; m < members.size(); ++m) {
        for (std::size_t j = 0; j < nattr; ++j) {
          Value& v = out.value(members[m].node, j);
          if (all.ints[j]) v.i = (*all.ints[j])[m];
          if (all.reals[j]) v.r = (*all.reals[j])[m];
          if (all.bools[j]) v.b = (*all.bools[j])[m] != 0;
        }
      }
    }
  }

  static ActorBatch gather(const ActorBatch& all, const std::vector<std::size_t>& rows) {
    ActorBatch sub;
    sub.symbol = all.symbol;
    sub.count = rows.size();
    const std::size_t n = all.ints.size();
    sub.ints.resize(n);
    sub.reals.resize(n);
    sub.bools.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      auto pick = [&](const auto& col, auto& dst) {
        if (!col) return;
        dst = std::make_shared<typename std::decay_t<decltype(*col)>>(rows.size());
        for (std::size_t r = 0; r < rows.size(); ++r) (*dst)[r] = (*col)[rows[r]];
      };
      pick(all.ints[j], sub.ints[j]);
      pick(all.reals[j], sub.reals[j]);
      pick(all.bools[j], sub.bools[j]);
    }
    return sub;
  }

  static void scatter(const ActorBatch& sub, const std::vector<std::size_t>& rows, ActorBatch& all) {
    for (std::size_t j = 0; j < all.ints.size(); ++j) {
      auto put = [&](const auto& src, auto& col) {
        if (!col) return;
        for (std::size_t r = 0; r < rows.size(); ++r) (*col)[rows[r]] = (*src)[r];
      };
      put(sub.ints[j], all.ints[j]);
      put(sub.reals[j], all.reals[j]);
      put(sub.bools[j], all.bools[j]);
    }
  }

  static void check_finite(const SymbolInfo& info, const ActorBatch& batch) {
    for (std::size_t j = 0; j < batch.reals.size(); ++j) {
      if (!batch.reals[j]) continue;
      for (double x : *batch.reals[j]) {
        if (!std::isfinite(x)) {
          throw SchemaError(info.name + "." + info.schema.params[j].name, "batch λ wrote a non-finite real");
        }
      }
    }
  }

  const EventList& events_;
  const FrameContext& ctx_;
  EventRouting routing_;
  BlobJournal* journal_;
  unsigned threads_;
  std::vector<std::unique_ptr<Level>> levels_;
  std::vector<std::unique_ptr<Evolved>> evolved_;  // in string order
  std::size_t next_evolved_ = 0;
  std::map<SymbolId, std::vector<BatchMember>> batches_;
};

}  // namespace

WorldString evolve(const WorldString& w, const EventList& events, const FrameContext& ctx) {
  if (events.alphabet_ptr() != w.alphabet_ptr()) throw Error("evolve: events and string use different alphabets");
  Evolver evolver(events, ctx);
  return evolver.run(w);
}

WorldString evolve_in_place(const WorldString& w, const EventList& events, const FrameContext& ctx,
                            BlobJournal& journal, unsigned threads) {
  if (events.alphabet_ptr() != w.alphabet_ptr()) throw Error("evolve: events and string use different alphabets");
  Evolver evolver(events, ctx, &journal, threads);
  return evolver.run(w);
}

// --- π ----------------------------------------------------------------------------------------

WorldString visualize(const WorldString& w, const EventList& events, const FrameContext& ctx) {
  if (events.alphabet_ptr() != w.alphabet_ptr()) throw Error("visualize: events and string use different alphabets");
  StringBuilder out(w.alphabet_ptr());
  out.reserve(w.nodes().size(), w.store().size(), w.store().chars_size());
  EventRouting routing(events, true);
  ActorState state;
  const auto nodes = w.nodes();
  std::size_t run = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].kind != NodeKind::Actor) continue;
    out.append_range(w, run, i);
    run = i + 1;
    const SymbolInfo& info = w.alphabet().symbol(nodes[i].symbol);
    if (!info.behavior) continue;  // θ = ε
    const auto& relevant = routing.for_type(info);
    if (relevant.empty()) continue;
    state.load(w, i);
    const auto id = state.id();
    for (std::uint32_t idx : relevant) {
      const EventView e = events[idx];
      if (!reaches(e, id)) continue;
      const EvolutionContext ectx{ctx.frame, ctx.time, derive_seed(derive_seed(ctx.seed, ctx.frame, 2u << 20), i, idx)};
      const std::size_t actors_before = out.actor_count();
      const std::size_t depth_before = out.depth();
      try {
        info.behavior->visualize(state, e, ectx, out);
        if (out.actor_count() != actors_before) {
          throw Error("θ must return primitives and transformations only (a string of L(M')), but it returned an actor");
        }
        if (out.depth() != depth_before) throw Error("θ left a scope open");
      } catch (...) {
        rethrow_in_frame(ctx, "visualize", to_text(w.node(i)), to_text(e), "string position " + std::to_string(i));
      }
    }
  }
  out.append_range(w, run, nodes.size());
  return out.finish();
}

// --- φ ----------------------------------------------------------------------------------------

void display(const WorldString& v, Backend& backend) {
  const auto nodes = v.nodes();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const NodeView node(v, i);
    switch (nodes[i].kind) {
      case NodeKind::Primitive: backend.primitive(node); break;
      case NodeKind::Transformation: backend.open(node); break;
      case NodeKind::Close: backend.close(node); break;
      case NodeKind::Actor:
        throw Error("display: '" + to_text(node) + "' at position " + std::to_string(i) +
                    " is an actor; only π's output (primitives and transformations) can be displayed");
    }
  }
}

}  // namespace vwg
