// vwg._core.Engine: the system algorithm, run with the GIL released between Python callbacks.
#include <algorithm>
#include <chrono>
#include <string>

#include "common.hpp"
#include "src/parallel.hpp"
#include "vwg/robot/platform_sync.hpp"

namespace vwg::bindings {

namespace {

/// What an observer sees of a completed frame; valid only during the observer call.
struct PyFrameRecord {
  std::uint64_t frame = 0;
  double time = 0.0;
  const WorldString* after = nullptr;
  const EventList* events = nullptr;
  void check() const {
    if (!after) throw SchemaError("FrameRecord", "is only available during the observer call");
  }
};

/// The engine and the Python objects it calls (kept alive as long as it is).
struct PyEngine {
  std::unique_ptr<Engine> engine;
  py::list keep_alive;
};

std::string stop_name(StopReason r) {
  switch (r) {
    case StopReason::Empty: return "empty";
    case StopReason::FrameLimit: return "frames";
    case StopReason::Requested: return "stopped";
    case StopReason::Done: return "done";
  }
  return "?";
}

}  // namespace

/// A stop condition written in Python: done(w, frame) runs the Python method (taking the GIL).
class PyStopCondition final : public StopCondition {
 public:
  bool done(const WorldString& w, std::uint64_t frame) override {
    PYBIND11_OVERRIDE_PURE(bool, StopCondition, done, w, frame);
  }
};

void init_engine(py::module_& m) {
  m.def("default_threads", &default_threads, "The machine's cores: the threads a frame uses unless told (threads=0).");
  py::class_<StopCondition, PyStopCondition, std::shared_ptr<StopCondition>>(m, "StopCondition", R"doc(
When a run has done its job: run() returns 'done' after a frame for which done(w, frame) is true.
C++ conditions (vwg.ArrivalCondition) cost no call into Python; a Python subclass may define
done(self, w, frame).)doc")
      .def(py::init<>())
      .def("done", &StopCondition::done, py::arg("w"), py::arg("frame"));

  py::class_<PyFrameRecord, std::shared_ptr<PyFrameRecord>>(m, "FrameRecord", "A completed frame as observers see it (valid during the call): its events and the string they made. The string at its start is the previous frame's ``after``.")
      .def_readonly("frame", &PyFrameRecord::frame)
      .def_readonly("time", &PyFrameRecord::time)
      .def_property_readonly("after", [](const PyFrameRecord& r) { r.check(); return WorldString(*r.after); },
                             "w after the frame (a copy).")
      .def_property_readonly("after_text", [](const PyFrameRecord& r) { r.check(); return to_text(*r.after); })
      .def_property_readonly("events", [](const PyFrameRecord& r) {
        r.check();
        py::list out;
        for (std::size_t i = 0; i < r.events->size(); ++i) out.append(event_to_python((*r.events)[i]));
        return out;
      }, "S: the events of the frame, in priority order.")
      .def_property_readonly("event_texts", [](const PyFrameRecord& r) {
        r.check();
        py::list out;
        for (std::size_t i = 0; i < r.events->size(); ++i) out.append(to_text((*r.events)[i]));
        return out;
      })
      .def("event_runs", [](const PyFrameRecord& r, std::size_t min_run) {
        r.check();
        return event_runs_to_python(*r.events, min_run);
      }, py::arg("min_run"), R"doc(
S as a recorder stores it: in order, each run of at least ``min_run`` consecutive events of one
type whose fields are all numbers or bools (all with a target, or none) as a tuple ``(type, n,
targets, fields)``: ``n`` the number of events, ``targets`` an int64 array or None, ``fields`` a list of ``(name, kind,
column)`` in the type's order, kind "f", "i" or "b" for float64, int64 and bool columns. Every
other event comes as its text. No Python object is made per event of a run.)doc")
      .def_property_readonly("blobs", [](const PyFrameRecord& r) {
        r.check();
        py::dict out;
        auto put = [&](const auto& blob) { out[py::str(blob_name(*blob).substr(1))] = blob_to_python(blob); };
        for_each_blob(*r.after, put);
        const EventList& events = *r.events;
        for (std::size_t b = 0; b < events.batch_count(); ++b) {
          const EventList::Batch& batch = events.batch(b);
          const auto& params = events.alphabet().event_type(batch.type).fields.params;
          // Most events (a scan's beams) hold no blob: their batch is skipped whole.
          if (batch.by_columns || std::none_of(params.begin(), params.end(), [](const ParamSpec& p) { return p.kind == ValueKind::Blob; })) continue;
          for (std::uint32_t i = batch.first_event; i < batch.first_event + batch.count; ++i) {
            const EventView e = events[i];
            for (std::size_t k = 0; k < e.field_count(); ++k)
              if (e.value(k).kind == ValueKind::Blob) put(e.store().blob(e.value(k)));
          }
        }
        return out;
      }, "The blobs referred to by the strings and events of the frame, by name.");

  py::class_<EngineState>(m, "EngineState", R"doc(
What a run keeps in its engine, between frames (Engine.save_state): the frame number, the string
w as text with the blobs it names (by name, without '@'), each generator's state and each actor
type's behaviour's state, as bytes. vwg.resume writes and reads them in a state file.)doc")
      .def(py::init<>())
      .def_readwrite("frame", &EngineState::frame)
      .def_readwrite("string", &EngineState::string, "The text form of w.")
      .def_property("blobs", [](const EngineState& s) {
        py::dict out;
        for (const auto& [name, blob] : s.blobs) out[py::str(name)] = std::const_pointer_cast<Blob>(blob);
        return out;
      }, [](EngineState& s, py::dict blobs) {
        BlobTable table;
        for (auto item : blobs) {
          const std::string key = py::str(item.first);
          table.emplace(key, blob_from_python(item.second, "blobs['" + key + "']"));
        }
        s.blobs = std::move(table);
      }, "The blobs the text names, by name.")
      .def_property("generators", [](const EngineState& s) {
        std::vector<py::bytes> out;
        for (const std::string& b : s.generators) out.emplace_back(b);
        return out;
      }, [](EngineState& s, const std::vector<py::bytes>& v) {
        s.generators.clear();
        for (const py::bytes& b : v) s.generators.emplace_back(b);
      }, "Each generator's saved state, in priority order.")
      .def_property("actors", [](const EngineState& s) {
        std::vector<std::pair<std::string, py::bytes>> out;
        for (const auto& [name, b] : s.actors) out.emplace_back(name, py::bytes(b));
        return out;
      }, [](EngineState& s, const std::vector<std::pair<std::string, py::bytes>>& v) {
        s.actors.clear();
        for (const auto& [name, b] : v) s.actors.emplace_back(name, std::string(b));
      },
      "(actor type, its behaviour's saved state) for each actor type that has a behaviour.");

  py::class_<PyEngine>(m, "Engine", R"doc(
The system algorithm (paper §II.D). Each frame: S = the generators' events in priority order,
w_next = η(w, S), v = π(w, Z), φ(v) on the backend, w = w_next. A frame is all or nothing: if λ, θ,
a generator or the backend raises, the engine keeps the last complete frame and raises
vwg.FrameError naming the frame, the stage, the actor and the event.)doc")
      .def(py::init([](const WorldString& initial, py::list generators, py::object backend, double dt, std::uint64_t seed,
                       std::uint64_t first_frame, std::uint64_t max_symbols, std::int64_t threads) {
             if (threads < 0 || threads > static_cast<std::int64_t>(kMaxThreads)) {
               throw SchemaError("threads", "expected 0 (the machine's cores) to " + std::to_string(kMaxThreads) +
                                                " threads, got " + std::to_string(threads));
             }
             PyEngine e;
             std::vector<std::shared_ptr<Generator>> gens;
             std::size_t i = 0;
             for (auto g : generators) {
               if (!py::isinstance<Generator>(g)) {
                 throw SchemaError("generators[" + std::to_string(i) + "]", "expected a vwg.Generator, got " +
                                                                            std::string(py::str(py::type::handle_of(g).attr("__name__"))));
               }
               gens.push_back(g.cast<std::shared_ptr<Generator>>());
               e.keep_alive.append(g);
               ++i;
             }
             std::shared_ptr<Backend> b;
             if (!backend.is_none()) {
               if (!py::isinstance<Backend>(backend)) throw SchemaError("backend", "expected a vwg.Backend or None");
               b = backend.cast<std::shared_ptr<Backend>>();
               e.keep_alive.append(backend);
             }
             e.engine = std::make_unique<Engine>(initial, std::move(gens), std::move(b), EngineOptions{dt, seed, first_frame, max_symbols, static_cast<unsigned>(threads)});
             return e;
           }),
           py::arg("initial"), py::arg("generators") = py::list(), py::arg("backend") = py::none(), py::arg("dt") = EngineOptions{}.dt,
           py::arg("seed") = EngineOptions{}.seed, py::arg("first_frame") = EngineOptions{}.first_frame,
           py::arg("max_symbols") = EngineOptions{}.max_symbols, py::arg("threads") = EngineOptions{}.threads)
      .def("step", [](PyEngine& e) {
        py::gil_scoped_release release;
        return e.engine->step();
      }, "Run one frame; False (and nothing done) if w = ε.")
      .def("step_with", [](PyEngine& e, py::object events) {
        EventList list = events_from_python(e.engine->alphabet_ptr(), events);
        py::gil_scoped_release release;
        return e.engine->step_with(list);
      }, py::arg("events"), "Run one frame with these events instead of the generators' (replay).")
      .def("run", [](PyEngine& e, std::uint64_t frames) {
        // Frames run in chunks with the GIL released; between chunks Ctrl-C is honoured. Chunks
        // grow while they take under 20 ms, so short frames do not pay for the switches.
        std::uint64_t done = 0, chunk = 1;
        while (done < frames) {
          const std::uint64_t n = std::min(chunk, frames - done);
          const auto t0 = std::chrono::steady_clock::now();
          StopReason r;
          const std::uint64_t before = e.engine->frame();
          {
            py::gil_scoped_release release;
            r = e.engine->run(n);
          }
          done += e.engine->frame() - before;
          if (PyErr_CheckSignals() != 0) throw py::error_already_set();
          if (r != StopReason::FrameLimit) return stop_name(r);
          if (std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(20)) chunk *= 2;
        }
        return stop_name(StopReason::FrameLimit);
      }, py::arg("frames"),
      "Run until w = ε ('empty'), `frames` more frames ran ('frames'), request_stop() ('stopped'), or the stop "
      "condition holds ('done').")
      .def("request_stop", [](PyEngine& e) { e.engine->request_stop(); }, "Stop run() after the current frame.")
      .def("keep_robots_in_step", [](PyEngine& e, std::shared_ptr<platform::RobotPlatform> platform, double radius,
                                     const std::string& actor) {
        e.keep_alive.append(py::cast(platform));
        robot::PlatformSync sync(*e.engine->alphabet_ptr(), platform, radius, {}, actor);
        py::gil_scoped_release release;  // waits for a frame under way, which may need the GIL
        e.engine->add_observer(std::move(sync));
      }, py::arg("platform"), py::arg("radius") = platform::kDefaultRobotRadius, py::arg("actor") = "ARobot",
      "After each frame, give the platform a robot (of `radius`, at its believed pose) for each robot actor a λ "
      "spawned, and take it away from those that left the string (in C++, no call into Python).")
      .def("stop_when", [](PyEngine& e, py::object condition) {
        std::shared_ptr<StopCondition> c;
        if (!condition.is_none()) {
          c = condition.cast<std::shared_ptr<StopCondition>>();
          e.keep_alive.append(condition);
        }
        py::gil_scoped_release release;  // waits for a frame under way, which may need the GIL
        e.engine->stop_when(std::move(c));
      }, py::arg("condition"), "run() returns 'done' after a frame that leaves condition (a vwg.StopCondition) true.")
      .def_property_readonly("string", [](const PyEngine& e) {
        py::gil_scoped_release release;  // a frame under way may need the GIL to end
        return e.engine->string_copy();
      }, "The current string w (a copy, taken between frames: safe from any thread).")
      .def("set_string", [](PyEngine& e, const WorldString& w) { e.engine->set_string(w); }, py::arg("w"))
      .def("save_state", [](PyEngine& e, bool generators) {
        py::gil_scoped_release release;  // the generators' and behaviours' own methods take it when they are Python's
        return e.engine->save_state(generators);
      }, py::arg("generators") = true,
      "The run's state between frames (vwg.EngineState); the platform keeps its own. generators=False leaves "
      "the generators' states out (a real robot's run: its string and its robots' maps and planners are kept).")
      .def("load_state", [](PyEngine& e, const EngineState& state) {
        py::gil_scoped_release release;
        e.engine->load_state(state);
      }, py::arg("state"), "Go on from a saved state (an engine made as the saved one was).")
      .def_property_readonly("frame", [](const PyEngine& e) { return e.engine->frame(); }, "Frames completed so far (t).")
      .def_property_readonly("time", [](const PyEngine& e) { return e.engine->time(); }, "Simulated seconds: frame * dt.")
      .def_property_readonly("dt", [](const PyEngine& e) { return e.engine->options().dt; })
      .def_property_readonly("seed", [](const PyEngine& e) { return e.engine->options().seed; })
      .def_property_readonly("threads", [](const PyEngine& e) { return e.engine->options().threads; },
                             "Threads a frame uses for its robots' lasers and λ (0 given: the machine's cores).")
      .def_property_readonly("last_events", [](const PyEngine& e) {
        const EventList events = [&] {
          py::gil_scoped_release release;
          return e.engine->last_events_copy();
        }();
        py::list out;
        for (std::size_t i = 0; i < events.size(); ++i) out.append(event_to_python(events[i]));
        return out;
      }, "The events S of the last completed frame (taken between frames: safe from any thread).")
      .def_property_readonly("generators", [](const PyEngine& e) {
        py::list out;
        for (const auto& g : e.engine->generators()) out.append(py::cast(g));
        return out;
      }, "The generators, in priority order.")
      .def_property_readonly("backend", [](const PyEngine& e) { return e.engine->backend(); })
      .def("collect_events", [](PyEngine& e) {
        EventList events = [&] {
          py::gil_scoped_release release;
          return e.engine->collect_events();
        }();
        py::list out;
        for (std::size_t i = 0; i < events.size(); ++i) out.append(event_to_python(events[i]));
        return out;
      }, "Ask the generators for the current frame's events without running the frame.")
      .def("add_observer", [](PyEngine& e, py::function fn) {
        e.keep_alive.append(fn);
        // The observer is handed over with the GIL released (and dropped there if refused): its
        // Python callable is let go of under the GIL by whichever copy is last.
        std::shared_ptr<py::function> callable(new py::function(std::move(fn)), [](py::function* f) {
          py::gil_scoped_acquire gil;
          delete f;
        });
        Engine::Observer observer = [callable](const FrameRecord& r) {
          py::gil_scoped_acquire gil;
          auto record = std::make_shared<PyFrameRecord>(PyFrameRecord{r.frame, r.time, &r.after, &r.events});
          py::object arg = py::cast(record);
          try {
            (*callable)(arg);
          } catch (...) {
            *record = PyFrameRecord{};
            throw;
          }
          *record = PyFrameRecord{};  // the views end with the call
        };
        py::gil_scoped_release release;  // waits for a frame under way, which may need the GIL
        e.engine->add_observer(std::move(observer));
      }, py::arg("observer"), "Call observer(record: FrameRecord) after every completed frame (added between frames: safe from any thread).");
}

}  // namespace vwg::bindings
