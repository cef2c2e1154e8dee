// Reciprocal avoidance in vwg._core: the generator of each robot's neighbours (what its laser sees of the robots
// and people around it) and the steering of an avoiding robot (vwg/robot/avoidance.hpp).
#include <memory>
#include <string>
#include <vector>

#include "common.hpp"
#include "vwg/robot/avoidance.hpp"
#include "vwg/sim/laser.hpp"

namespace vwg::bindings {

void init_avoidance(py::module_& m) {
  py::class_<robot::NeighbourGenerator, Generator, std::shared_ptr<robot::NeighbourGenerator>>(m, "NeighbourGenerator", R"doc(
gNeighbours for one robot: each frame eNeighbour<to=robot, x, y, vx, vy, radius> for each robot or person its
laser's scans show (compact pieces in front of what is behind them, tracked from scan to scan), in the robot's
own frame (x ahead, y to the left), moved on to the frame's time (vwg/robot/avoidance.hpp).)doc")
      .def(py::init([](std::shared_ptr<platform::RobotPlatform> platform, std::shared_ptr<sim::LaserGenerator> laser,
                       const platform::NeighbourSettings& settings, const Alphabet& alphabet, const std::string& event) {
             return std::make_shared<robot::NeighbourGenerator>(std::move(platform), std::move(laser), settings, alphabet,
                                                                event);
           }),
           py::arg("platform"), py::arg("laser"), py::arg("settings"), py::arg("alphabet"), py::arg("event") = "eNeighbour")
      .def_property_readonly("robot", &robot::NeighbourGenerator::robot)
      .def_property_readonly("neighbours", [](const robot::NeighbourGenerator& g) {
        py::list out;
        for (const platform::Neighbour& n : g.tracker().neighbours()) {
          out.append(py::dict(py::arg("id") = n.id, py::arg("x") = n.x, py::arg("y") = n.y, py::arg("vx") = n.vx,
                              py::arg("vy") = n.vy, py::arg("radius") = n.radius, py::arg("seen") = n.seen));
        }
        return out;
      }, "The tracks, in the odometry's world frame: [{id, x, y, vx, vy, radius, seen}].");

  m.def("steer", [](std::tuple<double, double, double> pose, double speed, double radius, const platform::RobotSettings& robot,
                    double preferred_heading, double preferred_speed,
                    const std::vector<std::tuple<double, double, double, double, double>>& neighbours,
                    const robot::AvoidanceSettings& settings) {
    std::vector<robot::orca::Neighbour> ns;
    for (const auto& [x, y, vx, vy, r] : neighbours) ns.push_back({{x, y}, {vx, vy}, r, 0.5});
    robot::SteerInput in;
    in.pose = {std::get<0>(pose), std::get<1>(pose), std::get<2>(pose)};
    in.speed = speed;
    in.radius = radius;
    in.limits = robot.limits;
    in.preferred_heading = preferred_heading;
    in.preferred_speed = preferred_speed;
    in.neighbours = ns;
    const platform::Velocity v = robot::steer(in, settings);
    return py::make_tuple(v.speed, v.turn_rate);
  }, py::arg("pose"), py::arg("speed"), py::arg("radius"), py::arg("robot"), py::arg("preferred_heading"),
     py::arg("preferred_speed"), py::arg("neighbours"), py::arg("settings"),
     R"doc((speed, turn_rate) of an avoiding robot at `pose` driving at `speed`, of `radius` and `robot`'s limits,
that would go `preferred_speed` toward `preferred_heading`, with neighbours (x, y, vx, vy, radius) in the world
frame, each avoiding too.)doc");
}

}  // namespace vwg::bindings
