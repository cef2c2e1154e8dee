// Monte Carlo localization in vwg._core: the likelihood field, the particle filter and the generator that
// sends each robot its estimated pose as eOdometry (vwg/robot/localization.hpp).
#include <memory>
#include <string>

#include "common.hpp"
#include "vwg/robot/localization.hpp"
#include "vwg/sim/laser.hpp"

namespace vwg::bindings {

namespace {

py::array_t<double> particles_array(const robot::ParticleFilter& f) {
  const auto& ps = f.particles();
  py::array_t<double> out({static_cast<py::ssize_t>(ps.size()), py::ssize_t{4}});
  auto view = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < static_cast<py::ssize_t>(ps.size()); ++i) {
    const robot::Particle& p = ps[static_cast<std::size_t>(i)];
    view(i, 0) = p.x, view(i, 1) = p.y, view(i, 2) = p.theta, view(i, 3) = p.weight;
  }
  return out;
}

py::tuple pose_tuple(const geometry::Pose2& p) { return py::make_tuple(p.x, p.y, p.theta); }

}  // namespace

void init_localization(py::module_& m) {
  m.def("kld_bound", &robot::kld_bound, py::arg("bins"), py::arg("err"), py::arg("z"),
        "KLD-sampling's bound (Fox 2003): the particles needed for `bins` occupied histogram bins.");
  py::class_<robot::LikelihoodField, std::shared_ptr<robot::LikelihoodField>>(m, "LikelihoodField", R"doc(
The likelihood field of a map for a laser of range ``max_range``: ``pz(x, y)`` = z_hit·exp(−d²/(2σ²)) +
z_rand/max_range, d the distance from the point to the centre of the nearest occupied cell (value >= 50),
capped at max_dist (off the map: max_dist).)doc")
      .def(py::init<const geometry::OccupancyGrid&, const robot::LocalizationSettings&, double>(), py::arg("map"),
           py::arg("settings"), py::arg("max_range"))
      .def("pz", &robot::LikelihoodField::pz, py::arg("x"), py::arg("y"))
      .def("distance", &robot::LikelihoodField::distance, py::arg("x"), py::arg("y"),
           "d (metres, capped) for the point, as the field holds it.");

  py::class_<robot::ParticleFilter>(m, "ParticleFilter", R"doc(
A particle filter of one robot's pose (Probabilistic Robotics, ch. 8): ``start`` around a pose, ``predict``
by an odometry motion, ``weigh`` on a scan against a LikelihoodField (amcl's 1 + Σ pz³), ``resample``
(low variance) and ``estimate``. The random streams are vwg.Rng-like seeds: the same seed, the same particles.)doc")
      .def(py::init([](const robot::LocalizationSettings& settings) { return robot::ParticleFilter(settings); }),
           py::arg("settings"))
      .def("start", [](robot::ParticleFilter& f, std::tuple<double, double, double> pose, std::uint64_t seed) {
        Rng rng(seed);
        f.start({std::get<0>(pose), std::get<1>(pose), std::get<2>(pose)}, rng);
      }, py::arg("pose"), py::arg("seed"), "Particles around pose (x, y, angle), drawn from `seed`.")
      .def("predict", [](robot::ParticleFilter& f, std::tuple<double, double, double> from,
                         std::tuple<double, double, double> to, std::uint64_t seed) {
        Rng rng(seed);
        f.predict({std::get<0>(from), std::get<1>(from), std::get<2>(from)}, {std::get<0>(to), std::get<1>(to), std::get<2>(to)},
                  rng);
      }, py::arg("odometry_from"), py::arg("odometry_to"), py::arg("seed"), "Move the particles by this odometry motion.")
      .def("weigh", [](robot::ParticleFilter& f, py::array_t<float, py::array::c_style | py::array::forcecast> ranges,
                       py::array_t<double, py::array::c_style | py::array::forcecast> angles, double max_range,
                       const robot::LikelihoodField& field) {
        if (ranges.ndim() != 1 || angles.ndim() != 1 || ranges.shape(0) != angles.shape(0)) {
          throw SchemaError("weigh", "expected ranges and angles of one length");
        }
        const platform::ScanView scan{{ranges.data(), static_cast<std::size_t>(ranges.shape(0))},
                                      {angles.data(), static_cast<std::size_t>(angles.shape(0))}, max_range};
        f.weigh(scan, field);
      }, py::arg("ranges"), py::arg("angles"), py::arg("max_range"), py::arg("field"))
      .def("resample", [](robot::ParticleFilter& f, std::uint64_t seed) {
        Rng rng(seed);
        f.resample(rng);
      }, py::arg("seed"))
      .def("effective_size", &robot::ParticleFilter::effective_size)
      .def("estimate", [](const robot::ParticleFilter& f) { return pose_tuple(f.estimate()); },
           "(x, y, angle): the weighted mean position and circular mean heading.")
      .def_property("particles", [](const robot::ParticleFilter& f) { return particles_array(f); },
                    [](robot::ParticleFilter& f, py::array_t<double, py::array::c_style | py::array::forcecast> a) {
                      if (a.ndim() != 2 || a.shape(1) != 4) throw SchemaError("particles", "expected an N × 4 array");
                      auto& ps = f.particles();
                      ps.resize(static_cast<std::size_t>(a.shape(0)));
                      auto v = a.unchecked<2>();
                      for (py::ssize_t i = 0; i < a.shape(0); ++i) {
                        ps[static_cast<std::size_t>(i)] = robot::Particle{v(i, 0), v(i, 1), v(i, 2), v(i, 3)};
                      }
                    },
                    "N × 4 float64 (x, y, angle, weight), a copy; assignable (tests, a chosen belief).");

  py::class_<robot::LocalizationGenerator, Generator, std::shared_ptr<robot::LocalizationGenerator>>(
      m, "LocalizationGenerator", R"doc(
Monte Carlo localization as a robot's odometry: each frame eOdometry<to=robot, x, y, angle, busy, commands>
with its pose estimated by a particle filter weighed on its laser's scan against the known map
(vwg/robot/localization.hpp). One a robot, in place of OdometryGenerator's event for that robot.)doc")
      .def(py::init([](std::shared_ptr<platform::RobotPlatform> platform, std::shared_ptr<sim::LaserGenerator> laser,
                       std::shared_ptr<const robot::LikelihoodField> field, const robot::LocalizationSettings& settings,
                       const Alphabet& alphabet, const std::string& event) {
             return std::make_shared<robot::LocalizationGenerator>(std::move(platform), std::move(laser), std::move(field),
                                                                   settings, alphabet, event);
           }),
           py::arg("platform"), py::arg("laser"), py::arg("field"), py::arg("settings"), py::arg("alphabet"),
           py::arg("event") = "eOdometry")
      .def_property_readonly("robot", &robot::LocalizationGenerator::robot)
      .def("estimate", [](const robot::LocalizationGenerator& g) -> py::object {
        const auto e = g.estimate();
        return e ? py::object(pose_tuple(*e)) : py::object(py::none());
      }, "The pose last sent to the robot (x, y, angle), or None before its first frame.")
      .def_property_readonly("particles", [](const robot::LocalizationGenerator& g) { return particles_array(g.filter()); },
                             "The robot's particles: N × 4 float64 (x, y, angle, weight), a copy.");
}

}  // namespace vwg::bindings
