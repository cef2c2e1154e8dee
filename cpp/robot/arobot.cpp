#include "vwg/robot/arobot.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "src/unique_number.hpp"
#include "vwg/error.hpp"
#include "vwg/geometry/directions.hpp"
#include "vwg/geometry/pose.hpp"
#include "vwg/text.hpp"

namespace vwg::robot {

namespace {

ParamSpec spec(const char* name, ValueKind kind, std::optional<Datum> def = std::nullopt) {
  return ParamSpec{name, kind, std::move(def)};
}

std::shared_ptr<const Blob> empty_path() { return std::make_shared<const Blob>(DType::Float64, std::vector<std::int64_t>{0, 2}); }

std::shared_ptr<const Blob> no_neighbours() {
  return std::make_shared<const Blob>(DType::Float64, std::vector<std::int64_t>{0, 5});
}

std::shared_ptr<const Blob> path_blob(const std::vector<double>& xy) {
  const auto n = static_cast<std::int64_t>(xy.size() / 2);
  return std::make_shared<const Blob>(DType::Float64, std::vector<std::int64_t>{n, 2}, xy.data(), xy.size() * sizeof(double));
}

}  // namespace

Schema arobot_attributes() {
  Schema s;
  s.params = {
      spec("id", ValueKind::Int, Datum(1)),
      spec("grid", ValueKind::Blob),
      spec("row", ValueKind::Int, Datum(0)),
      spec("column", ValueKind::Int, Datum(0)),
      spec("angle", ValueKind::Real, Datum(0.0)),
      spec("objective", ValueKind::Int, Datum(-1)),
      // The action (eq. 11): Rotate<turn>(Move<move>(Robot<id>)) while `acting`, held as numbers so
      // θ builds it from symbol ids, with no text made and parsed in the frame.
      spec("acting", ValueKind::Bool, Datum(false)),
      spec("turn", ValueKind::Real, Datum(0.0)),
      spec("move", ValueKind::Real, Datum(0.0)),
      spec("x", ValueKind::Real, Datum(0.0)),
      spec("y", ValueKind::Real, Datum(0.0)),
      spec("path", ValueKind::Blob, Datum(empty_path())),
      spec("sent", ValueKind::Int, Datum(0)),
      spec("acked", ValueKind::Int, Datum(0)),
      spec("busy", ValueKind::Bool, Datum(false)),
      spec("reached", ValueKind::Bool, Datum(false)),
      spec("replans", ValueKind::Int, Datum(0)),
      spec("collisions", ValueKind::Int, Datum(0)),
      spec("status", ValueKind::Text, Datum("idle")),
      spec("wait", ValueKind::Int, Datum(0)),
      // Reciprocal avoidance: whether it avoids, the neighbours of frame `sensed` (N×5: x, y, vx, vy, radius
      // in its own frame), and the velocity it was last given (shown as Velocity<speed, turn_rate>).
      spec("avoid", ValueKind::Bool, Datum(false)),
      spec("neighbours", ValueKind::Blob, Datum(no_neighbours())),
      spec("sensed", ValueKind::Int, Datum(-1)),
      spec("speed", ValueKind::Real, Datum(0.0)),
      spec("turn_rate", ValueKind::Real, Datum(0.0)),
  };
  return s;
}

std::vector<std::string> arobot_events() {
  return {"eLaser", "eCamera", "eDecide", "eExecute", "eObjective", "eOdometry", "eCollision", "eNeighbour"};
}

std::vector<std::pair<std::string, Schema>> arobot_event_types() {
  auto fields = [](std::initializer_list<ParamSpec> p) { return Schema{p, false}; };
  return {
      {"eLaser", fields({spec("dist", ValueKind::Real, Datum(0.0)), spec("angle", ValueKind::Real, Datum(0.0))})},
      {"eCamera", fields({spec("marker", ValueKind::Int, Datum(0)), spec("dist", ValueKind::Real, Datum(0.0)),
                          spec("angle", ValueKind::Real, Datum(0.0))})},
      {"eDecide", fields({})},
      {"eExecute", fields({})},
      {"eObjective", fields({spec("marker", ValueKind::Int, Datum(-1))})},
      {"eOdometry", fields({spec("x", ValueKind::Real, Datum(0.0)), spec("y", ValueKind::Real, Datum(0.0)),
                            spec("angle", ValueKind::Real, Datum(0.0)), spec("busy", ValueKind::Bool, Datum(false)),
                            spec("commands", ValueKind::Int, Datum(0))})},
      {"eCollision", fields({spec("other", ValueKind::Int, Datum(0))})},
      {"eNeighbour", fields({spec("x", ValueKind::Real, Datum(0.0)), spec("y", ValueKind::Real, Datum(0.0)),
                             spec("vx", ValueKind::Real, Datum(0.0)), spec("vy", ValueKind::Real, Datum(0.0)),
                             spec("radius", ValueKind::Real, Datum(0.0))})},
  };
}

struct ARobotSerials;

void check_settings(const ARobotConfig& c, const std::string& owner) {
  const std::pair<const char*, double> positive[] = {{"radius", c.radius}, {"goal_tolerance", c.goal_tolerance},
                                                     {"step_length", c.step_length},
                                                     {"marker_goal_distance", c.marker_goal_distance}};
  for (const auto& [name, v] : positive) {
    if (!std::isfinite(v) || v <= 0) throw SchemaError(owner + "." + name, "expected a finite number > 0, got " + format_real(v));
  }
  if (!std::isfinite(c.margin) || c.margin < 0) throw SchemaError(owner + ".margin", "expected a finite number >= 0, got " + format_real(c.margin));
  if (c.retry_frames < 0) throw SchemaError(owner + ".retry_frames", "expected a number of frames >= 0, got " + std::to_string(c.retry_frames));
}

ARobot::ARobot(const Alphabet& alphabet, ARobotConfig config, std::shared_ptr<Decider> decider)
    : config_(std::move(config)), decider_(std::move(decider)), serial_(next_unique_number<ARobotSerials>()) {
  if (!decider_) throw SchemaError("ARobot", "needs a decider (random, A*, OMPL or one written in Python)");
  if (config_.map.width <= 0 || config_.map.height <= 0 || !(config_.map.resolution > 0)) {
    throw SchemaError("ARobot.map", "expected the world map's geometry");
  }
  check_settings(config_, "ARobot");
  check_settings(config_.avoidance, "ARobot.avoidance");
  ev_ = Events{alphabet.event_type_id("eLaser"),   alphabet.event_type_id("eCamera"),
               alphabet.event_type_id("eDecide"),  alphabet.event_type_id("eExecute"),
               alphabet.event_type_id("eObjective"), alphabet.event_type_id("eOdometry"),
               alphabet.event_type_id("eCollision"), alphabet.event_type_id("eNeighbour")};
  sym_ = Symbols{alphabet.symbol_id("Robot", SymbolKind::Primitive), alphabet.symbol_id("Move", SymbolKind::Transformation),
                 alphabet.symbol_id("Rotate", SymbolKind::Transformation), std::nullopt, std::nullopt, std::nullopt};
  // Path<robot, points> and Status<robot, text>: what a view shows of the robot comes through π and
  // φ like its action, when the alphabet declares them (MOTION_SYMBOLS does).
  if (const auto p = alphabet.find_symbol("Path"); p && alphabet.symbol(*p).kind == SymbolKind::Primitive) sym_.path = p;
  if (const auto t = alphabet.find_symbol("Status"); t && alphabet.symbol(*t).kind == SymbolKind::Primitive) sym_.status = t;
  if (const auto v = alphabet.find_symbol("Velocity"); v && alphabet.symbol(*v).kind == SymbolKind::Transformation) {
    sym_.velocity = v;
  }
}

ObstacleBits& ARobot::bits_of(std::int64_t robot) {
  // A robot's laser events come one after another: the last entry this thread used is remembered,
  // so the guard is taken about once per robot per frame, not once per beam. The ARobot's serial
  // (never reused) keeps an entry of one that is gone from being taken for another's.
  thread_local struct {
    std::uint64_t owner = 0;
    std::int64_t robot = 0;
    ObstacleBits* bits = nullptr;
  } last;
  if (last.owner == serial_ && last.robot == robot) return *last.bits;
  const std::lock_guard<std::mutex> lock(bits_mutex_);
  last = {serial_, robot, &bits_.try_emplace(robot, robot).first->second};
  return *last.bits;
}

void ARobot::evolve(ActorState& self, const EventView& e, const EvolutionContext& ctx, Replacement&) {
  const geometry::MapGeometry& g = config_.map;
  const EventTypeId type = e.type();
  if (type == ev_.laser) {
    const double a = self.get_real(kAngle) + e.number(1);
    double cos_a = 0.0, sin_a = 0.0;
    geometry::beam_directions({&a, 1}, "avx2", {&cos_a, 1}, {&sin_a, 1});
    ScanBeam b = beam(self, e.number(0), cos_a, sin_a);
    unmark_neighbours(self, ctx, std::span<ScanBeam>(&b, 1));
    edit_map(self, [&](MapEdit& map, ObstacleBits& bits) {
      sense_scan(map, g, bits, self.get_real(kX), self.get_real(kY), std::span<const ScanBeam>(&b, 1), config_.carve_free_space);
    });
  } else if (type == ev_.camera) {
    const double a = self.get_real(kAngle) + e.number(2);
    const double d = e.number(1) + 0.5 * g.resolution;
    edit_map(self, [&](MapEdit& map, ObstacleBits& bits) {
      mark_marker(map, g, self.get_real(kX) + d * std::cos(a), self.get_real(kY) + d * std::sin(a),
                  static_cast<int>(e.value(0).i), &bits);
    });
  } else if (type == ev_.objective) {
    const std::int64_t marker = e.value(0).i;
    // A new task, or (marker < 0) the supervisor interrupting the current one: the robot stops where it is.
    const bool interrupted = marker < 0 && self.get_int(kObjective) >= 0 && !self.get_bool(kReached);
    self.set_int(kObjective, marker);
    self.set_bool(kReached, false);
    self.set_blob(kPath, empty_path());
    self.set_int(kWait, 0);
    self.set_text(kStatus, marker >= 0 ? "to marker " + std::to_string(marker) : interrupted ? "interrupted" : "idle");
  } else if (type == ev_.odometry) {
    const double x = e.number(0), y = e.number(1);
    self.set_real(kX, x);
    self.set_real(kY, y);
    self.set_real(kAngle, e.number(2));
    self.set_bool(kBusy, e.value(3).b);
    self.set_int(kAcked, e.value(4).i);
    int row, col;
    if (g.cell_of(x, y, row, col)) {
      self.set_int(kRow, row);
      self.set_int(kColumn, col);
    }
  } else if (type == ev_.collision) {
    self.set_int(kCollisions, self.get_int(kCollisions) + 1);
    // A wall it did not see (too near for the Kinect, beside the camera): like a bumper, mark the
    // cell just ahead, so the next plan goes round it. Robots move on: they are not marked.
    if (e.value(0).i == 0) {
      const double a = self.get_real(kAngle), d = config_.radius + 0.5 * g.resolution;
      edit_map(self, [&](MapEdit& map, ObstacleBits& bits) {
        mark_obstacle(map, g, self.get_real(kX) + d * std::cos(a), self.get_real(kY) + d * std::sin(a), &bits);
      });
    }
  } else if (type == ev_.neighbour) {
    // The first of a frame replaces the last frame's; the others of the frame join it.
    std::vector<double> rows;
    if (self.get_int(kSensed) == static_cast<std::int64_t>(ctx.frame)) {
      const auto old = self.get_blob(kNeighbours)->view<double>();
      rows.assign(old.begin(), old.end());
    }
    for (std::size_t i = 0; i < 5; ++i) rows.push_back(e.number(i));
    const auto n = static_cast<std::int64_t>(rows.size() / 5);
    self.set_blob(kNeighbours, std::make_shared<const Blob>(DType::Float64, std::vector<std::int64_t>{n, 5}, rows.data(),
                                                            rows.size() * sizeof(double)));
    self.set_int(kSensed, static_cast<std::int64_t>(ctx.frame));
  } else if (type == ev_.decide) {
    if (self.get_bool(kAvoid)) {
      decide_avoiding(self, ctx);
    } else {
      decide(self, ctx);
    }
  }
  // eExecute: nothing changes; θ shows the action (DESIGN.md choice 3).
}

void ARobot::neighbours_in_world(const ActorState& self, const EvolutionContext& ctx,
                                 std::vector<orca::Neighbour>& out) const {
  out.clear();
  if (self.get_int(kSensed) != static_cast<std::int64_t>(ctx.frame)) return;  // none seen this frame
  const auto rows = self.get_blob(kNeighbours)->view<double>();
  const double x = self.get_real(kX), y = self.get_real(kY), theta = self.get_real(kAngle);
  const double c = std::cos(theta), s = std::sin(theta);
  for (std::size_t i = 0; i + 5 <= rows.size(); i += 5) {
    const double* r = &rows[i];
    out.push_back(orca::Neighbour{{x + c * r[0] - s * r[1], y + s * r[0] + c * r[1]},
                                  {c * r[2] - s * r[3], s * r[2] + c * r[3]}, r[4], 0.5});
  }
}

void ARobot::unmark_neighbours(const ActorState& self, const EvolutionContext& ctx, std::span<ScanBeam> scan) const {
  if (!self.get_bool(kAvoid)) return;
  thread_local std::vector<orca::Neighbour> neighbours;
  neighbours_in_world(self, ctx, neighbours);
  // A return within two cells of a tracked disc is off that neighbour: the tracker's disc is fitted to an arc and
  // moved on from the last frame's scan. Measured on bench_avoidance's crowd (100 robots, 600,000 beams), the
  // returns off neighbours end within one cell of their discs for 91 %, two cells 99 %; beyond, as many returns
  // end as off walls near robots. With one cell, the rest were marked and blocked plans: 15 searches a frame
  // against 9.7 with two.
  const double slack = 2 * config_.map.resolution;
  for (ScanBeam& b : scan) {
    for (const orca::Neighbour& n : neighbours) {
      // Squared distances: every beam against every neighbour, and std::hypot was 2 % of an avoiding crowd's frame.
      const double dx = b.end_x - n.position.x, dy = b.end_y - n.position.y, reach = n.radius + slack;
      if (dx * dx + dy * dy <= reach * reach) {
        // A return off a robot or a person: the beam still clears the way to it, and marks nothing.
        b.mark_x = b.mark_y = std::numeric_limits<double>::quiet_NaN();
        break;
      }
    }
  }
}

ScanBeam ARobot::beam(const ActorState& self, double dist, double cos_a, double sin_a) const {
  const double hx = self.get_real(kX) + dist * cos_a, hy = self.get_real(kY) + dist * sin_a;
  // Half a cell beyond the surface, so the cell marked is the one the beam stopped in.
  const double half = 0.5 * config_.map.resolution;
  return ScanBeam{hx, hy, hx + half * cos_a, hy + half * sin_a};
}

void ARobot::evolve_run(ActorState& self, const EventList& events, std::span<const std::uint32_t> at, const EvolutionContext& ctx,
                        Replacement& out) {
  if (events[at.front()].type() != ev_.laser) {
    ActorBehavior::evolve_run(self, events, at, ctx, out);
    return;
  }
  thread_local struct {
    std::vector<double> turned, cos_a, sin_a;
    std::vector<ScanBeam> scan;
  } scratch;
  auto& [turned, cos_a, sin_a, scan] = scratch;
  turned.clear(), scan.clear();
  const double heading = self.get_real(kAngle);
  for (const std::uint32_t i : at) turned.push_back(heading + events[i].number(1));
  cos_a.resize(turned.size()), sin_a.resize(turned.size());
  geometry::beam_directions(turned, "avx2", cos_a, sin_a);  // all at once, 4 at a time
  for (std::size_t k = 0; k < at.size(); ++k) scan.push_back(beam(self, events[at[k]].number(0), cos_a[k], sin_a[k]));
  unmark_neighbours(self, ctx, scan);
  edit_map(self, [&](MapEdit& map, ObstacleBits& bits) {
    sense_scan(map, config_.map, bits, self.get_real(kX), self.get_real(kY), scan, config_.carve_free_space);
  });
}

bool ARobot::goal_of(const ActorState& self, int marker, double& x, double& y) const {
  if (auto it = config_.rooms.find(marker); it != config_.rooms.end()) {
    x = it->second.first;
    y = it->second.second;
    return true;
  }
  // Seen by the camera only: stand in front of it, on the robot's side.
  double mx, my;
  if (!find_marker(*self.get_blob(kGrid), config_.map, marker, mx, my)) return false;
  const double dx = self.get_real(kX) - mx, dy = self.get_real(kY) - my, n = std::hypot(dx, dy);
  if (n < 1e-9) return false;
  x = mx + config_.marker_goal_distance * dx / n;
  y = my + config_.marker_goal_distance * dy / n;
  return true;
}

Decision ARobot::consult(ActorState& self, const EvolutionContext& ctx, double gx, double gy) {
  DecisionInput in;
  in.robot = self.get_int(kId);
  in.map = self.get_blob(kGrid);
  in.geometry = &config_.map;
  in.pose = geometry::Pose2{self.get_real(kX), self.get_real(kY), self.get_real(kAngle)};
  in.goal_x = gx;
  in.goal_y = gy;
  in.radius = config_.radius + config_.margin;
  in.step_length = config_.step_length;
  in.path_owner = self.get_blob(kPath);
  in.path = in.path_owner->view<double>();
  in.seed = ctx.seed;
  Decision d = decider_->decide(in);
  if (d.replanned) self.set_int(kReplans, self.get_int(kReplans) + 1);
  return d;
}

void ARobot::decide(ActorState& self, const EvolutionContext& ctx) {
  const std::int64_t objective = self.get_int(kObjective);
  // A decided action is shown (θ, eExecute) in the next frame only: from then on it is gone.
  if (self.get_bool(kActing)) {
    self.set_bool(kActing, false);
    self.set_real(kTurn, 0.0);
    self.set_real(kMove, 0.0);
  }
  if (objective < 0) {
    // No task, yet still moving: its task was interrupted (eObjective<-1>). The move under way (once the motors
    // have it) is replaced by none, Rotate<0>(Move<0>), which brings the robot to rest within its limits. An
    // avoiding robot comes to rest by its zero velocity.
    if (self.get_bool(kBusy) && self.get_int(kAcked) >= self.get_int(kSent)) {
      self.set_bool(kActing, true);
      self.set_int(kSent, self.get_int(kSent) + 1);
    }
    return;
  }
  // Wait until the motors have received the last command and finished it.
  if (self.get_int(kAcked) < self.get_int(kSent) || self.get_bool(kBusy)) return;
  if (const std::int64_t wait = self.get_int(kWait); wait > 0) {
    self.set_int(kWait, wait - 1);
    return;
  }
  double gx, gy;
  if (!goal_of(self, static_cast<int>(objective), gx, gy)) {
    self.set_text(kStatus, "marker " + std::to_string(objective) + " unknown");
    return;
  }
  const double x = self.get_real(kX), y = self.get_real(kY), theta = self.get_real(kAngle);
  if (std::hypot(gx - x, gy - y) <= config_.goal_tolerance) {
    if (!self.get_bool(kReached)) {
      self.set_bool(kReached, true);
      self.set_text(kStatus, "arrived at marker " + std::to_string(objective));
      self.set_blob(kPath, empty_path());
    }
    return;
  }
  const Decision d = consult(self, ctx, gx, gy);
  if (d.kind == Decision::Kind::NoPath) {
    // Wait a little before searching again, from scratch: the way may clear (a robot moves on).
    self.set_text(kStatus, "no path to marker " + std::to_string(objective));
    self.set_blob(kPath, empty_path());
    self.set_int(kWait, config_.retry_frames);
    return;
  }
  if (!d.keep_path) self.set_blob(kPath, path_blob(d.path));
  self.set_bool(kActing, true);
  self.set_real(kTurn, d.turn);
  self.set_real(kMove, d.distance);
  self.set_int(kSent, self.get_int(kSent) + 1);
  self.set_bool(kBusy, true);
  // Dead reckoning (eq. 12, eDecide): the belief moves where the action should take the robot;
  // odometry corrects it as the motion happens.
  const double heading = geometry::wrap_angle(theta + d.turn);
  const double nx = x + d.distance * std::cos(heading), ny = y + d.distance * std::sin(heading);
  self.set_real(kAngle, heading);
  self.set_real(kX, nx);
  self.set_real(kY, ny);
  int row, col;
  if (config_.map.cell_of(nx, ny, row, col)) {
    self.set_int(kRow, row);
    self.set_int(kColumn, col);
  }
  self.set_text(kStatus, "to marker " + std::to_string(objective));
}

void ARobot::set_velocity(ActorState& self, double speed, double turn_rate) {
  // A robot at rest that stays at rest shows no action (and sends no command).
  if (speed == 0.0 && turn_rate == 0.0 && self.get_real(kSpeed) == 0.0 && self.get_real(kTurnRate) == 0.0) return;
  self.set_bool(kActing, true);
  self.set_real(kSpeed, speed);
  self.set_real(kTurnRate, turn_rate);
  self.set_int(kSent, self.get_int(kSent) + 1);
}

void ARobot::decide_avoiding(ActorState& self, const EvolutionContext& ctx) {
  if (self.get_bool(kActing)) self.set_bool(kActing, false);
  const std::int64_t objective = self.get_int(kObjective);
  const double x = self.get_real(kX), y = self.get_real(kY), theta = self.get_real(kAngle);
  if (objective < 0) return avoid(self, ctx, theta, 0.0);
  if (const std::int64_t wait = self.get_int(kWait); wait > 0) {
    self.set_int(kWait, wait - 1);
    return avoid(self, ctx, theta, 0.0);
  }
  double gx, gy;
  if (!goal_of(self, static_cast<int>(objective), gx, gy)) {
    self.set_text(kStatus, "marker " + std::to_string(objective) + " unknown");
    return avoid(self, ctx, theta, 0.0);
  }
  const double to_goal = std::hypot(gx - x, gy - y);
  // Once there it stays, but gives way: a robot sent to the same room takes its place, as ORCA's shares have it.
  if (self.get_bool(kReached)) return avoid(self, ctx, theta, 0.0);
  if (to_goal <= config_.goal_tolerance) {
    self.set_bool(kReached, true);
    self.set_text(kStatus, "arrived at marker " + std::to_string(objective));
    self.set_blob(kPath, empty_path());
    return avoid(self, ctx, theta, 0.0);
  }
  const Decision d = consult(self, ctx, gx, gy);
  if (d.kind == Decision::Kind::NoPath) {
    self.set_text(kStatus, "no path to marker " + std::to_string(objective));
    self.set_blob(kPath, empty_path());
    self.set_int(kWait, config_.retry_frames);
    forget_seen(self);
    return avoid(self, ctx, theta, 0.0);
  }
  if (!d.keep_path) self.set_blob(kPath, path_blob(d.path));
  self.set_text(kStatus, "to marker " + std::to_string(objective));
  // As fast as still stops at the goal within the acceleration limit.
  avoid(self, ctx, theta + d.turn, std::min(config_.limits.max_speed, std::sqrt(2.0 * config_.limits.max_accel * to_goal)));
}

void ARobot::forget_seen(ActorState& self) {
  // What is still there is marked again by the next scan; what moved on (a person it could not tell from a wall,
  // out of sight since) is gone. The prior map's walls stay.
  const int rows = config_.map.height, cols = config_.map.width;
  edit_map(self, [&](MapEdit& map, ObstacleBits& bits) {
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if (!bits.seen(r, c)) continue;
        const auto k = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c);
        if (map[k] != kSeenCell) continue;
        map.set(k, kFreeCell);
        bits.set(r, c, kFreeCell);
      }
    }
  });
}

void ARobot::avoid(ActorState& self, const EvolutionContext& ctx, double heading, double speed) {
  const double x = self.get_real(kX), y = self.get_real(kY), theta = self.get_real(kAngle);
  thread_local std::vector<orca::Neighbour> neighbours;
  neighbours_in_world(self, ctx, neighbours);
  SteerInput steering;
  steering.pose = geometry::Pose2{x, y, theta};
  steering.speed = self.get_real(kSpeed);
  steering.radius = config_.radius;
  steering.limits = config_.limits;
  steering.preferred_heading = heading;
  steering.preferred_speed = speed;
  steering.neighbours = neighbours;
  platform::Velocity v = steer(steering, config_.avoidance);
  // Never into what the robot's own map holds (ORCA knows only the neighbours).
  const double ahead = v.speed * config_.avoidance.wall_lookahead;
  if (ahead > 0.0) {
    const Blob& map = *self.get_blob(kGrid);
    const double radius = move_radius(map, config_.map, x, y, config_.radius);
    if (!segment_clear(map, config_.map, x, y, x + ahead * std::cos(theta), y + ahead * std::sin(theta), radius)) v.speed = 0.0;
  }
  set_velocity(self, v.speed, v.turn_rate);
}

void ARobot::visualize(const ActorState& self, const EventView& e, const EvolutionContext&, StringBuilder& out) {
  if (e.type() != ev_.execute) return;
  const Datum robot_id(self.get_int(kId));
  if (sym_.path && self.get_blob(kPath)->nbytes() > 0) {
    const Datum params[] = {robot_id, Datum(self.get_blob(kPath))};
    out.primitive(*sym_.path, params);
  }
  if (sym_.status) {
    const Datum params[] = {robot_id, Datum(std::string(self.get_text(kStatus)))};
    out.primitive(*sym_.status, params);
  }
  // Rotate<turn>(Move<move>(Robot<id>)) while acting (Velocity<speed, turn_rate>(Robot<id>) when avoiding);
  // otherwise the robot primitive alone (Table I: drawn by a renderer, no motion on a robot).
  const bool acting = self.get_bool(kActing);
  if (acting && self.get_bool(kAvoid)) {
    if (!sym_.velocity) throw SchemaError("ARobot", "a robot that avoids needs the transformation Velocity<speed, turn_rate>");
    const Datum velocity[] = {Datum(self.get_real(kSpeed)), Datum(self.get_real(kTurnRate))};
    out.open(*sym_.velocity, velocity);
    out.primitive(sym_.robot, std::span<const Datum>(&robot_id, 1));
    out.close();
    return;
  }
  if (acting) {
    const Datum turn(self.get_real(kTurn)), move(self.get_real(kMove));
    out.open(sym_.rotate, std::span<const Datum>(&turn, 1));
    out.open(sym_.move, std::span<const Datum>(&move, 1));
  }
  out.primitive(sym_.robot, std::span<const Datum>(&robot_id, 1));
  if (acting) out.close().close();
}

}  // namespace vwg::robot
