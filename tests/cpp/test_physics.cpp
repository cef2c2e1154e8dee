// The Box2D world: merged walls, motion under limits, stopping at walls, noise, collisions.
// Expected values are worked out by hand in the comments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "vwg/error.hpp"
#include "vwg/sim/laser.hpp"
#include "vwg/sim/physics.hpp"
#include "vwg/sim/raycast.hpp"

using namespace vwg::sim;

namespace {

/// An empty w × h map (cells) at `res` m/cell with the listed blocked cells.
OccupancyGrid make_grid(int w, int h, double res, std::initializer_list<std::pair<int, int>> blocked = {}) {
  OccupancyGrid g;
  g.width = w;
  g.height = h;
  g.resolution = res;
  g.data.assign(static_cast<std::size_t>(w) * h, kFree);
  for (auto [r, c] : blocked) g.data[static_cast<std::size_t>(r) * w + c] = kOccupied;
  return g;
}

void block_column(OccupancyGrid& g, int col) {
  for (int r = 0; r < g.height; ++r) g.data[static_cast<std::size_t>(r) * g.width + col] = kOccupied;
}

RobotSettings robot_at(int id, double x, double y, double theta = 0.0) {
  RobotSettings r;
  r.id = id;
  r.start = Pose2{x, y, theta};
  r.radius = 0.2;
  r.limits = RobotLimits{0.5, 1.5, 1.0, 4.0};
  return r;
}

}  // namespace

TEST(Physics, WallsMergeIntoFewRectanglesCoveringEveryBlockedCellOnce) {
  // Rows from the bottom:      row 2: . X X .     An L: the run of row 0 grows into row 1
  //                            row 1: X X . .     only if the whole run is blocked there (it is
  //                            row 0: X X . .     not for cols 0-1 of row 2), so: [r0-2, c0-2) and
  //                                                [r2, c1-3): two rectangles.
  OccupancyGrid g = make_grid(4, 3, 1.0, {{0, 0}, {0, 1}, {1, 0}, {1, 1}, {2, 1}, {2, 2}});
  const auto rects = PhysicsWorld::merge_walls(g, 50);
  ASSERT_EQ(rects.size(), 2u);
  EXPECT_EQ((std::array{rects[0].row0, rects[0].col0, rects[0].row1, rects[0].col1}), (std::array{0, 0, 2, 2}));
  EXPECT_EQ((std::array{rects[1].row0, rects[1].col0, rects[1].row1, rects[1].col1}), (std::array{2, 1, 3, 3}));
  // A 200 × 200 map whose border and two walls are blocked: far fewer shapes than cells.
  OccupancyGrid big = make_grid(200, 200, 0.05);
  for (int k = 0; k < 200; ++k) {
    for (auto [r, c] : {std::pair{0, k}, {199, k}, {k, 0}, {k, 199}, {100, k}, {k, 50}}) {
      big.data[static_cast<std::size_t>(r) * 200 + c] = kOccupied;
    }
  }
  const auto merged = PhysicsWorld::merge_walls(big, 50);
  std::vector<int> cover(200 * 200, 0);
  for (const auto& r : merged) {
    for (int rr = r.row0; rr < r.row1; ++rr) {
      for (int cc = r.col0; cc < r.col1; ++cc) ++cover[static_cast<std::size_t>(rr) * 200 + cc];
    }
  }
  for (std::size_t i = 0; i < cover.size(); ++i) EXPECT_EQ(cover[i], big.data[i] == kOccupied ? 1 : 0);
  EXPECT_LT(merged.size(), 20u);
}

TEST(Physics, DrivesOneMetreExactlyWithinItsLimits) {
  OccupancyGrid g = make_grid(200, 200, 0.05);  // 10 × 10 m, empty
  const RobotSettings robots[] = {robot_at(1, 2.0, 2.0)};
  PhysicsWorld world(g, robots, PhysicsSettings{});
  world.command(1, {{MotionStep::Drive, 1.0}});
  // Trapezoid: 0.5 s to reach 0.5 m/s (0.125 m), 0.125 m to brake, 0.75 m at 0.5 m/s (1.5 s):
  // 0.5 + 1.5 + 0.5 = 2.5 s in all.
  double top_speed = 0.0;
  for (int k = 0; k < 24; ++k) {
    world.advance(0.1);
    top_speed = std::max(top_speed, world.robot(1).speed);
  }
  EXPECT_TRUE(world.robot(1).busy) << "done before 2.4 s";
  world.advance(0.2);
  EXPECT_FALSE(world.robot(1).busy) << "not done by 2.6 s";
  EXPECT_LE(top_speed, 0.5 + 1e-9);
  EXPECT_NEAR(world.robot(1).pose.x, 3.0, 1e-5);
  EXPECT_NEAR(world.robot(1).pose.y, 2.0, 1e-6);
  EXPECT_NEAR(world.robot(1).odometry.x, 3.0, 1e-5);  // no noise: odometry is the truth
  EXPECT_NEAR(world.robot(1).travelled, 1.0, 1e-5);
}

TEST(Physics, TurnsThenDrivesAsAPlan) {
  OccupancyGrid g = make_grid(200, 200, 0.05);
  const RobotSettings robots[] = {robot_at(1, 5.0, 5.0)};
  PhysicsWorld world(g, robots, PhysicsSettings{});
  // Rotate<π/2>(Move<1>(Robot)): turn left a quarter, then 1 m along +y: (5, 6), heading π/2.
  world.command(1, {{MotionStep::Turn, M_PI / 2}, {MotionStep::Drive, 1.0}});
  world.advance(10.0);
  const RobotState& s = world.robot(1);
  EXPECT_FALSE(s.busy);
  EXPECT_NEAR(s.pose.x, 5.0, 1e-5);
  EXPECT_NEAR(s.pose.y, 6.0, 1e-5);
  // The last tick of a turn brakes within the turn acceleration: it may end past the angle by a
  // fraction of a·dt² (4 rad/s² × (0.01 s)² = 4e-4 rad).
  EXPECT_NEAR(s.pose.theta, M_PI / 2, 1e-4);
  // A turn of 3π/2 more goes round the long way, not wrapped to -π/2: the robot ends facing 0
  // after turning for at least 3π/2 / 1.5 = 3.14 s.
  world.command(1, {{MotionStep::Turn, 3 * M_PI / 2}});
  world.advance(3.1);
  EXPECT_TRUE(world.robot(1).busy);
  world.advance(2.0);
  EXPECT_NEAR(std::remainder(world.robot(1).pose.theta, 2 * M_PI), 0.0, 2e-4);
}

TEST(Physics, StopsAtAWallAndReportsTheCollision) {
  OccupancyGrid g = make_grid(200, 100, 0.05);
  block_column(g, 80);  // a wall whose face is at x = 80 · 0.05 = 4.0 m
  const RobotSettings robots[] = {robot_at(1, 2.0, 2.5)};
  PhysicsWorld world(g, robots, PhysicsSettings{});
  EXPECT_LT(world.wall_shapes(), 10u);
  world.command(1, {{MotionStep::Drive, 5.0}});
  world.advance(15.0);
  const RobotState& s = world.robot(1);
  EXPECT_FALSE(s.busy) << "the plan is given up at the wall";
  EXPECT_NEAR(s.pose.x, 4.0 - 0.2, 0.02);  // touching: centre one radius from the face
  const auto collisions = world.take_collisions();
  ASSERT_GE(collisions.size(), 1u);
  EXPECT_EQ(collisions[0].robot, 1);
  EXPECT_EQ(collisions[0].other, 0);
  EXPECT_TRUE(world.take_collisions().empty());
}

TEST(Physics, AGivenUpDriveIsReportedAgainWhileTheContactLasts) {
  OccupancyGrid g = make_grid(200, 100, 0.05);
  block_column(g, 80);
  const RobotSettings robots[] = {robot_at(1, 2.0, 2.5)};
  PhysicsWorld world(g, robots, PhysicsSettings{});
  world.command(1, {{MotionStep::Drive, 5.0}});
  world.advance(15.0);
  EXPECT_GE(world.take_collisions().size(), 1u);
  // Pressed against the wall, it is told to drive on: the contact never ended, yet the robot
  // hears that this drive is blocked too.
  world.command(1, {{MotionStep::Drive, 1.0}});
  world.advance(2.0);
  const auto again = world.take_collisions();
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].other, 0);
  EXPECT_FALSE(world.robot(1).busy);
}

TEST(Physics, RobotsCollideWithEachOther) {
  OccupancyGrid g = make_grid(200, 100, 0.05);
  const RobotSettings robots[] = {robot_at(1, 2.0, 2.5), robot_at(2, 5.0, 2.5, M_PI)};
  PhysicsWorld world(g, robots, PhysicsSettings{});
  world.command(1, {{MotionStep::Drive, 3.0}});
  world.command(2, {{MotionStep::Drive, 3.0}});
  world.advance(10.0);
  const auto collisions = world.take_collisions();
  bool one_hit_two = false;
  for (const auto& c : collisions) one_hit_two |= c.robot == 1 && c.other == 2;
  EXPECT_TRUE(one_hit_two);
  EXPECT_GE(world.robot(2).pose.x - world.robot(1).pose.x, 0.4 - 0.02);  // never through each other
}

TEST(Physics, NoiseIsSeededAndZeroNoiseIsExact) {
  OccupancyGrid g = make_grid(200, 200, 0.05);
  const RobotSettings robots[] = {robot_at(1, 2.0, 2.0)};
  auto run = [&](double motors, double odometry, std::uint64_t seed) {
    PhysicsSettings s;
    s.noise = NoiseModel{motors, odometry};
    s.seed = seed;
    PhysicsWorld world(g, robots, s);
    world.command(1, {{MotionStep::Drive, 2.0}, {MotionStep::Turn, 1.0}, {MotionStep::Drive, 1.0}});
    world.advance(20.0);
    return world.robot(1);
  };
  const RobotState exact = run(0, 0, 1);
  const RobotState a = run(0.05, 0.05, 1), b = run(0.05, 0.05, 1), c = run(0.05, 0.05, 2);
  EXPECT_EQ(a.pose.x, b.pose.x);
  EXPECT_EQ(a.odometry.y, b.odometry.y);
  EXPECT_NE(a.pose.x, c.pose.x);
  EXPECT_GT(std::hypot(a.pose.x - exact.pose.x, a.pose.y - exact.pose.y), 1e-4);  // motors err
  EXPECT_GT(std::hypot(a.odometry.x - a.pose.x, a.odometry.y - a.pose.y), 1e-5);  // odometry drifts
  // Exact run by hand: (2, 2) + 2 m along 0, turn 1 rad, 1 m along 1 rad.
  EXPECT_NEAR(exact.pose.x, 4.0 + std::cos(1.0), 1e-4);
  EXPECT_NEAR(exact.pose.y, 2.0 + std::sin(1.0), 1e-4);
}

TEST(Physics, BadRobotsAreRefusedWithTheirField) {
  OccupancyGrid g = make_grid(100, 100, 0.05);
  block_column(g, 40);  // x in [2.0, 2.05)
  auto refuse = [&](std::vector<RobotSettings> robots, const std::string& text) {
    try {
      PhysicsWorld world(g, robots, PhysicsSettings{});
      ADD_FAILURE() << "accepted: " << text;
    } catch (const vwg::SchemaError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  refuse({robot_at(1, 2.1, 2.0)}, "inside a wall");
  refuse({robot_at(1, -1.0, 2.0)}, "outside the map");
  refuse({robot_at(1, 1.0, 1.0), robot_at(1, 1.0, 3.0)}, "used twice");
  refuse({robot_at(1, 1.0, 1.0), robot_at(2, 1.1, 1.0)}, "overlaps robot 1");
  RobotSettings slow = robot_at(1, 1.0, 1.0);
  slow.limits.max_speed = 0.0;
  refuse({slow}, "max_speed");
}

/// `count` robots at random poses drawn from `at` for x and y, apart from each other, with radii
/// of 0.1 to 0.25 m; `refused(x, y, radius)` leaves out places (inside walls).
template <class Refused>
std::vector<RobotSettings> random_crowd(std::size_t count, std::uniform_real_distribution<double> at, std::mt19937& rng,
                                        Refused refused) {
  std::uniform_real_distribution<double> turn(-M_PI, M_PI);
  std::vector<RobotSettings> robots;
  while (robots.size() < count) {
    RobotSettings r = robot_at(static_cast<int>(robots.size()) + 1, at(rng), at(rng));
    r.radius = 0.1 + 0.05 * (r.id % 4);
    if (refused(r.start.x, r.start.y, r.radius)) continue;
    r.start.theta = turn(rng);
    const bool apart = std::all_of(robots.begin(), robots.end(), [&](const RobotSettings& o) {
      return std::hypot(o.start.x - r.start.x, o.start.y - r.start.y) > o.radius + r.radius + 0.01;
    });
    if (apart) robots.push_back(r);
  }
  return robots;
}

/// Each robot's scan with the scanner's shortcuts (sorted angles) against the same beams in
/// reverse order, taken back (unsorted: every beam tested against every robot). Returns how many
/// ranges a robot made nearer than the walls.
int expect_shortcuts_change_no_range(const RangeScanner& scanner, const std::vector<RobotSettings>& robots,
                                     const std::vector<double>& angles, double max_range) {
  const double fov = angles.back() - angles.front();
  const std::vector<double> reversed(angles.rbegin(), angles.rend());
  int nearer_than_walls = 0;
  for (const RobotSettings& r : robots) {
    std::vector<float> fast(angles.size()), full(angles.size()), walls(angles.size());
    const Pose2 pose = scanner.world().robot(r.id).pose;
    scanner.scan(r.id, pose, angles, max_range, fast);
    scanner.scan(r.id, pose, reversed, max_range, full);
    scanner.raycaster().scan(pose, angles, max_range, walls);
    for (std::size_t i = 0; i < angles.size(); ++i) {
      EXPECT_EQ(fast[i], full[angles.size() - 1 - i]) << "robot " << r.id << " beam " << i << " fov " << fov;
      if (fast[i] != full[angles.size() - 1 - i]) return nearer_than_walls;
      nearer_than_walls += fast[i] < walls[i];
    }
  }
  return nearer_than_walls;
}

int expect_shortcuts_change_no_range(const RangeScanner& scanner, const std::vector<RobotSettings>& robots,
                                     const LaserSpec& spec) {
  return expect_shortcuts_change_no_range(scanner, robots, beam_angles(spec), spec.max_range);
}

TEST(Physics, RobotsFoundByIdAndDiscsFollowThePosesAfterRemovals) {
  // Robots are looked up by id (not by walking the list) and their discs kept beside their states:
  // both must stay right as robots leave from the middle and the rest move.
  std::vector<RobotSettings> robots;
  for (int k = 0; k < 8; ++k) robots.push_back(robot_at(10 + 3 * k, 1.0 + k, 1.0 + 0.5 * (k % 3)));
  PhysicsWorld world(make_grid(200, 200, 0.05), robots, PhysicsSettings{});
  auto check = [&] {
    ASSERT_EQ(world.discs().size(), world.robots().size());
    for (std::size_t i = 0; i < world.robots().size(); ++i) {
      const RobotState& s = world.robots()[i];
      EXPECT_EQ(&world.robot(s.id), &s);
      EXPECT_EQ(world.find_robot(s.id), &s);
      // The walk of the platform's default finds the same state as the simulator's index.
      EXPECT_EQ(world.vwg::platform::RobotPlatform::find_robot(s.id), &s);
      EXPECT_EQ(world.discs()[i].id, s.id);
      EXPECT_EQ(world.discs()[i].x, s.pose.x);
      EXPECT_EQ(world.discs()[i].y, s.pose.y);
      EXPECT_EQ(world.discs()[i].radius, s.radius);
    }
  };
  for (const RobotSettings& r : robots) world.drive(r.id, 0.4, 0.3);
  world.advance(0.5);
  check();
  world.remove_robot(16);  // the third
  world.remove_robot(10);  // the first
  EXPECT_THROW(world.robot(16), vwg::SchemaError);
  EXPECT_EQ(world.find_robot(16), nullptr);
  EXPECT_EQ(world.vwg::platform::RobotPlatform::find_robot(10), nullptr);
  world.advance(0.5);
  check();
  EXPECT_EQ(world.robots().front().id, 13);
  world.add_robot(robot_at(16, 5.0, 8.0));
  world.advance(0.2);
  check();
  EXPECT_EQ(world.robot(16).pose.y, world.discs().back().y);
}

TEST(RangeScanner, ApproximateBearingIsWithinItsBound) {
  // Abramowitz & Stegun's bound, 1e-5 rad (1.15e-5 with the coefficients as printed), against libm
  // on a million directions and the axes.
  double worst = 0.0;
  for (int k = 0; k <= 1000000; ++k) {
    const double a = -M_PI + 2 * M_PI * k / 1000000.0, radius = 1e-3 + (k % 7) * 3.0;
    const double x = radius * std::cos(a), y = radius * std::sin(a);
    worst = std::max(worst, std::abs(std::remainder(approximate_atan2(y, x) - std::atan2(y, x), 2 * M_PI)));
  }
  EXPECT_LT(worst, 1.2e-5);
  EXPECT_EQ(approximate_atan2(0.0, 0.0), 0.0);
  EXPECT_NEAR(approximate_atan2(0.0, -1.0), M_PI, 1e-5);
  EXPECT_NEAR(approximate_atan2(-1.0, 0.0), -M_PI_2, 1e-5);
}

TEST(RangeScanner, RobotsBehindWallsAreSkippedWithoutChangingARange) {
  // A crowd in a 12 × 12 m floor of 3 × 3 rooms with doors: most robots within reach of a laser
  // are behind a wall, and the scanner skips them without the exact test (beams that can meet
  // them already stop nearer). The ranges must be those of testing every beam against every robot,
  // which it does when the angles are not sorted.
  OccupancyGrid g = make_grid(240, 240, 0.05);
  for (int line = 80; line < 240; line += 80) {
    for (int k = 0; k < 240; ++k) {
      const bool door = k % 80 >= 34 && k % 80 < 46;
      if (door) continue;
      g.data[static_cast<std::size_t>(line) * 240 + k] = 100;  // a wall along a row
      g.data[static_cast<std::size_t>(k) * 240 + line] = 100;  // and one along a column
    }
  }
  std::mt19937 rng(5);
  // Robots may stand against a wall (a wall is the cells [4, 4.05) m and [8, 8.05) m on each axis),
  // where a disc's near side is in front of the wall and its centre not.
  auto in_wall = [](double v, double radius) {
    const double m = std::fmod(v, 4.0);
    return m < 0.05 + radius + 0.01 || m > 4.0 - radius - 0.01;
  };
  const std::vector<RobotSettings> robots = random_crowd(
      120, std::uniform_real_distribution<double>(0.5, 11.5), rng,
      [&](double x, double y, double radius) { return in_wall(x, radius) || in_wall(y, radius); });
  auto world = std::make_shared<PhysicsWorld>(g, robots, PhysicsSettings{});
  const RangeScanner scanner(std::make_shared<GridRaycaster>(g), world);
  int nearer_than_walls = 0;
  for (const double fov : {M_PI / 2, M_PI, 2 * M_PI}) {
    LaserSpec spec;
    spec.beams = fov < M_PI ? 91 : 360;
    spec.fov = fov;
    spec.max_range = 10.0;
    nearer_than_walls += expect_shortcuts_change_no_range(scanner, robots, spec);
  }
  EXPECT_GT(nearer_than_walls, 500) << "robots were seen";

  // Beams not evenly spaced (dense in places, sparse in others, two at one angle), where the
  // scanner's first guess of a beam from the mean spacing is far off and must be settled.
  std::uniform_real_distribution<double> within(-M_PI / 2, M_PI / 2), narrow(0.2, 0.3);
  int uneven_nearer = 0;
  for (int round = 0; round < 3; ++round) {
    std::vector<double> angles;
    for (int k = 0; k < 60; ++k) angles.push_back(within(rng));
    for (int k = 0; k < 60; ++k) angles.push_back(narrow(rng));
    angles.push_back(angles[5]);
    std::sort(angles.begin(), angles.end());
    uneven_nearer += expect_shortcuts_change_no_range(scanner, robots, angles, 10.0);
  }
  EXPECT_GT(uneven_nearer, 100) << "robots were seen";
}

TEST(RangeScanner, SkippingRobotsOutOfReachChangesNoRange) {
  // A crowd in an open 10 × 10 m room. The scanner's shortcuts (far robots by squared distance,
  // robots behind a scan of at most half a turn, only the beams a disc subtends) must give the
  // ranges of testing every beam against every robot, which it does when the angles are not
  // sorted: each scan is compared with the same beams in reverse order, taken back.
  OccupancyGrid g = make_grid(200, 200, 0.05);
  std::mt19937 rng(3);
  const std::vector<RobotSettings> robots =
      random_crowd(60, std::uniform_real_distribution<double>(0.6, 9.4), rng, [](double, double, double) { return false; });
  auto world = std::make_shared<PhysicsWorld>(g, robots, PhysicsSettings{});
  const RangeScanner scanner(std::make_shared<GridRaycaster>(g), world);
  int nearer_than_walls = 0;
  for (const double fov : {M_PI / 3, M_PI, 1.5 * M_PI, 2 * M_PI}) {
    for (const double range : {1.5, 4.0, 12.0}) {
      LaserSpec spec;
      spec.beams = 181;
      spec.fov = fov;
      spec.max_range = range;
      nearer_than_walls += expect_shortcuts_change_no_range(scanner, robots, spec);
    }
  }
  EXPECT_GT(nearer_than_walls, 1000) << "robots were seen";
}

TEST(DiscIndex, NearVisitsEveryDiscWithinReachOnceAndFewBeyond) {
  // Against a walk over every disc: each disc whose centre is within `reach` of the query on both
  // axes is visited exactly once; discs far beyond the squares around the query are not. Among
  // the discs: two at one point, one at a point that is not finite, and (second round) a spread
  // so wide that the squares must grow past kSquare to keep their table small.
  std::mt19937 rng(11);
  for (const double spread : {60.0, 3e7}) {
    std::uniform_real_distribution<double> at(-spread / 2, spread / 2), reach_of(0.0, 12.0);
    std::vector<Disc> discs;
    for (int k = 0; k < 3000; ++k) discs.push_back({at(rng), at(rng), 0.1 + 0.05 * (k % 4), k + 1});
    discs.push_back({discs[7].x, discs[7].y, 0.2, 9001});
    discs.push_back({std::nan(""), 1.0, 0.2, 9002});
    DiscIndex index;
    index.rebuild(discs);
    EXPECT_EQ(index.max_radius(), 0.25);
    EXPECT_LE(index.squares(), 3 * 4 * discs.size() + 1) << "the table stays small however far the discs spread";
    if (spread < 100) {
      EXPECT_EQ(index.side(), DiscIndex::kSquare);
    }
    for (int q = 0; q < 300; ++q) {
      const double x = q == 0 ? discs[7].x : at(rng), y = q == 0 ? discs[7].y : at(rng);
      const double reach = q == 0 ? 0.0 : reach_of(rng);
      std::vector<int> visits(discs.size(), 0);
      index.near(x, y, reach, [&](std::uint32_t i) { ++visits[i]; });
      const double side = index.side();
      for (std::size_t i = 0; i < discs.size(); ++i) {
        const double dx = std::abs(discs[i].x - x), dy = std::abs(discs[i].y - y);
        ASSERT_LE(visits[i], 1) << "disc " << i;
        if (dx <= reach && dy <= reach) {
          ASSERT_EQ(visits[i], 1) << "disc " << i << " query " << q;
        }
        // Beyond the query's squares by a whole square on an axis: never visited.
        if (dx > reach + 2 * side || dy > reach + 2 * side) {
          ASSERT_EQ(visits[i], 0) << "disc " << i << " query " << q;
        }
      }
      if (q == 0) {
        EXPECT_EQ(visits[7] + visits[3000], 2) << "two discs at one point";
      }
      // A box of unequal sides about the query point (a scan's half-plane): the same rules.
      const double left = reach_of(rng), right = reach_of(rng), below = reach_of(rng), above = reach_of(rng);
      std::fill(visits.begin(), visits.end(), 0);
      index.within(x - left, x + right, y - below, y + above, [&](std::uint32_t i) { ++visits[i]; });
      for (std::size_t i = 0; i < discs.size(); ++i) {
        const double dx = discs[i].x - x, dy = discs[i].y - y;
        ASSERT_LE(visits[i], 1) << "disc " << i;
        if (dx >= -left && dx <= right && dy >= -below && dy <= above) {
          ASSERT_EQ(visits[i], 1) << "disc " << i << " box " << q;
        }
        if (dx < -left - 2 * side || dx > right + 2 * side || dy < -below - 2 * side || dy > above + 2 * side) {
          ASSERT_EQ(visits[i], 0) << "disc " << i << " box " << q;
        }
      }
    }
  }
  DiscIndex empty;
  empty.rebuild({});
  int visited = 0;
  empty.near(0.0, 0.0, 1e9, [&](std::uint32_t) { ++visited; });
  EXPECT_EQ(visited, 0);
}

TEST(RangeScanner, ACrowdOnALargeFloorGivesTheRangesOfEveryBeamAgainstEveryRobot) {
  // 500 robots on an open 30 × 30 m floor with a 4 m laser: most robots are squares of the floor
  // away, and the scanner looks only at those near. Each range must equal the one worked out here
  // from the walls' range and every other robot's disc (the nearest point in front of the sensor
  // where the beam's line meets the disc, with the scanner's arithmetic).
  OccupancyGrid g = make_grid(600, 600, 0.05);
  std::mt19937 rng(7);
  const std::vector<RobotSettings> robots =
      random_crowd(500, std::uniform_real_distribution<double>(0.5, 29.5), rng, [](double, double, double) { return false; });
  auto world = std::make_shared<PhysicsWorld>(g, robots, PhysicsSettings{});
  for (const RobotSettings& r : robots) world->drive(r.id, 0.3, 0.5);
  world->advance(0.5);  // the index follows the robots as they move
  const RangeScanner scanner(std::make_shared<GridRaycaster>(g), world);
  LaserSpec spec;
  spec.beams = 181;
  spec.fov = M_PI;
  spec.max_range = 4.0;
  const std::vector<double> angles = beam_angles(spec);
  int nearer_than_walls = 0;
  for (const RobotState& me : world->robots()) {
    std::vector<float> got(angles.size()), want(angles.size());
    scanner.scan(me.id, me.pose, angles, spec.max_range, got);
    scanner.raycaster().scan(me.pose, angles, spec.max_range, want);
    // The beams' directions with the scanner's sine and cosine (the raycaster's).
    std::vector<double> turned(angles.size()), cos_a(angles.size()), sin_a(angles.size());
    for (std::size_t i = 0; i < angles.size(); ++i) turned[i] = me.pose.theta + angles[i];
    beam_directions(turned, "avx2", cos_a, sin_a);
    for (std::size_t i = 0; i < angles.size(); ++i) {
      const double dx = cos_a[i], dy = sin_a[i];
      const float walls = want[i];
      for (const RobotState& other : world->robots()) {
        if (other.id == me.id) continue;
        const double cx = other.pose.x - me.pose.x, cy = other.pose.y - me.pose.y, r2 = other.radius * other.radius;
        const double along = cx * dx + cy * dy, across2 = cx * cx + cy * cy - along * along;
        if (across2 > r2) continue;
        const double t = along - std::sqrt(r2 - across2);
        if (t >= 0.0 && t < want[i]) want[i] = static_cast<float>(t);
      }
      ASSERT_EQ(got[i], want[i]) << "robot " << me.id << " beam " << i;
      nearer_than_walls += want[i] < walls;
    }
  }
  EXPECT_GT(nearer_than_walls, 3000) << "robots were seen";
}
