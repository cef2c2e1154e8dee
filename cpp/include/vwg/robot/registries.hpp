// The case study's deciders by name (vwg/registry.hpp), the built-in ones registered on first use.
// A third party adds its own with add(); the Python package's registry (vwg.registry) starts from
// these names. The platforms and sensors the simulator provides are registered beside it
// (vwg/sim/registries.hpp), so that a robot program needs no simulator.
#pragma once

#include "vwg/registry.hpp"
#include "vwg/robot/decider.hpp"

namespace vwg::robot {

/// Deciders by name: random, astar, jps (Jump Point Search), dstar, and the OMPL planners rrtconnect, rrtstar and prm
/// (LazyPRM), bounded by iterations so that a run is the same on any machine.
Registry<Decider>& deciders();

}  // namespace vwg::robot
