#include "vwg/sim/people.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "vwg/error.hpp"
#include "vwg/plan/astar.hpp"
#include "vwg/random.hpp"
#include "vwg/text.hpp"

namespace vwg::sim {

namespace {

ParamSpec spec(const char* name, ValueKind kind, std::optional<Datum> def = std::nullopt) {
  return ParamSpec{name, kind, std::move(def)};
}

std::shared_ptr<const Blob> points_blob(const std::vector<double>& xy) {
  const auto n = static_cast<std::int64_t>(xy.size() / 2);
  return std::make_shared<const Blob>(DType::Float64, std::vector<std::int64_t>{n, 2}, xy.data(), xy.size() * sizeof(double));
}

}  // namespace

void check_settings(const SocialForceSettings& s, const std::string& owner) {
  const std::pair<const char*, double> positive[] = {
      {"relaxation", s.relaxation},     {"people_strength", s.people_strength}, {"people_range", s.people_range},
      {"robot_strength", s.robot_strength}, {"robot_range", s.robot_range},     {"wall_strength", s.wall_strength},
      {"wall_range", s.wall_range},     {"reach", s.reach},                     {"arrive", s.arrive}};
  for (const auto& [name, v] : positive) {
    if (!std::isfinite(v) || v <= 0) throw SchemaError(owner + "." + name, "expected a finite number > 0, got " + format_real(v));
  }
  if (!(s.sidestep >= 0.0 && s.sidestep <= 10.0)) {
    throw SchemaError(owner + ".sidestep", "expected a share from 0 to 10, got " + format_real(s.sidestep));
  }
  if (!(s.give_up > 0.0 && s.give_up <= 1e6)) {
    throw SchemaError(owner + ".give_up", "expected seconds > 0, got " + format_real(s.give_up));
  }
  if (!(s.max_speed >= 1.0 && s.max_speed <= 10.0)) {
    throw SchemaError(owner + ".max_speed", "expected 1 to 10 times the walking speed, got " + format_real(s.max_speed));
  }
}

Vec push_of(double x, double y, double radius, double ox, double oy, double other_radius, double strength, double range,
            double reach) {
  const double dx = x - ox, dy = y - oy, d = std::hypot(dx, dy);
  if (d > reach || d < 1e-9) return {};
  const double f = strength * std::exp((radius + other_radius - d) / range);
  return {f * dx / d, f * dy / d};
}

Vec repulsion(const PhysicsWorld::Person& person, std::span<const Disc> discs, const geometry::ClearanceField& walls,
              const OccupancyGrid& map, const SocialForceSettings& s) {
  Vec f;
  for (const Disc& d : discs) {
    if (d.id == -person.id) continue;
    const bool robot = d.id > 0;
    const Vec p = push_of(person.x, person.y, person.radius, d.x, d.y, d.radius, robot ? s.robot_strength : s.people_strength,
                          robot ? s.robot_range : s.people_range, s.reach);
    f.x += p.x, f.y += p.y;
    // Someone ahead also turns the person to its right (people keep right): no standstill face to face.
    const double speed = std::hypot(person.vx, person.vy);
    if (speed > 1e-6 && (d.x - person.x) * person.vx + (d.y - person.y) * person.vy > 0) {
      const double push = s.sidestep * std::hypot(p.x, p.y) / speed;
      f.x += push * person.vy, f.y -= push * person.vx;
    }
  }
  // The nearest wall: its clearance (cells) and, by central differences a quarter cell apart, the way away from it.
  double u, v;
  map.world_to_grid(person.x, person.y, u, v);
  const double cap = s.reach / map.resolution, h = 0.25;
  const double c = walls.clearance(u, v, cap);
  if (c < cap) {
    const double gu = walls.clearance(u + h, v, cap) - walls.clearance(u - h, v, cap);
    const double gv = walls.clearance(u, v + h, cap) - walls.clearance(u, v - h, cap);
    const double n = std::hypot(gu, gv);
    if (n > 1e-12) {
      // Grid axes to the world's (a map may be turned by its origin's yaw).
      const double ct = std::cos(map.origin.theta), st = std::sin(map.origin.theta);
      const double wx = ct * gu - st * gv, wy = st * gu + ct * gv;
      const double push = s.wall_strength * std::exp((person.radius - c * map.resolution) / s.wall_range);
      f.x += push * wx / n, f.y += push * wy / n;
    }
  }
  return f;
}

Schema person_attributes() {
  Schema s;
  s.params = {
      spec("id", ValueKind::Int, Datum(1)),
      spec("x", ValueKind::Real, Datum(0.0)),
      spec("y", ValueKind::Real, Datum(0.0)),
      spec("vx", ValueKind::Real, Datum(0.0)),
      spec("vy", ValueKind::Real, Datum(0.0)),
      spec("radius", ValueKind::Real, Datum(0.25)),
      spec("speed", ValueKind::Real, Datum(1.0)),
      // Where it walks: its waypoints (N×2), in turn (looping or not), or, wandering, rooms drawn from the seed.
      spec("goals", ValueKind::Blob, Datum(points_blob({}))),
      spec("loop", ValueKind::Bool, Datum(true)),
      spec("wander", ValueKind::Bool, Datum(false)),
      spec("leg", ValueKind::Int, Datum(0)),  // legs begun; -1: a walk that does not loop has ended
      spec("way", ValueKind::Blob, Datum(points_blob({}))),  // the points of this leg's way still ahead
      spec("stuck", ValueKind::Real, Datum(0.0)),  // seconds it has been all but stopped on this way
      // Seconds it stands before it looks for a way again, after it found none to its goal (a goal walled off,
      // or the person shut in): searching every frame would cost a whole-map search a frame.
      spec("rest", ValueKind::Real, Datum(0.0)),
  };
  return s;
}

PersonBehavior::PersonBehavior(const Alphabet& alphabet, const OccupancyGrid& map, SocialForceSettings settings, double dt,
                               double largest_radius)
    : geometry_(geometry::MapGeometry::of(map)), map_(map),
      walls_(geometry::BlockedGrid::from_occupancy(map), true), settings_(settings), dt_(dt), social_(alphabet.event_type_id("eSocial")),
      execute_(alphabet.event_type_id("eExecute")), pedestrian_(alphabet.symbol_id("Pedestrian", SymbolKind::Primitive)) {
  check_settings(settings_, "people");
  if (!(dt > 0 && std::isfinite(dt))) throw SchemaError("dt", "expected seconds > 0");
  grown_ = walls_.inflated(largest_radius / map.resolution);
}

std::vector<double> PersonBehavior::route(double x, double y, double gx, double gy) const {
  int r0, c0, r1, c1;
  if (!geometry_.cell_of(x, y, r0, c0) || !geometry_.cell_of(gx, gy, r1, c1)) return {};
  // From the free cell nearest to each end (a person pushed against a wall, a goal beside one).
  const auto free_near = [&](geometry::Cell c) -> geometry::Cell {
    for (int d = 0; d <= 20; ++d) {
      for (int dr = -d; dr <= d; ++dr) {
        for (int dc = -d; dc <= d; ++dc) {
          const geometry::Cell n{c.row + dr, c.col + dc};
          if (std::max(std::abs(dr), std::abs(dc)) == d && grown_.inside(n) && !grown_.blocked(n)) return n;
        }
      }
    }
    return {-1, -1};
  };
  const geometry::Cell start = free_near({r0, c0}), goal = free_near({r1, c1});
  if (start.row < 0 || goal.row < 0) return {};
  thread_local plan::AStar astar;
  const plan::GridPath path = astar.search(grown_, start, goal);
  std::vector<double> xy;
  for (std::size_t i = 1; i < path.cells.size(); ++i) {
    double px, py;
    geometry_.centre_of(path.cells[i].row, path.cells[i].col, px, py);
    xy.push_back(px), xy.push_back(py);
  }
  if (path.found()) xy.push_back(gx), xy.push_back(gy);
  return xy;
}

void PersonBehavior::evolve(ActorState& self, const EventView& e, const EvolutionContext& ctx, Replacement&) {
  if (e.type() != social_) return;
  double x = self.get_real(kPx), y = self.get_real(kPy), vx = self.get_real(kPvx), vy = self.get_real(kPvy);
  const double speed = self.get_real(kPspeed);
  std::int64_t leg = self.get_int(kLeg);
  auto way = self.get_blob(kWay)->view<double>();
  std::vector<double> ahead(way.begin(), way.end());
  // The points passed drop off the way; a way walked to its end ends the leg, and so does one on which the person
  // has been all but stopped for `give_up` seconds (someone stands in its door, or on its goal): it walks on to
  // its next goal instead.
  // Those before the nearest point of the next 2 m of way are behind it (it cut a corner past them); farther on, a
  // way that comes back beside a wall is not near.
  std::size_t nearest = 0;
  double along = 0.0;
  for (std::size_t i = 2; i + 1 < ahead.size(); i += 2) {
    along += std::hypot(ahead[i] - ahead[i - 2], ahead[i + 1] - ahead[i - 1]);
    if (along > 2.0) break;
    if (std::hypot(ahead[i] - x, ahead[i + 1] - y) < std::hypot(ahead[nearest] - x, ahead[nearest + 1] - y)) nearest = i;
  }
  ahead.erase(ahead.begin(), ahead.begin() + static_cast<std::ptrdiff_t>(nearest));
  while (ahead.size() >= 2 && std::hypot(ahead[0] - x, ahead[1] - y) <= settings_.arrive) ahead.erase(ahead.begin(), ahead.begin() + 2);
  double stuck = std::hypot(vx, vy) < 0.1 * speed && !ahead.empty() ? self.get_real(kStuck) + dt_ : 0.0;
  if (stuck >= settings_.give_up) {
    ahead.clear();
    stuck = 0.0;
  }
  self.set_real(kStuck, stuck);
  const auto goals = self.get_blob(kGoals)->view<double>();
  const std::size_t n = goals.size() / 2;
  double rest = self.get_real(kRest);
  if (rest > 0.0) rest = rest - dt_ > 1e-9 ? rest - dt_ : 0.0;  // (no retry a frame late for a rounding)
  if (ahead.empty() && leg >= 0 && n > 0 && rest == 0.0) {
    std::size_t k;
    if (self.get_bool(kWander)) {
      Rng rng(derive_seed(ctx.seed, 0x77616C6BULL, static_cast<std::uint64_t>(self.get_int(kPersonId)) << 32 | static_cast<std::uint64_t>(leg)));
      k = static_cast<std::size_t>(rng.below(n));
    } else if (self.get_bool(kLoop)) {
      k = static_cast<std::size_t>(leg) % n;
    } else {
      k = static_cast<std::size_t>(leg);
    }
    if (k >= n) {
      leg = -1;  // the last waypoint is behind: it stands (and still gives way)
    } else {
      ++leg;
      ahead = route(x, y, goals[2 * k], goals[2 * k + 1]);
      if (ahead.empty()) rest = settings_.give_up;  // no way there: it stands, then tries its next goal
    }
  }
  if (rest != self.get_real(kRest)) self.set_real(kRest, rest);
  // Toward the farthest point of the way within 2 m that the person sees: a disc of its radius goes there
  // straight without touching a wall (round a door's frame, not into it).
  double ex = 0.0, ey = 0.0;
  if (ahead.size() >= 2) {
    std::size_t t = 0;
    double u0, v0;
    map_.world_to_grid(x, y, u0, v0);
    const double r = self.get_real(kPradius) / map_.resolution;
    while (t + 3 < ahead.size() && std::hypot(ahead[t + 2] - x, ahead[t + 3] - y) <= 2.0) {
      double u1, v1;
      map_.world_to_grid(ahead[t + 2], ahead[t + 3], u1, v1);
      if (!walls_.segment_clear(u0, v0, u1, v1, r)) break;
      t += 2;
    }
    const double dx = ahead[t] - x, dy = ahead[t + 1] - y, d = std::hypot(dx, dy);
    if (d > 1e-9) ex = dx / d, ey = dy / d;
  }
  const double fx = e.number(0), fy = e.number(1);
  vx += ((speed * ex - vx) / settings_.relaxation + fx) * dt_;
  vy += ((speed * ey - vy) / settings_.relaxation + fy) * dt_;
  const double v = std::hypot(vx, vy), most = settings_.max_speed * speed;
  if (v > most) vx *= most / v, vy *= most / v;
  x += vx * dt_, y += vy * dt_;
  self.set_real(kPx, x), self.set_real(kPy, y), self.set_real(kPvx, vx), self.set_real(kPvy, vy);
  self.set_int(kLeg, leg);
  if (ahead.size() != way.size()) self.set_blob(kWay, points_blob(ahead));
}

void PersonBehavior::visualize(const ActorState& self, const EventView& e, const EvolutionContext&, StringBuilder& out) {
  if (e.type() != execute_) return;
  const Datum params[] = {Datum(self.get_int(kPersonId)), Datum(self.get_real(kPx)), Datum(self.get_real(kPy)),
                          Datum(self.get_real(kPvx)), Datum(self.get_real(kPvy)), Datum(self.get_real(kPradius))};
  out.primitive(pedestrian_, params);
}

SocialForceGenerator::SocialForceGenerator(std::shared_ptr<const PhysicsWorld> world, SocialForceSettings settings,
                                           const Alphabet& alphabet, const std::string& event)
    : world_(std::move(world)), settings_(settings), event_(alphabet.event_type_id(event)) {
  if (!world_) throw Error("SocialForceGenerator: no simulator");
  check_settings(settings_, "people");
  require_fields(alphabet, event_, {{"fx", ValueKind::Real}, {"fy", ValueKind::Real}});
  walls_ = geometry::ClearanceField(geometry::BlockedGrid::from_occupancy(world_->grid()), true);
}

void SocialForceGenerator::generate(const FrameInfo&, EventList& out) {
  for (const PhysicsWorld::Person& p : world_->people()) {
    const Vec f = repulsion(p, world_->discs(), walls_, world_->grid(), settings_);
    const Datum fields[] = {f.x, f.y};
    out.emit(event_, fields, p.id);
  }
}

PeopleBackend::PeopleBackend(std::shared_ptr<PhysicsWorld> world, const Alphabet& alphabet)
    : world_(std::move(world)), pedestrian_(alphabet.symbol_id("Pedestrian", SymbolKind::Primitive)) {
  if (!world_) throw Error("PeopleBackend: no simulator");
}

void PeopleBackend::primitive(const NodeView& p) {
  if (p.symbol() != pedestrian_) return;
  if (p.value_count() < 6) throw SchemaError("Pedestrian", "expected id, x, y, vx, vy and radius");
  world_->set_person(static_cast<int>(p.number(0)), p.number(1), p.number(2), p.number(3), p.number(4), p.number(5));
}

}  // namespace vwg::sim
