#include "vwg/generator.hpp"

#include "vwg/error.hpp"
#include "vwg/text.hpp"

namespace vwg {

EveryFrameGenerator::EveryFrameGenerator(const Alphabet& alphabet, std::string_view type,
                                         std::vector<Datum> fields, std::int64_t target)
    : type_(alphabet.event_type_id(type)), target_(target), name_("every_frame(" + std::string(type) + ")") {
  // Check the fields once by emitting into a scratch list of a copy-free alias of the alphabet.
  const EventTypeInfo& info = alphabet.event_type(type_);
  const auto& specs = info.fields.params;
  if (fields.size() > specs.size()) {
    throw SchemaError(info.name, "has " + std::to_string(specs.size()) + " fields, got " + std::to_string(fields.size()));
  }
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (i < fields.size()) {
      fields_.push_back(coerce(specs[i], fields[i], info.name));
    } else if (specs[i].default_value) {
      fields_.push_back(*specs[i].default_value);
    } else {
      throw SchemaError(info.name + "." + specs[i].name, "missing (it has no default)");
    }
  }
}

void EveryFrameGenerator::generate(const FrameInfo&, EventList& out) { out.emit(type_, fields_, target_); }

std::string EveryFrameGenerator::name() const { return name_; }

void Generator::save_state(StateWriter&) const {
  throw SchemaError(name(), "cannot be saved: the generator does not say what it keeps (override save_state and "
                            "load_state; one that keeps nothing writes nothing)");
}

void Generator::load_state(StateReader& in) {
  in.fail("the generator " + name() + " does not say how to load a state");
}

}  // namespace vwg
