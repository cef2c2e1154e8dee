// People who walk (robots in a living world): actors of the string that move by the social force model
// (Helbing and Molnár, "Social force model for pedestrian dynamics", Phys. Rev. E 51, 1995), with bodies on the
// simulator that robots touch and sensors see. In the model:
//
//   Person<id, x, y, vx, vy, radius, speed, goals, loop, wander, leg, way, stuck, rest>
//   gSocial       eSocial<to=person, fx, fy>: the repulsion of the others near each person (people and robots,
//                 where the simulator has them) and of the walls, as accelerations
//   λ(eSocial)    the person's own pull toward its way (v0·e − v)/τ plus the repulsion, integrated over the
//                 frame; at the end of a leg, the next waypoint (in turn, looping or not) or, wandering, a room
//                 drawn from the seed; each leg's way is A* on the map grown by the person's radius, walked
//                 toward its farthest point within 2 m in plain sight (a disc of the person's radius clears the walls)
//   θ(eExecute)   Pedestrian<id, x, y, vx, vy, radius>, which the people's backend puts on the simulator
//
// The repulsion of another at distance d (centres), radii summing to r, is A·exp((r − d)/B) along the line
// from it; of a wall at clearance d, A_w·exp((radius − d)/B_w) away from it (the clearance's gradient).
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "vwg/actor.hpp"
#include "vwg/alphabet.hpp"
#include "vwg/backend.hpp"
#include "vwg/generator.hpp"
#include "vwg/geometry/blocked_grid.hpp"
#include "vwg/geometry/clearance_field.hpp"
#include "vwg/geometry/map_geometry.hpp"
#include "vwg/geometry/occupancy_grid.hpp"
#include "vwg/sim/physics.hpp"

namespace vwg::sim {

struct SocialForceSettings {
  double relaxation = 0.5;      ///< τ, seconds: how fast a person takes its desired velocity
  double people_strength = 2.1; ///< A, m/s²: another person's push at contact
  double people_range = 0.3;    ///< B, metres: how fast it falls off
  double robot_strength = 3.0;  ///< A for a robot (people give robots more room)
  double robot_range = 0.5;     ///< B for a robot
  double sidestep = 0.5;        ///< share of a push ahead of a person that also turns it to its right (keep right)
  double wall_strength = 5.0;   ///< A_w, m/s²
  double wall_range = 0.1;      ///< B_w, metres
  double reach = 3.0;           ///< metres: others and walls farther than this are left out
  double max_speed = 1.3;       ///< the fastest a person goes, as a multiple of its walking speed
  double arrive = 0.4;          ///< metres: a point of the way is passed this close
  double give_up = 3.0;         ///< seconds all but stopped (under a tenth of its speed) before a person walks on elsewhere; and
                                ///< seconds it stands after finding no way to a goal before it tries its next
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, SocialForceSettings>
void visit_settings(S& s, F&& field) {
  field("relaxation", s.relaxation, "seconds: how fast a person takes its desired velocity (tau)");
  field("people_strength", s.people_strength, "m/s^2: another person's push at contact (A)");
  field("people_range", s.people_range, "metres: how fast it falls off (B)");
  field("robot_strength", s.robot_strength, "m/s^2: a robot's push at contact");
  field("robot_range", s.robot_range, "metres: how fast a robot's push falls off");
  field("sidestep", s.sidestep, "share of a push ahead of a person that also turns it to its right (keep right)");
  field("wall_strength", s.wall_strength, "m/s^2: a wall's push at contact");
  field("wall_range", s.wall_range, "metres: how fast a wall's push falls off");
  field("reach", s.reach, "metres: others and walls farther than this are left out");
  field("max_speed", s.max_speed, "the fastest a person goes, as a multiple of its walking speed");
  field("arrive", s.arrive, "metres: a point of the way is passed this close");
  field("give_up", s.give_up,
        "seconds all but stopped before a person leaves its way for its next goal, and seconds it stands after finding "
        "no way to a goal before it tries the next");
}

/// Throws SchemaError naming `owner.field` for a value that is not finite and > 0 (max_speed: >= 1).
void check_settings(const SocialForceSettings& s, const std::string& owner);

struct Vec {
  double x = 0.0, y = 0.0;
};

/// The push of one other disc (a person or a robot) at (ox, oy) of radius `other_radius` on a person at (x, y):
/// strength·exp((radius + other_radius − d)/range) along the line from the other; none beyond `reach`.
Vec push_of(double x, double y, double radius, double ox, double oy, double other_radius, double strength, double range,
            double reach);

/// The social force of a frame (the repulsion of the people and robots of `discs`, less the person itself, id
/// −person, and of the walls of `walls`): what gSocial sends.
Vec repulsion(const PhysicsWorld::Person& person, std::span<const Disc> discs, const geometry::ClearanceField& walls,
              const OccupancyGrid& map, const SocialForceSettings& s);

/// The Person actor type's attributes (register it with them).
Schema person_attributes();
enum PersonAttr : std::size_t { kPersonId, kPx, kPy, kPvx, kPvy, kPradius, kPspeed, kGoals, kLoop, kWander, kLeg, kWay, kStuck, kRest };

/// λ and θ of Person (see the top of this file). `map` is the world's true map (people know their building).
class PersonBehavior final : public ActorBehavior {
 public:
  PersonBehavior(const Alphabet& alphabet, const OccupancyGrid& map, SocialForceSettings settings, double dt,
                 double largest_radius);
  void evolve(ActorState& self, const EventView& e, const EvolutionContext& ctx, Replacement& out) override;
  void visualize(const ActorState& self, const EventView& e, const EvolutionContext& ctx, StringBuilder& out) override;
  /// Each person's λ reads only its own state and its event; the A* searches are per thread.
  bool concurrent() const override { return true; }

 private:
  /// The way from where the person is to the goal of its leg (world points), or none.
  std::vector<double> route(double x, double y, double gx, double gy) const;

  geometry::MapGeometry geometry_;
  OccupancyGrid map_;
  geometry::ClearanceField walls_;
  geometry::BlockedGrid grown_;  ///< the map grown by the largest person's radius
  SocialForceSettings settings_;
  double dt_;
  EventTypeId social_, execute_;
  SymbolId pedestrian_;
};

/// gSocial: eSocial<to=person, fx, fy> for every person of the simulator, from where the simulator has the
/// people and robots when the frame begins.
class SocialForceGenerator final : public Generator {
 public:
  SocialForceGenerator(std::shared_ptr<const PhysicsWorld> world, SocialForceSettings settings, const Alphabet& alphabet,
                       const std::string& event = "eSocial");
  void generate(const FrameInfo& frame, EventList& out) override;
  std::string name() const override { return "social force"; }
  /// Nothing of its own: it reads the simulator.
  void save_state(StateWriter&) const override {}
  void load_state(StateReader& in) override { in.end(); }

 private:
  std::shared_ptr<const PhysicsWorld> world_;
  SocialForceSettings settings_;
  EventTypeId event_;
  geometry::ClearanceField walls_;
};

/// φ of Pedestrian<id, x, y, vx, vy, radius>: the person's body on the simulator, there and moving so.
class PeopleBackend final : public Backend {
 public:
  PeopleBackend(std::shared_ptr<PhysicsWorld> world, const Alphabet& alphabet);
  void primitive(const NodeView& p) override;
  void open(const NodeView&) override {}
  void close(const NodeView&) override {}
  std::string name() const override { return "people (sim)"; }

 private:
  std::shared_ptr<PhysicsWorld> world_;
  SymbolId pedestrian_;
};

}  // namespace vwg::sim
