#include "vwg/sim/physics.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <box2d/box2d.h>

#include "vwg/engine.hpp"
#include "vwg/error.hpp"
#include "vwg/hash.hpp"
#include "vwg/text.hpp"
#include "vwg/geometry/pose.hpp"

namespace vwg::sim {

namespace {

constexpr std::uintptr_t kWallTag = 0;  // fixture user data of walls; robots store their id (>= 1)
constexpr std::uintptr_t kPersonTag = std::uintptr_t{1} << 40;  // people store their id with this bit

// The journal's entries (save_state): one byte saying which call, then its arguments.
enum Op : std::uint8_t { kAddRobot = 1, kRemoveRobot, kCommand, kDrive, kAdvance, kTakeCollisions, kSetPerson };
constexpr std::uint64_t kJournalFormat = 1;

// A robot's settings field by field, in visit_settings' order: a field added there is kept here too.
void write_robot(StateWriter& out, const RobotSettings& rs) {
  visit_settings(rs, [&](const char*, const auto& v, const char*) {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, int>) {
      out.i64(v);
    } else if constexpr (std::is_same_v<T, double>) {
      out.f64(v);
    } else if constexpr (std::is_same_v<T, platform::Pose2>) {
      for (double c : {v.x, v.y, v.theta}) out.f64(c);
    } else {
      static_assert(std::is_same_v<T, std::vector<std::string>>);
      out.u64(v.size());
      for (const std::string& text : v) out.text(text);
    }
  });
}

RobotSettings read_robot(StateReader& in) {
  RobotSettings rs;
  visit_settings(rs, [&](const char* field, auto& v, const char*) {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, int>) {
      const std::int64_t x = in.i64();
      if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max()) {
        in.fail(std::string("a robot's ") + field + " out of range: " + std::to_string(x));
      }
      v = static_cast<int>(x);
    } else if constexpr (std::is_same_v<T, double>) {
      v = in.f64();
    } else if constexpr (std::is_same_v<T, platform::Pose2>) {
      for (double* c : {&v.x, &v.y, &v.theta}) *c = in.f64();
    } else {
      static_assert(std::is_same_v<T, std::vector<std::string>>);
      v.resize(in.count(8, field));
      for (std::string& text : v) text = in.text();
    }
  });
  if (rs.id < 1) in.fail("a robot id out of range: " + std::to_string(rs.id));
  return rs;
}

std::uint64_t fingerprint_of(const OccupancyGrid& grid, std::span<const RobotSettings> robots, const PhysicsSettings& s) {
  StateWriter out;
  out.i64(grid.width);
  out.i64(grid.height);
  for (double v : {grid.resolution, grid.origin.x, grid.origin.y, grid.origin.theta, s.step, s.noise.motors, s.noise.odometry}) {
    out.f64(v);
  }
  for (std::int64_t v : {std::int64_t{s.velocity_iterations}, std::int64_t{s.position_iterations},
                         std::int64_t{s.obstacle_threshold}, std::int64_t{s.walls_at_border}}) {
    out.i64(v);
  }
  out.u64(s.seed);
  for (const RobotSettings& rs : robots) write_robot(out, rs);
  return hash_combine(hash_bytes(grid.data.data(), grid.data.size()), hash_bytes(out.bytes().data(), out.bytes().size()));
}

}  // namespace

void check_settings(const NoiseModel& noise, const std::string& owner) {
  for (const auto& [field, value] : {std::pair{"motors", noise.motors}, std::pair{"odometry", noise.odometry}}) {
    if (!std::isfinite(value) || value < 0.0) {
      throw SchemaError(owner + "." + field, "expected a finite standard deviation >= 0, got " + format_real(value));
    }
  }
}

void check_settings(const PhysicsSettings& s, const std::string& owner) {
  if (!std::isfinite(s.step) || s.step <= 0.0 || s.step > 1.0) {
    throw SchemaError(owner + ".step", "expected a time step in (0, 1] seconds, got " + format_real(s.step));
  }
  if (s.velocity_iterations < 1 || s.velocity_iterations > 1000) throw SchemaError(owner + ".velocity_iterations", "expected 1 to 1000");
  if (s.position_iterations < 1 || s.position_iterations > 1000) throw SchemaError(owner + ".position_iterations", "expected 1 to 1000");
  if (s.obstacle_threshold < 1 || s.obstacle_threshold > 100) throw SchemaError(owner + ".obstacle_threshold", "expected 1 to 100");
  check_settings(s.noise, owner + ".noise");
}

namespace {

void check_finite_positive(double v, const std::string& field) {
  if (!std::isfinite(v) || v <= 0.0) throw SchemaError(field, "expected a finite value > 0, got " + std::to_string(v));
}

}  // namespace

struct PhysicsWorld::Box2D {
  b2World world{b2Vec2(0.0f, 0.0f)};  // seen from above: no gravity
};

struct PhysicsWorld::Robot {
  RobotSettings settings;
  b2Body* body = nullptr;  // owned by the b2World
  Rng rng;
  platform::MotionFollower follower;
  bool driven = false;  // drive() holds a velocity: the follower is set aside until the next command
  platform::Velocity held{};
  /// What it is told to do now: the held velocities, or its plan's.
  platform::Velocity velocity() const { return driven ? held : follower.velocity(); }
  int contacts = 0;
  int last_other = 0;  // what it touched last: a robot id, or 0 for a wall
  int stuck_steps = 0;
};

/// Counts contacts per robot and records the beginning of each as a Collision.
class PhysicsWorld::Contacts : public b2ContactListener {
 public:
  explicit Contacts(PhysicsWorld& world) : world_(world) {}
  void BeginContact(b2Contact* contact) override { update(contact, +1); }
  void EndContact(b2Contact* contact) override { update(contact, -1); }

 private:
  void update(b2Contact* contact, int delta) {
    const std::uintptr_t a = contact->GetFixtureA()->GetUserData().pointer;
    const std::uintptr_t b = contact->GetFixtureB()->GetUserData().pointer;
    for (auto [self, other] : {std::pair{a, b}, std::pair{b, a}}) {
      if (self == kWallTag || (self & kPersonTag) != 0) continue;
      const std::size_t i = world_.index_of(static_cast<int>(self));
      Robot& r = world_.robots_[i];
      r.contacts += delta;
      if (delta > 0) {
        RobotState& s = world_.states_[i];
        ++s.collisions;
        const int other_id = other == kWallTag          ? 0
                             : (other & kPersonTag) != 0 ? -static_cast<int>(other & ~kPersonTag)
                                                         : static_cast<int>(other);
        r.last_other = other_id;
        world_.collisions_.push_back(Collision{r.settings.id, other_id, s.pose, world_.time_});
      }
    }
  }
  PhysicsWorld& world_;
};

std::vector<PhysicsWorld::CellRect> PhysicsWorld::merge_walls(const OccupancyGrid& grid, int threshold) {
  std::vector<CellRect> rects;
  std::vector<std::uint8_t> used(static_cast<std::size_t>(grid.width) * grid.height, 0);
  auto free_wall = [&](int r, int c) {
    return grid.at(r, c) >= threshold && !used[static_cast<std::size_t>(r) * grid.width + c];
  };
  for (int r = 0; r < grid.height; ++r) {
    for (int c = 0; c < grid.width; ++c) {
      if (!free_wall(r, c)) continue;
      int c1 = c;
      while (c1 < grid.width && free_wall(r, c1)) ++c1;
      int r1 = r + 1;
      while (r1 < grid.height) {
        bool whole = true;
        for (int k = c; k < c1 && whole; ++k) whole = free_wall(r1, k);
        if (!whole) break;
        ++r1;
      }
      for (int rr = r; rr < r1; ++rr) {
        for (int k = c; k < c1; ++k) used[static_cast<std::size_t>(rr) * grid.width + k] = 1;
      }
      rects.push_back(CellRect{r, c, r1, c1});
      c = c1 - 1;
    }
  }
  return rects;
}

PhysicsWorld::PhysicsWorld(const OccupancyGrid& grid, std::span<const RobotSettings> robots, PhysicsSettings settings)
    : grid_(grid), settings_(settings), box2d_(std::make_unique<Box2D>()) {
  if (grid_.width <= 0 || grid_.height <= 0 || grid_.data.size() != static_cast<std::size_t>(grid_.width) * grid_.height) {
    throw SchemaError("grid", "expected width × height cells");
  }
  check_finite_positive(grid_.resolution, "grid.resolution");
  check_settings(settings_, "physics");

  // Walls: one static body, one box fixture per merged rectangle.
  b2BodyDef wall_def;
  b2Body* walls = box2d_->world.CreateBody(&wall_def);
  const double res = grid_.resolution;
  auto add_box = [&](double u0, double v0, double u1, double v1) {  // grid units
    double cx, cy;
    grid_.grid_to_world((u0 + u1) / 2, (v0 + v1) / 2, cx, cy);
    b2PolygonShape box;
    box.SetAsBox(static_cast<float>((u1 - u0) * res / 2), static_cast<float>((v1 - v0) * res / 2),
                 b2Vec2(static_cast<float>(cx), static_cast<float>(cy)), static_cast<float>(grid_.origin.theta));
    b2FixtureDef fd;
    fd.shape = &box;
    fd.friction = 0.0f;
    fd.userData.pointer = kWallTag;
    walls->CreateFixture(&fd);
    ++wall_shapes_;
  };
  for (const CellRect& r : merge_walls(grid_, settings_.obstacle_threshold)) add_box(r.col0, r.row0, r.col1, r.row1);
  if (settings_.walls_at_border) {
    const double w = grid_.width, h = grid_.height, t = 1.0;
    add_box(-t, -t, w + t, 0);
    add_box(-t, h, w + t, h + t);
    add_box(-t, 0, 0, h);
    add_box(w, 0, w + t, h);
  }

  contacts_ = std::make_unique<Contacts>(*this);
  box2d_->world.SetContactListener(contacts_.get());
  robots_.reserve(robots.size());
  states_.reserve(robots.size());
  for (const RobotSettings& rs : robots) add_body(rs);
  disc_index_.rebuild(discs_);  // once for all of them
  fingerprint_ = fingerprint_of(grid_, robots, settings_);
}

void PhysicsWorld::add_robot(const RobotSettings& rs) {
  add_body(rs);
  disc_index_.rebuild(discs_);
  journal_.u8(kAddRobot);
  write_robot(journal_, rs);
}

void PhysicsWorld::add_body(const RobotSettings& rs) {
  const std::string who = "robot " + std::to_string(rs.id);
  check_settings(rs, who);
  for (std::size_t k = 0; k < robots_.size(); ++k) {
    const Robot& other = robots_[k];
    if (other.settings.id == rs.id) throw SchemaError(who, "the id is used twice");
    const double d = std::hypot(states_[k].pose.x - rs.start.x, states_[k].pose.y - rs.start.y);
    if (d < other.settings.radius + rs.radius) {
      throw SchemaError(who + ".start", "overlaps robot " + std::to_string(other.settings.id));
    }
  }
  const double res = grid_.resolution;
  double u, v;
  grid_.world_to_grid(rs.start.x, rs.start.y, u, v);
  if (u < 0 || v < 0 || u >= grid_.width || v >= grid_.height) throw SchemaError(who + ".start", "is outside the map");
  const double rc = rs.radius / res;  // radius in cells
  for (int row = static_cast<int>(std::floor(v - rc)); row <= static_cast<int>(std::floor(v + rc)); ++row) {
    for (int col = static_cast<int>(std::floor(u - rc)); col <= static_cast<int>(std::floor(u + rc)); ++col) {
      if (!grid_.blocked(row, col, settings_.obstacle_threshold)) continue;
      const double du = std::max({col - u, 0.0, u - (col + 1)});
      const double dv = std::max({row - v, 0.0, v - (row + 1)});
      if (std::hypot(du, dv) < rc) {
        throw SchemaError(who + ".start", "the robot at (" + std::to_string(rs.start.x) + ", " +
                                              std::to_string(rs.start.y) + ") is inside a wall");
      }
    }
  }
  b2BodyDef bd;
  bd.type = b2_dynamicBody;
  bd.position.Set(static_cast<float>(rs.start.x), static_cast<float>(rs.start.y));
  bd.angle = static_cast<float>(rs.start.theta);
  bd.allowSleep = false;
  Robot r{rs, nullptr, Rng{}, platform::MotionFollower(rs.limits)};
  r.body = box2d_->world.CreateBody(&bd);
  b2CircleShape circle;
  circle.m_radius = static_cast<float>(rs.radius);
  b2FixtureDef fd;
  fd.shape = &circle;
  fd.density = 1.0f;
  fd.friction = 0.0f;
  fd.userData.pointer = static_cast<std::uintptr_t>(rs.id);
  r.body->CreateFixture(&fd);
  r.rng.reseed(derive_seed(settings_.seed, 0x726F626FULL, static_cast<std::uint64_t>(rs.id)));
  robots_.push_back(std::move(r));
  RobotState st;
  st.id = rs.id;
  st.radius = rs.radius;
  st.pose = st.odometry = platform::quantize_pose({bd.position.x, bd.position.y, bd.angle});
  states_.push_back(st);
  // Robots' discs first, in their order, then the people's.
  discs_.insert(discs_.begin() + static_cast<std::ptrdiff_t>(states_.size() - 1), Disc{st.pose.x, st.pose.y, st.radius, st.id});
  index_[rs.id] = states_.size() - 1;
}

void PhysicsWorld::remove_robot(int id) {
  const std::size_t i = index_of(id);
  // Box2D ends the body's contacts (the listener still finds the robot), then it is forgotten.
  box2d_->world.DestroyBody(robots_[i].body);
  robots_.erase(robots_.begin() + static_cast<std::ptrdiff_t>(i));
  states_.erase(states_.begin() + static_cast<std::ptrdiff_t>(i));
  discs_.erase(discs_.begin() + static_cast<std::ptrdiff_t>(i));
  disc_index_.rebuild(discs_);
  index_.erase(id);
  for (auto& [other, k] : index_) k -= k > i ? 1 : 0;
  journal_.u8(kRemoveRobot);
  journal_.i64(id);
}

std::size_t PhysicsWorld::index_of(int id) const {
  // By id, not by walking the robots: every robot's generators and commands look themselves up
  // each frame, which a walk made quadratic in the crowd.
  if (const auto it = index_.find(id); it != index_.end()) return it->second;
  throw SchemaError("robot", "no robot with id " + std::to_string(id) + " on the simulator");
}

PhysicsWorld::~PhysicsWorld() {
  if (box2d_) box2d_->world.SetContactListener(nullptr);
}

PhysicsWorld::Robot& PhysicsWorld::find(int id) { return robots_[index_of(id)]; }

const RobotState& PhysicsWorld::robot(int id) const { return states_[index_of(id)]; }

const RobotState* PhysicsWorld::find_robot(int id) const {
  const auto it = index_.find(id);
  return it != index_.end() ? &states_[it->second] : nullptr;
}

void PhysicsWorld::command(int robot, std::vector<MotionStep> plan) {
  Robot& r = find(robot);
  for (const MotionStep& s : plan) {
    if (!std::isfinite(s.amount) || !std::isfinite(s.rate)) {
      throw SchemaError("robot " + std::to_string(robot) + " command", "non-finite amount");
    }
  }
  journal_.u8(kCommand);
  journal_.i64(robot);
  journal_.u64(plan.size());
  for (const MotionStep& s : plan) {
    journal_.u8(s.kind);
    journal_.f64(s.amount);
    if (s.kind == MotionStep::Steer) journal_.f64(s.rate);
  }
  // The motors' error: each step is executed as amount·(1 + N(0, motors²)) (the follower, closed
  // on the true pose, then carries out the wrong amount faithfully); a steer's turn rate by the same factor.
  if (settings_.noise.motors > 0.0) {
    for (MotionStep& s : plan) {
      const double factor = 1.0 + r.rng.normal(0.0, settings_.noise.motors);
      s.amount *= factor;
      s.rate *= factor;
    }
  }
  r.follower.command(plan);
  r.driven = false;
  r.stuck_steps = 0;
  RobotState& s = states_[static_cast<std::size_t>(&r - robots_.data())];
  ++s.commands;
  s.busy = r.follower.busy();
}

void PhysicsWorld::drive(int robot, double speed, double turn_rate) {
  if (!std::isfinite(speed) || !std::isfinite(turn_rate)) {
    throw SchemaError("robot " + std::to_string(robot) + " drive", "expected finite velocities");
  }
  Robot& r = find(robot);
  journal_.u8(kDrive);
  journal_.i64(robot);
  journal_.f64(speed);
  journal_.f64(turn_rate);
  r.follower.stop();
  r.driven = true;
  r.held = {speed, turn_rate};
  RobotState& s = states_[static_cast<std::size_t>(&r - robots_.data())];
  s.busy = false;
}

void PhysicsWorld::step_robot(Robot& r, const RobotState& state, double dt) {
  const platform::Velocity v = r.driven ? r.held : r.follower.tick(state.pose, dt);
  // Along the body's own heading: the same for a plan followed here and for velocities from a link.
  const float a = r.body->GetAngle();
  r.body->SetLinearVelocity(static_cast<float>(v.speed) * b2Vec2(std::cos(a), std::sin(a)));
  r.body->SetAngularVelocity(static_cast<float>(v.turn_rate));
}

void PhysicsWorld::advance(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) throw SchemaError("advance", "expected a finite time >= 0");
  journal_.u8(kAdvance);
  journal_.f64(seconds);
  const double dt = settings_.step;
  const double total = pending_ + seconds;
  const auto steps = static_cast<std::int64_t>(std::floor(total / dt + 1e-9));
  pending_ = std::max(0.0, total - static_cast<double>(steps) * dt);
  // The index follows the discs however this ends (a step that throws has moved some of them).
  struct Reindex {
    PhysicsWorld& world;
    ~Reindex() { world.disc_index_.rebuild(world.discs_); }
  } reindex{*this};
  for (std::int64_t k = 0; k < steps; ++k) {
    std::vector<b2Vec2> before(robots_.size());
    std::vector<float> angle_before(robots_.size());
    for (std::size_t i = 0; i < robots_.size(); ++i) {
      step_robot(robots_[i], states_[i], dt);
      before[i] = robots_[i].body->GetPosition();
      angle_before[i] = robots_[i].body->GetAngle();
    }
    box2d_->world.Step(static_cast<float>(dt), settings_.velocity_iterations, settings_.position_iterations);
    time_ += dt;
    for (std::size_t k = 0; k < people_.size(); ++k) {
      const b2Vec2 p = person_bodies_[k]->GetPosition();
      people_[k].x = p.x, people_[k].y = p.y;
      Disc& d = discs_[robots_.size() + k];
      d.x = p.x, d.y = p.y;
    }
    for (std::size_t i = 0; i < robots_.size(); ++i) {
      Robot& r = robots_[i];
      RobotState& s = states_[i];
      const b2Vec2 p = r.body->GetPosition();
      const float a = r.body->GetAngle();
      const b2Vec2 heading(std::cos(angle_before[i]), std::sin(angle_before[i]));
      const double ds = b2Dot(p - before[i], heading);
      const double da = static_cast<double>(a) - angle_before[i];
      s.pose = platform::quantize_pose({p.x, p.y, a});
      discs_[i].x = s.pose.x;
      discs_[i].y = s.pose.y;
      s.travelled += std::abs(ds);
      if (settings_.noise.odometry > 0.0) {
        const double sigma = settings_.noise.odometry;
        const double ds_m = ds + r.rng.normal(0.0, sigma * std::sqrt(std::abs(ds)));
        const double da_m = da + r.rng.normal(0.0, sigma * std::sqrt(std::abs(da)));
        s.odometry.theta += da_m / 2;
        s.odometry.x += ds_m * std::cos(s.odometry.theta);
        s.odometry.y += ds_m * std::sin(s.odometry.theta);
        s.odometry.theta = geometry::wrap_angle(s.odometry.theta + da_m / 2);
      } else {
        s.odometry = s.pose;
      }
      // Pushing against a wall or a robot without getting anywhere: give up the plan.
      if (r.follower.driving() && r.contacts > 0 && std::abs(ds) < 0.25 * std::abs(r.velocity().speed) * dt) {
        if (++r.stuck_steps >= 20) {
          r.follower.stop();
          // Reported like a collision: the robot learns that this drive is blocked, even when
          // the contact began long ago (a wall it keeps pushing against).
          collisions_.push_back(Collision{r.settings.id, r.last_other, s.pose, time_});
        }
      } else {
        r.stuck_steps = 0;
      }
      r.follower.settle(s.pose);  // idle when driven: nothing to settle
      s.speed = r.velocity().speed;
      s.turn_rate = r.velocity().turn_rate;
      s.busy = r.follower.busy();
    }
  }
}

void PhysicsWorld::set_person(int id, double x, double y, double vx, double vy, double radius) {
  const std::string who = "person " + std::to_string(id);
  if (id < 1) throw SchemaError(who, "expected an id >= 1");
  for (const double v : {x, y, vx, vy}) {
    if (!std::isfinite(v) || std::abs(v) > platform::kMaxCoordinate) throw SchemaError(who, "expected finite positions and velocities");
  }
  if (!(radius > 0.0 && radius <= 10.0)) throw SchemaError(who + ".radius", "expected 0 to 10 metres");
  journal_.u8(kSetPerson);
  journal_.i64(id);
  for (const double v : {x, y, vx, vy, radius}) journal_.f64(v);
  std::size_t k = 0;
  while (k < people_.size() && people_[k].id != id) ++k;
  if (k == people_.size()) {
    b2BodyDef bd;
    bd.type = b2_kinematicBody;
    bd.allowSleep = false;
    b2Body* body = box2d_->world.CreateBody(&bd);
    b2CircleShape circle;
    circle.m_radius = static_cast<float>(radius);
    b2FixtureDef fd;
    fd.shape = &circle;
    fd.userData.pointer = kPersonTag | static_cast<std::uintptr_t>(id);
    body->CreateFixture(&fd);
    people_.push_back(Person{id, x, y, vx, vy, radius});
    person_bodies_.push_back(body);
    discs_.push_back(Disc{x, y, radius, -id});
  }
  b2Body* body = person_bodies_[k];
  body->SetTransform(b2Vec2(static_cast<float>(x), static_cast<float>(y)), 0.0f);
  body->SetLinearVelocity(b2Vec2(static_cast<float>(vx), static_cast<float>(vy)));
  const b2Vec2 p = body->GetPosition();
  people_[k] = Person{id, p.x, p.y, vx, vy, people_[k].radius};
  Disc& d = discs_[robots_.size() + k];
  d.x = p.x, d.y = p.y;
  disc_index_.rebuild(discs_);
}

std::vector<Collision> PhysicsWorld::take_collisions() {
  journal_.u8(kTakeCollisions);
  return std::exchange(collisions_, {});
}

void PhysicsWorld::save_state(StateWriter& out) const {
  out.u64(kJournalFormat);
  out.u64(fingerprint_);
  out.text(journal_.bytes());
}

void PhysicsWorld::load_state(StateReader& in) {
  if (const std::uint64_t format = in.u64(); format != kJournalFormat) {
    in.fail("a simulator journal of format " + std::to_string(format) + "; this vwg reads format " +
            std::to_string(kJournalFormat));
  }
  if (in.u64() != fingerprint_) {
    in.fail("saved by a simulator of another map, settings or robots than this one");
  }
  const std::string journal = in.text();
  in.end();
  const std::string& done = journal_.bytes();
  if (journal.size() < done.size() || journal.compare(0, done.size(), done) != 0) {
    in.fail("this simulator has already been used in another way than the saved one (load a state into a new one)");
  }
  // The rest, read whole and checked first (ids, kinds, times: a forged journal is refused before it
  // runs), then call by call: the same calls give the same bits (and journal themselves again).
  struct Call {
    Op op;
    int robot = 0;
    double a = 0.0, b = 0.0, x = 0.0, y = 0.0, radius = 0.0;  // kDrive: a, b; kSetPerson: all five
    RobotSettings settings;
    std::vector<MotionStep> plan;
  };
  std::vector<Call> calls;
  StateReader ops(std::string_view(journal).substr(done.size()), in.part() + " journal");
  auto robot_id = [&] {
    const std::int64_t id = ops.i64();
    if (id < 1 || id > std::numeric_limits<int>::max()) ops.fail("a robot id out of range: " + std::to_string(id));
    return static_cast<int>(id);
  };
  double seconds = time_ + pending_;
  while (ops.left() > 0) {
    Call c;
    c.op = static_cast<Op>(ops.u8());
    switch (c.op) {
      case kAddRobot:
        c.settings = read_robot(ops);
        break;
      case kRemoveRobot:
        c.robot = robot_id();
        break;
      case kCommand: {
        c.robot = robot_id();
        c.plan.resize(ops.count(9, "motion steps"));
        for (MotionStep& step : c.plan) {
          const std::uint8_t kind = ops.u8();
          if (kind > MotionStep::Steer) ops.fail("a motion step of unknown kind " + std::to_string(kind));
          step = MotionStep{static_cast<MotionStep::Kind>(kind), ops.f64()};
          if (kind == MotionStep::Steer) step.rate = ops.f64();
        }
        break;
      }
      case kDrive:
        c.robot = robot_id();
        c.a = ops.f64();
        c.b = ops.f64();
        break;
      case kAdvance:
        c.a = ops.f64();
        // A frame's time at most, and in all no more than the saved run's.
        if (!(c.a >= 0.0 && c.a <= kMaxDt)) ops.fail("an advance of " + format_real(c.a) + " s");
        seconds += c.a;
        if (seconds > in.max_seconds() * (1.0 + 1e-9) + 1e-6) {
          ops.fail("its steps pass more time than the saved run's " + format_real(in.max_seconds()) + " s");
        }
        break;
      case kTakeCollisions:
        break;
      case kSetPerson: {
        const std::int64_t id = ops.i64();
        if (id < 1 || id > std::numeric_limits<int>::max()) ops.fail("a person id out of range: " + std::to_string(id));
        c.robot = static_cast<int>(id);
        for (double* v : {&c.a, &c.b, &c.x, &c.y, &c.radius}) *v = ops.f64();
        break;
      }
      default:
        ops.fail("an entry of unknown kind");
    }
    calls.push_back(std::move(c));
  }
  for (Call& c : calls) {
    switch (c.op) {
      case kAddRobot: add_robot(c.settings); break;
      case kRemoveRobot: remove_robot(c.robot); break;
      case kCommand: command(c.robot, std::move(c.plan)); break;
      case kDrive: drive(c.robot, c.a, c.b); break;
      case kAdvance: advance(c.a); break;
      case kTakeCollisions: take_collisions(); break;
      case kSetPerson: set_person(c.robot, c.a, c.b, c.x, c.y, c.radius); break;
    }
  }
}

}  // namespace vwg::sim
