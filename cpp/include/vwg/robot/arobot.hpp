// ARobot, the actor of the case study (paper eq. 11-13):
//
//   ARobot<grid, row, column, angle, objective, action> responding to eLaser, eCamera, eDecide,
//   eExecute, eObjective
//
// with, beside the paper's attributes: `id` (several robots share a world, and events are
// addressed to one), the continuous pose belief `x, y` (row and column are its cell), the plan
// `path`, and the bookkeeping of its motion commands, arrival, replans and collisions. The action
// is held as numbers (`acting`, `turn`, `move`), so θ builds it from symbol ids. It also responds
// to eOdometry and eCollision, the platform's feedback (simulator or real robot).
//
//   λ(eLaser<dist, angle>)   marks the obstacle at (x + dist·cos(angle₀ + angle), ...) in the grid
//                            and clears the cells the beam crossed (moving obstacles leave)
//   λ(eCamera<marker, dist, angle>)  marks the marker's cell (eq. 12)
//   λ(eObjective<marker>)    sets the objective
//   λ(eOdometry<x, y, angle, busy, commands>)  updates the pose belief and what the motors did
//   λ(eDecide)               when the last command is done: the Decider's next motion (turn a,
//                            move d); the belief moves on. A robot with `avoid` set decides every
//                            frame: the Decider's next step as a preferred velocity, made safe for
//                            the neighbours of the frame by ORCA (vwg/robot/avoidance.hpp), shown as
//                            Velocity<speed, turn_rate>(Robot<id>)
//   λ(eNeighbour<x, y, vx, vy, radius>)  the robots and people its laser sees this frame (its frame); an
//                            avoiding robot's λ(eLaser) marks no cell for a return off one of them
//   θ(eExecute)              Rotate<a>(Move<d>(Robot<id>)) (or Robot<id>, drawn and not moved),
//                            with Path<id, points> and Status<id, text> when the alphabet has them
#pragma once

#include <concepts>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <string>
#include <type_traits>
#include <utility>

#include "vwg/actor.hpp"
#include "vwg/alphabet.hpp"
#include "vwg/robot/avoidance.hpp"
#include "vwg/robot/decider.hpp"
#include "vwg/robot/robot_map.hpp"

namespace vwg::robot {

struct ARobotConfig {
  geometry::MapGeometry map;               ///< geometry of the robots' grids (that of the world map)
  double radius = platform::kDefaultRobotRadius;  ///< metres
  double margin = 0.07;          ///< extra clearance kept from obstacles when moving, metres
  double goal_tolerance = 0.25;  ///< arrived when the belief is this close to the goal, metres
  double step_length = 1.0;      ///< longest straight move per decision, metres
  double marker_goal_distance = 1.0;  ///< where to stand in front of a marker known only from the camera
  /// The rooms the robot knows: marker id -> where to stand. Markers it does not know are found
  /// with the camera (then it stands marker_goal_distance in front of them).
  std::map<int, std::pair<double, double>> rooms;
  bool carve_free_space = true;  ///< clear reported obstacles along laser beams
  int retry_frames = 10;         ///< after finding no way (another robot in it?), decisions to skip before trying again
  /// Avoiding robots (attribute `avoid`): the speed and turn limits ORCA keeps to (the slowest robot's), and
  /// its settings.
  platform::RobotLimits limits;
  AvoidanceSettings avoidance;
};

/// The settings among ARobotConfig's fields (vwg._core.ARobotConfig through the settings binder:
/// the defaults a world file and the Python side start from); `map` and `rooms` come from the world.
template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, ARobotConfig>
void visit_settings(S& s, F&& field) {
  field("radius", s.radius, "metres");
  field("margin", s.margin, "extra clearance kept from obstacles when moving, metres");
  field("goal_tolerance", s.goal_tolerance, "arrived when the belief is this close to the goal, metres");
  field("step_length", s.step_length, "longest straight move per decision, metres");
  field("marker_goal_distance", s.marker_goal_distance, "where to stand in front of a marker known only from the camera, metres");
  field("carve_free_space", s.carve_free_space, "clear reported obstacles along laser beams");
  field("retry_frames", s.retry_frames, "decisions to skip after finding no way before trying again");
}

/// Throws SchemaError naming `owner.field`: a radius, goal tolerance, step length or marker goal
/// distance that is not finite and > 0, a negative or non-finite margin, negative retry frames.
void check_settings(const ARobotConfig& config, const std::string& owner);

/// The attribute schema of ARobot (register the actor type with it).
Schema arobot_attributes();
/// The event types ARobot responds to, in the paper's order (eLaser, eCamera, eDecide, eExecute,
/// eObjective) and then eOdometry, eCollision, eNeighbour.
std::vector<std::string> arobot_events();
/// The events' fields, as the alphabet must declare them.
std::vector<std::pair<std::string, Schema>> arobot_event_types();

/// Attribute indices of ARobot (the order of arobot_attributes()).
enum ARobotAttr : std::size_t {
  kId, kGrid, kRow, kColumn, kAngle, kObjective, kActing, kTurn, kMove, kX, kY, kPath, kSent, kAcked, kBusy, kReached, kReplans,
  kCollisions, kStatus, kWait, kAvoid, kNeighbours, kSensed, kSpeed, kTurnRate
};

class ARobot final : public ActorBehavior {
 public:
  /// `alphabet` must have the events of arobot_event_types() and the symbols Robot, Move, Rotate.
  ARobot(const Alphabet& alphabet, ARobotConfig config, std::shared_ptr<Decider> decider);

  void evolve(ActorState& self, const EventView& e, const EvolutionContext& ctx, Replacement& out) override;
  /// Robots evolve side by side when their decider allows it (A*, D* Lite, random: yes).
  bool concurrent() const override { return decider_->concurrent(); }
  void visualize(const ActorState& self, const EventView& e, const EvolutionContext& ctx, StringBuilder& out) override;
  /// A laser scan (the eLaser events of a frame, one a beam) is taken a run at a time: one edit of
  /// the map for all its beams (sense_scan: the same map as one beam at a time).
  bool takes_runs(EventTypeId type) const override { return type == ev_.laser; }
  void evolve_run(ActorState& self, const EventList& events, std::span<const std::uint32_t> at, const EvolutionContext& ctx,
                  Replacement& out) override;

  /// Its decider's state; the obstacle bits are a cache of each robot's map, made again from it.
  void save_state(StateWriter& out) const override { decider_->save_state(out); }
  void load_state(StateReader& in) override { decider_->load_state(in); }

  const ARobotConfig& config() const { return config_; }
  Decider& decider() { return *decider_; }

 private:
  void decide(ActorState& self, const EvolutionContext& ctx);
  /// The decider's next step from the belief to (gx, gy), its replans counted.
  Decision consult(ActorState& self, const EvolutionContext& ctx, double gx, double gy);
  /// decide() for a robot that avoids: every frame, the velocity of steer().
  void decide_avoiding(ActorState& self, const EvolutionContext& ctx);
  /// The velocity of steer() toward `heading` at `speed` (0: stay, giving way to neighbours), shown.
  void avoid(ActorState& self, const EvolutionContext& ctx, double heading, double speed);
  /// An avoiding robot that finds no way forgets the obstacles its sensors reported (the prior map's walls stay):
  /// a robot or person it could not tell from a wall may have moved on; the next scan marks again what is still
  /// there in sight.
  void forget_seen(ActorState& self);
  /// Show Velocity<speed, turn_rate> from the next frame (stopping: zeros).
  void set_velocity(ActorState& self, double speed, double turn_rate);
  /// Where beam eLaser<dist, angle> stopped, and the point whose cell it marks (eq. 12); cos_a
  /// and sin_a are of the beam's direction in the world (its angle plus the robot's heading), from
  /// vwg's own sine and cosine (geometry::beam_directions: the same bits on every machine, for one
  /// beam or a scan's run of them).
  ScanBeam beam(const ActorState& self, double dist, double cos_a, double sin_a) const;
  bool goal_of(const ActorState& self, int marker, double& x, double& y) const;
  /// A robot that avoids keeps its map for what stays: the returns off this frame's neighbours (robots and
  /// people, which ORCA avoids as they move) mark no cell (their beams still clear the way to them).
  void unmark_neighbours(const ActorState& self, const EvolutionContext& ctx, std::span<ScanBeam> scan) const;
  /// This frame's eNeighbour rows, from the robot's frame into the world's (none when it saw none this frame).
  void neighbours_in_world(const ActorState& self, const EvolutionContext& ctx, std::vector<orca::Neighbour>& out) const;

  /// Run `edit(map, bits)` on the robot's map (in place when the engine allows it) and its
  /// ObstacleBits, made valid for the map before and kept valid after.
  template <class Edit>
  void edit_map(ActorState& self, Edit&& edit) {
    MapEdit map = self.edit_blob<std::int16_t>(kGrid);
    ObstacleBits& bits = bits_of(self.get_int(kId));
    bits.sync(map.blob(), config_.map);
    edit(map, bits);
    bits.keep(map.blob());
    // A robot that saw others pass keeps no page of them within kReshareEvery edits of their going
    // (memory stays flat).
    if (bits.reshare_due_after_edit()) {
      map.reshare();
      bits.reshare();
    }
  }

  ARobotConfig config_;
  std::shared_ptr<Decider> decider_;
  ObstacleBits& bits_of(std::int64_t robot);

  // Per robot id: its map's obstacles as bits (a cache of the map, checked against its revision;
  // see ObstacleBits). Robots evolve on several threads: the table is guarded, each robot's entry
  // is its own.
  std::mutex bits_mutex_;
  std::unordered_map<std::int64_t, ObstacleBits> bits_;  // node-based: entries stay where they are
  std::uint64_t serial_;  // this ARobot among all made in the process (bits_of's per-thread cache)
  struct Events {
    EventTypeId laser, camera, decide, execute, objective, odometry, collision, neighbour;
  } ev_{};
  struct Symbols {
    SymbolId robot, move, rotate;
    std::optional<SymbolId> path, status;  // shown with the action when the alphabet has them
    std::optional<SymbolId> velocity;      // an avoiding robot's action
  } sym_{};
};

}  // namespace vwg::robot
