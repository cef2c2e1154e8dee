// What a robot knows of the robots and people around it from its own scans (not the simulator's truth), for
// reciprocal avoidance (vwg/robot/orca.hpp): the compact pieces of a scan that stand out in front of what is
// behind them, tracked from scan to scan into positions and velocities. Walls are long pieces and are left out.
//
// A piece is a run of consecutive returns, each within `jump` of the last (a beam with no return ends it). It
// is kept when it is at most `max_width` across and the beams beside it reach at least `jump` further (or
// nothing): something in front. Its width is from its first to its last return plus one beam's spacing at its
// range (each end is within half a spacing of an edge); its radius is half that (clamped to [min_radius,
// max_radius]), its centre
// one radius beyond its nearest return along that beam (a disc's nearest point lies on the line to its centre).
// Each piece is matched, in scan order, to the nearest track within `gate` not yet matched; the track's velocity
// follows the piece's displacement (an exponential average, weight `smoothing`); a piece with no track starts
// one at rest; a track not seen for `forget` seconds is dropped.
#pragma once

#include <concepts>
#include <string>
#include <type_traits>
#include <vector>

#include "vwg/geometry/pose.hpp"
#include "vwg/platform/scan_source.hpp"
#include "vwg/state.hpp"

namespace vwg::platform {

struct NeighbourSettings {
  double jump = 0.25;        ///< metres between consecutive returns of one piece, and in front of its sides
  double max_width = 0.9;    ///< metres: wider pieces are walls
  double min_radius = 0.1;   ///< metres
  double max_radius = 0.4;   ///< metres
  double gate = 0.4;         ///< metres a piece may be from the track it continues
  double smoothing = 0.5;    ///< weight of the newest displacement in a track's velocity
  double forget = 0.5;       ///< seconds a track lives unseen
};

template <class S, class F>
  requires std::same_as<std::remove_const_t<S>, NeighbourSettings>
void visit_settings(S& s, F&& field) {
  field("jump", s.jump, "metres between consecutive returns of one piece, and in front of its sides");
  field("max_width", s.max_width, "metres: wider pieces are walls");
  field("min_radius", s.min_radius, "metres");
  field("max_radius", s.max_radius, "metres");
  field("gate", s.gate, "metres a piece may be from the track it continues");
  field("smoothing", s.smoothing, "weight of the newest displacement in a track's velocity");
  field("forget", s.forget, "seconds a track lives unseen");
}

/// Throws SchemaError naming `owner.field` for a value that is not finite and > 0 (smoothing: in (0, 1]), or a
/// min_radius above max_radius.
void check_settings(const NeighbourSettings& s, const std::string& owner);

struct Neighbour {
  int id = 0;  ///< the track's number (from 1, in the order tracks began)
  double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0, radius = 0.0;
  double seen = 0.0;  ///< when it was last seen, seconds
};

class NeighbourTracker {
 public:
  explicit NeighbourTracker(NeighbourSettings settings = {});
  /// The scan taken from `pose` (world frame) at `time` seconds (later than the last scan's).
  void update(const ScanView& scan, const geometry::Pose2& pose, double time);
  const std::vector<Neighbour>& neighbours() const { return tracks_; }
  /// The tracks and the next track number (a saved run).
  void save(StateWriter& out) const;
  /// Back to what save() wrote; throws SchemaError (through `in`) for a damaged state.
  void load(StateReader& in);

 private:
  NeighbourSettings settings_;
  std::vector<Neighbour> tracks_;
  int next_id_ = 1;
};

}  // namespace vwg::platform
