// People who walk in vwg._core: the Person actor, gSocial and the people's backend (vwg/sim/people.hpp).
#include <memory>
#include <string>
#include <vector>

#include "common.hpp"
#include "sim_convert.hpp"
#include "vwg/sim/people.hpp"

namespace vwg::bindings {

void init_people(py::module_& m) {
  m.def("add_person_actor", [](Alphabet& alphabet, MapArg map, const sim::SocialForceSettings& settings, double dt,
                               double largest_radius) {
    const SymbolId id = alphabet.add_actor("Person", {"eSocial", "eExecute"}, sim::person_attributes(), nullptr);
    alphabet.set_behavior(id, std::make_shared<sim::PersonBehavior>(alphabet, grid_from_python(map), settings, dt,
                                                                    largest_radius));
  }, py::arg("alphabet"), py::arg("map"), py::arg("settings"), py::arg("dt"), py::arg("largest_radius"),
     R"doc(Register the actor type Person (people who walk by the social force model, vwg/sim/people.hpp) on the
world's true map. The alphabet must have the primitive Pedestrian<id, x, y, vx, vy, radius> and the events
eSocial<fx, fy> and eExecute.)doc");
  m.def("person_attributes", [] { return schema_to_python(sim::person_attributes()); },
        "Person's attributes {name: (kind, default)}.");

  py::class_<sim::SocialForceGenerator, Generator, std::shared_ptr<sim::SocialForceGenerator>>(m, "SocialForceGenerator", R"doc(
gSocial: eSocial<to=person, fx, fy> for every person on the simulator, the repulsion (m/s²) of the people and
robots near it and of the walls, from where the simulator has them when the frame begins.)doc")
      .def(py::init<std::shared_ptr<const sim::PhysicsWorld>, sim::SocialForceSettings, const Alphabet&, const std::string&>(),
           py::arg("world"), py::arg("settings"), py::arg("alphabet"), py::arg("event") = "eSocial");

  py::class_<sim::PeopleBackend, Backend, std::shared_ptr<sim::PeopleBackend>>(m, "PeopleBackend",
                                                                              "φ of Pedestrian: the person's body on the simulator.")
      .def(py::init<std::shared_ptr<sim::PhysicsWorld>, const Alphabet&>(), py::arg("world"), py::arg("alphabet"));

  m.def("social_push", [](std::tuple<double, double, double> person, std::tuple<double, double, double> other,
                          double strength, double range, double reach) {
    const auto [x, y, r] = person;
    const auto [ox, oy, orad] = other;
    const sim::Vec f = sim::push_of(x, y, r, ox, oy, orad, strength, range, reach);
    return py::make_tuple(f.x, f.y);
  }, py::arg("person"), py::arg("other"), py::arg("strength"), py::arg("range"), py::arg("reach"),
     "The push (m/s², x and y) of a disc `other` (x, y, radius) on a person (x, y, radius): strength·exp((r − d)/range).");

  m.def("social_force", [](const sim::PhysicsWorld& world, int person, const sim::SocialForceSettings& settings) {
    for (const sim::PhysicsWorld::Person& p : world.people()) {
      if (p.id != person) continue;
      const geometry::ClearanceField walls(geometry::BlockedGrid::from_occupancy(world.grid()), true);
      const sim::Vec f = sim::repulsion(p, world.discs(), walls, world.grid(), settings);
      return py::make_tuple(f.x, f.y);
    }
    throw SchemaError("person", "no person " + std::to_string(person) + " on the simulator");
  }, py::arg("world"), py::arg("person"), py::arg("settings"),
     "What gSocial sends person `person` now: the repulsion of the others and the walls (m/s², x and y).");
}

}  // namespace vwg::bindings
