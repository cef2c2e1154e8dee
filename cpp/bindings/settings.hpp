// Settings structs (LaserSpec, CameraSpec, RobotSettings, ...) in Python, bound as they are: a
// struct's `visit_settings` lists its fields, and this binder makes of it a class whose keyword
// constructor, properties, equality, repr, replace(), to_dict(), fields(), check() and pickling all
// come from that list. The defaults are the C++ member initialisers, so they live in one place;
// world-file loaders read fields() and call check(), which names `owner.field` on bad values.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "common.hpp"
#include "sim_convert.hpp"
#include "vwg/text.hpp"

namespace vwg::bindings::settings {

/// Whether T is a settings struct (has visit_settings).
template <class T>
concept Settings = requires(T& t) { visit_settings(t, [](const char*, auto&, const char*) {}); };

template <class M>
std::string type_name() {
  if constexpr (std::is_same_v<M, bool>) return "bool";
  else if constexpr (std::is_integral_v<M>) return "int";
  else if constexpr (std::is_floating_point_v<M>) return "float";
  else if constexpr (std::is_same_v<M, std::string>) return "str";
  else if constexpr (std::is_same_v<M, geometry::Pose2>) return "tuple[float, float, float]";
  else if constexpr (std::is_same_v<M, std::vector<std::string>>) return "tuple[str, ...]";
  else return py::str(py::type::of<M>().attr("__name__"));
}

template <class M>
py::object to_python(const M& v) {
  if constexpr (std::is_same_v<M, geometry::Pose2>) return pose_to_python(v);
  else if constexpr (std::is_same_v<M, std::vector<std::string>>) return py::tuple(py::cast(v));
  else return py::cast(v);
}

/// How a field reads in Python: a pose as (x, y, yaw), names as a tuple, the rest as they are.
template <class M>
using Shown = std::conditional_t<std::is_same_v<M, geometry::Pose2>, std::tuple<double, double, double>,
                                 std::conditional_t<std::is_same_v<M, std::vector<std::string>>, py::tuple, M>>;

template <class M>
Shown<M> shown(const M& v) {
  if constexpr (std::is_same_v<M, geometry::Pose2>) return {v.x, v.y, v.theta};
  else if constexpr (std::is_same_v<M, std::vector<std::string>>) return py::tuple(py::cast(v));
  else return v;
}

/// How a setter's argument is typed in the stubs (the setter itself takes any object and names
/// the field when it does not fit).
template <class M>
struct FieldTag {
  static constexpr auto name = py::detail::make_caster<M>::name;  // a settings class: its Python name
};
template <>
struct FieldTag<bool> {
  static constexpr auto name = py::detail::const_name("bool");
};
template <>
struct FieldTag<int> : IntTag {};
template <>
struct FieldTag<std::uint64_t> : IntTag {};
template <>
struct FieldTag<double> : RealTag {};
template <>
struct FieldTag<std::string> {
  static constexpr auto name = py::detail::const_name("str");
};
template <>
struct FieldTag<geometry::Pose2> {
  static constexpr auto name = py::detail::const_name("tuple[float, float, float]");
};
template <>
struct FieldTag<std::vector<std::string>> {
  static constexpr auto name = py::detail::const_name("collections.abc.Sequence[str]");
};

/// A value's type and text, for "expected ..., got float 1e9".
inline std::string got(py::handle h) {
  return std::string(py::str(py::type::of(h).attr("__name__"))) + " " + std::string(py::repr(h));
}

template <class T>
void set_fields(T& s, py::handle values, const std::string& owner);

template <class M>
void from_python(py::handle h, M& into, const std::string& field) {
  const bool is_bool = py::isinstance<py::bool_>(h);
  if constexpr (std::is_same_v<M, bool>) {
    if (!is_bool) throw SchemaError(field, "expected true or false, got " + got(h));
    into = h.cast<bool>();
  } else if constexpr (std::is_integral_v<M>) {
    if (is_bool || !py::isinstance<py::int_>(h)) throw SchemaError(field, "expected an integer, got " + got(h));
    // Range-checked through Python's arbitrary-precision ints: 2**70 is an error, not a wrap.
    const py::int_ lo(std::numeric_limits<M>::min()), hi(std::numeric_limits<M>::max());
    if (h < lo || h > hi) {
      throw SchemaError(field, "expected an integer from " + std::to_string(std::numeric_limits<M>::min()) + " to " +
                                   std::to_string(std::numeric_limits<M>::max()) + ", got " + std::string(py::repr(h)));
    }
    into = h.cast<M>();
  } else if constexpr (std::is_floating_point_v<M>) {
    if (is_bool || !(py::isinstance<py::int_>(h) || py::isinstance<py::float_>(h))) {
      throw SchemaError(field, "expected a number, got " + got(h));
    }
    into = PyFloat_AsDouble(h.ptr());
    if (PyErr_Occurred()) {
      PyErr_Clear();
      throw SchemaError(field, "expected a number that fits a double, got " + std::string(py::repr(h)));
    }
  } else if constexpr (std::is_same_v<M, std::string>) {
    if (!py::isinstance<py::str>(h)) throw SchemaError(field, "expected text, got " + got(h));
    into = h.cast<std::string>();
  } else if constexpr (std::is_same_v<M, geometry::Pose2>) {
    if (py::isinstance<py::str>(h) || !py::isinstance<py::sequence>(h) || py::len(h) != 3) {
      throw SchemaError(field, "expected [x, y, yaw], got " + got(h));
    }
    double xyz[3];
    py::sequence seq = py::reinterpret_borrow<py::sequence>(h);
    for (int i = 0; i < 3; ++i) from_python(seq[static_cast<std::size_t>(i)], xyz[i], field + "[" + std::to_string(i) + "]");
    into = geometry::Pose2{xyz[0], xyz[1], xyz[2]};
  } else if constexpr (std::is_same_v<M, std::vector<std::string>>) {
    if (py::isinstance<py::str>(h) || !py::isinstance<py::sequence>(h)) throw SchemaError(field, "expected a list of names, got " + got(h));
    std::vector<std::string> out;
    std::size_t i = 0;
    for (py::handle item : h) {
      if (!py::isinstance<py::str>(item)) throw SchemaError(field + "[" + std::to_string(i) + "]", "expected a name, got " + got(item));
      out.push_back(item.cast<std::string>());
      ++i;
    }
    into = std::move(out);
  } else {
    static_assert(Settings<M>, "a settings field of an unsupported type");
    if (py::isinstance<M>(h)) {
      into = h.cast<M>();
    } else if (py::isinstance<py::dict>(h)) {
      M fresh{};
      set_fields(fresh, h, field);
      into = fresh;
    } else {
      throw SchemaError(field, "expected a " + type_name<M>() + " or a mapping, got " + got(h));
    }
  }
}

template <class T>
std::vector<std::string> field_names() {
  std::vector<std::string> names;
  T probe{};
  visit_settings(probe, [&](const char* name, auto&, const char*) { names.emplace_back(name); });
  return names;
}

/// Set the fields a mapping (or kwargs) names; an unknown name is an error that lists the known.
template <class T>
void set_fields(T& s, py::handle values, const std::string& owner) {
  py::dict d = py::reinterpret_borrow<py::dict>(values);
  for (auto item : d) {
    const std::string key = py::str(item.first);
    bool found = false;
    visit_settings(s, [&](const char* name, auto& member, const char*) {
      if (key == name) {
        from_python(item.second, member, owner + "." + key);
        found = true;
      }
    });
    if (!found) {
      std::string known;
      for (const std::string& n : field_names<T>()) known += (known.empty() ? "" : ", ") + n;
      throw SchemaError(owner + "." + key, "unknown setting (expected one of " + known + ")");
    }
  }
}

template <class T>
py::dict to_dict(const T& s) {
  py::dict d;
  visit_settings(s, [&](const char* name, const auto& member, const char*) { d[name] = to_python(member); });
  return d;
}

template <class T>
bool equal(const T& a, const T& b) {
  bool same = true;
  // Walk both in step: the visitor's order is fixed, so the i-th field of each is the same one.
  std::vector<py::object> left;
  visit_settings(a, [&](const char*, const auto& member, const char*) { left.push_back(to_python(member)); });
  std::size_t i = 0;
  visit_settings(b, [&](const char*, const auto& member, const char*) { same = same && left[i++].equal(to_python(member)); });
  return same;
}

/// The class `name` for T, with everything derived from its fields. `check` is the struct's
/// check_settings overload.
template <class T>
py::class_<T> bind(py::module_& m, const char* name, const std::string& doc) {
  const T defaults{};
  std::string signature = "__init__(self, *";
  std::string table = doc + "\n\nFields (defaults from the C++ struct):\n";
  visit_settings(defaults, [&](const char* field, const auto& member, const char* help) {
    using M = std::remove_cvref_t<decltype(member)>;
    const std::string shown = py::repr(to_python(member));
    signature += std::string(", ") + field + ": " + type_name<M>() + " = " + shown;
    table += std::string("  ") + field + " = " + shown + ": " + help + "\n";
  });
  signature += ") -> None\n";

  py::class_<T> cls(m, name, table.c_str());
  {
    // The generated signature names every field and its default, for help() and the .pyi stubs.
    py::options options;
    options.disable_function_signatures();
    const std::string init_doc = signature + "\nThe settings, each keyword replacing its default.";
    cls.def(py::init([name = std::string(name)](const py::kwargs& kw) {
              T s{};
              set_fields(s, kw, name);
              return s;
            }),
            init_doc.c_str());
  }
  visit_settings(defaults, [&](const char* field, const auto& member, const char* help) {
    using M = std::remove_cvref_t<decltype(member)>;
    const std::string key = field;
    const std::string doc = std::string(help) + " (" + type_name<M>() + ")";
    auto setter = [key, owner = std::string(name)](T& s, const LooseArg<FieldTag<M>>& value) {
      visit_settings(s, [&](const char* f, auto& v, const char*) {
        if (key == f) from_python(value, v, owner + "." + key);
      });
    };
    if constexpr (Settings<M>) {
      // A nested settings struct is the one inside, not a copy: `physics.noise.motors = 0.1` sticks.
      cls.def_property(
          field,
          py::cpp_function(
              [key](T& s) -> M& {
                M* out = nullptr;
                visit_settings(s, [&](const char* f, auto& v, const char*) {
                  if constexpr (std::is_same_v<std::remove_cvref_t<decltype(v)>, M>) {
                    if (key == f) out = &v;
                  }
                });
                return *out;
              },
              py::return_value_policy::reference_internal),
          setter, doc.c_str());
      return;
    }
    cls.def_property(
        field,
        // Typed by the field's C++ type, so the stubs say int, float, tuple[float, float, float], ...
        [key](const T& s) {
          Shown<M> out{};
          visit_settings(s, [&](const char* f, const auto& v, const char*) {
            if constexpr (std::is_same_v<std::remove_cvref_t<decltype(v)>, M>) {
              if (key == f) out = shown(v);
            }
          });
          return out;
        },
        setter, doc.c_str());
  });
  cls.def("__eq__", [](const T& a, py::handle b) { return py::isinstance<T>(b) && equal(a, b.cast<const T&>()); },
          py::is_operator())
      .def("__ne__", [](const T& a, py::handle b) { return !(py::isinstance<T>(b) && equal(a, b.cast<const T&>())); },
           py::is_operator())
      .def("__repr__", [name = std::string(name)](const T& s) {
        std::string out = "vwg." + name + "(";
        bool first = true;
        visit_settings(s, [&](const char* f, const auto& v, const char*) {
          out += (first ? "" : ", ") + std::string(f) + "=" + std::string(py::repr(to_python(v)));
          first = false;
        });
        return out + ")";
      })
      .def("__copy__", [](const T& s) { return T(s); })
      .def("__deepcopy__", [](const T& s, py::handle) { return T(s); }, py::arg("memo"))
      .def("replace", [name = std::string(name)](const T& s, const py::kwargs& kw) {
        T copy = s;
        set_fields(copy, kw, name);
        return copy;
      }, "A copy with these fields changed: spec.replace(beams=180).")
      .def("to_dict", [](const T& s) { return to_dict(s); }, "{field: value}, as a world file writes them.")
      .def("check", [](const T& s, const std::string& owner) { check_settings(s, owner); }, py::arg("owner"),
           "Raise vwg.SchemaError naming `owner.field` for a value out of range (what the C++ side would refuse).")
      .def_static("fields", [defaults]() {
        std::vector<std::tuple<std::string, std::string, py::object, std::string>> out;
        visit_settings(defaults, [&](const char* f, const auto& v, const char* help) {
          using M = std::remove_cvref_t<decltype(v)>;
          out.emplace_back(f, type_name<M>(), to_python(v), help);
        });
        return out;
      }, "[(name, type, default, meaning)] of every field, in order.")
      .def(py::pickle([](const T& s) { return to_dict(s); },
                      [name = std::string(name)](const py::dict& d) {
                        T s{};
                        set_fields(s, d, name);
                        return s;
                      }));
  return cls;
}

}  // namespace vwg::bindings::settings
