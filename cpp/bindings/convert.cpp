// Python <-> vwg values, schemas and strings.
#include <cmath>
#include <string>

#include "common.hpp"

namespace vwg::bindings {

py::object python_class(const char* module, const char* name) { return py::module_::import(module).attr(name); }

std::string python_type_name(py::handle self) {
  py::handle type = py::type::handle_of(self);
  if (py::hasattr(type, "name")) {
    py::object n = type.attr("name");
    if (PyUnicode_Check(n.ptr())) return n.cast<std::string>();
  }
  return py::str(type.attr("__name__"));
}

namespace {

std::string describe_python(py::handle obj) {
  std::string type = py::str(py::type::handle_of(obj).attr("__name__"));
  std::string r = py::repr(obj);
  if (r.size() > 60) r = r.substr(0, 57) + "...";
  return type + " " + r;
}

bool is_numpy_type(py::handle obj, std::initializer_list<const char*> names) {
  py::handle type = py::type::handle_of(obj);
  if (!py::hasattr(type, "__module__")) return false;
  if (std::string(py::str(type.attr("__module__"))) != "numpy") return false;
  const std::string n = py::str(type.attr("__name__"));
  for (const char* name : names) {
    if (n == name) return true;
  }
  return false;
}

bool is_python_bool(py::handle obj) { return PyBool_Check(obj.ptr()) || is_numpy_type(obj, {"bool_", "bool"}); }
bool is_python_int(py::handle obj) {
  if (is_python_bool(obj)) return false;
  return PyLong_Check(obj.ptr()) || (is_numpy_type(obj, {"int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64", "intc", "intp", "longlong"}));
}
bool is_python_real(py::handle obj) {
  if (is_python_bool(obj)) return false;
  return PyFloat_Check(obj.ptr()) || is_numpy_type(obj, {"float16", "float32", "float64", "longdouble"});
}

std::int64_t to_int64(py::handle obj, const std::string& field) {
  py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(obj.ptr()));
  if (!index) throw py::error_already_set();
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow) throw SchemaError(field, "integer " + std::string(py::str(obj)) + " does not fit in 64 bits");
  return v;
}

ValueKind infer_kind(py::handle obj, const std::string& field) {
  if (is_python_bool(obj)) return ValueKind::Bool;
  if (is_python_int(obj)) return ValueKind::Int;
  if (is_python_real(obj)) return ValueKind::Real;
  if (PyUnicode_Check(obj.ptr())) return ValueKind::Text;
  if (py::isinstance<Blob>(obj) || py::isinstance<py::array>(obj)) return ValueKind::Blob;
  throw SchemaError(field, "cannot hold " + describe_python(obj) +
                               "; values are int, float, bool, str or vwg.Blob / numpy arrays");
}

}  // namespace

std::shared_ptr<const Blob> blob_from_python(py::handle obj, const std::string& field) {
  if (py::isinstance<Blob>(obj)) return obj.cast<std::shared_ptr<Blob>>();
  if (!py::isinstance<py::array>(obj)) throw SchemaError(field, "expected a vwg.Blob or a numpy array, got " + describe_python(obj));
  py::array a = py::reinterpret_borrow<py::array>(obj);
  const std::string kind(1, a.dtype().kind());
  const std::size_t itemsize = static_cast<std::size_t>(a.dtype().itemsize());
  DType dtype;
  if (kind == "i" && itemsize == 1) dtype = DType::Int8;
  else if (kind == "u" && itemsize == 1) dtype = DType::UInt8;
  else if (kind == "b" && itemsize == 1) dtype = DType::UInt8;
  else if (kind == "i" && itemsize == 2) dtype = DType::Int16;
  else if (kind == "i" && itemsize == 4) dtype = DType::Int32;
  else if (kind == "i" && itemsize == 8) dtype = DType::Int64;
  else if (kind == "f" && itemsize == 4) dtype = DType::Float32;
  else if (kind == "f" && itemsize == 8) dtype = DType::Float64;
  else throw SchemaError(field, "arrays of dtype " + std::string(py::str(a.dtype())) + " cannot be blobs; use int8, uint8, int16, int32, int64, float32 or float64");
  if (a.ndim() > 4) throw SchemaError(field, "a blob has at most 4 dimensions, got " + std::to_string(a.ndim()));
  // A C-contiguous copy in native byte order.
  py::array c = py::array::ensure(a, py::array::c_style | py::array::forcecast);
  if (!c) throw py::error_already_set();
  std::vector<std::int64_t> shape(c.shape(), c.shape() + c.ndim());
  if (dtype == DType::Float32 || dtype == DType::Float64) {
    // Blobs are values of the world: no NaN inside, so that equal texts mean equal states.
    py::object finite = py::module_::import("numpy").attr("isfinite")(c).attr("all")();
    if (!finite.cast<bool>()) throw SchemaError(field, "the array holds NaN or infinity");
  }
  return std::make_shared<const Blob>(dtype, std::move(shape), c.data(), static_cast<std::size_t>(c.nbytes()));
}

py::object blob_to_python(const std::shared_ptr<const Blob>& blob) {
  return py::cast(std::const_pointer_cast<Blob>(blob));
}

Datum datum_from_python(py::handle obj, const ParamSpec* spec, const std::string& field) {
  // Fast paths for the exact built-in types (no numpy type lookups).
  PyObject* p = obj.ptr();
  if (spec) {
    if (spec->kind == ValueKind::Real && PyFloat_CheckExact(p)) {
      const double r = PyFloat_AS_DOUBLE(p);
      if (std::isfinite(r)) return Datum(r);
    } else if (spec->kind == ValueKind::Int && PyLong_CheckExact(p)) {
      int overflow = 0;
      const long long v = PyLong_AsLongLongAndOverflow(p, &overflow);
      if (!overflow && !(v == -1 && PyErr_Occurred())) return Datum(static_cast<std::int64_t>(v));
      PyErr_Clear();
    } else if (spec->kind == ValueKind::Bool && PyBool_Check(p)) {
      return Datum(p == Py_True);
    }
  }
  const ValueKind kind = spec ? spec->kind : infer_kind(obj, field);
  auto mismatch = [&]() -> SchemaError {
    return SchemaError(field, "expected " + std::string(kind_name(kind)) + ", got " + describe_python(obj));
  };
  switch (kind) {
    case ValueKind::Int:
      if (!is_python_int(obj)) throw mismatch();
      return Datum(to_int64(obj, field));
    case ValueKind::Real: {
      if (!is_python_real(obj) && !is_python_int(obj)) throw mismatch();
      const double r = is_python_int(obj) ? static_cast<double>(to_int64(obj, field)) : obj.cast<double>();
      if (!std::isfinite(r)) throw SchemaError(field, "expected a finite real, got " + std::string(py::repr(obj)));
      return Datum(r);
    }
    case ValueKind::Bool:
      if (!is_python_bool(obj)) throw mismatch();
      return Datum(obj.cast<bool>());
    case ValueKind::Text:
      if (!PyUnicode_Check(obj.ptr())) throw mismatch();
      return Datum(obj.cast<std::string>());
    case ValueKind::Blob:
      return Datum(blob_from_python(obj, field));
  }
  throw mismatch();
}

py::object value_to_python(const ValueStore& store, const Value& v) {
  switch (v.kind) {
    case ValueKind::Int: return py::int_(v.i);
    case ValueKind::Real: return py::float_(v.r);
    case ValueKind::Bool: return py::bool_(v.b);
    case ValueKind::Text: return py::str(std::string(store.text(v)));
    case ValueKind::Blob: return blob_to_python(store.blob(v));
  }
  return py::none();
}

py::object datum_to_python(const Datum& d) {
  switch (d.kind()) {
    case ValueKind::Int: return py::int_(d.as_int());
    case ValueKind::Real: return py::float_(d.as_real());
    case ValueKind::Bool: return py::bool_(d.as_bool());
    case ValueKind::Text: return py::str(d.as_text());
    case ValueKind::Blob: return blob_to_python(d.as_blob());
  }
  return py::none();
}

Schema schema_from_python(py::handle spec, const std::string& owner, bool allow_variadic) {
  if (spec.is_none()) {
    if (!allow_variadic) return Schema{};
    return Schema::any();
  }
  Schema schema;
  auto kind_of_type = [&](py::handle t, const std::string& name) -> std::optional<ValueKind> {
    if (t.ptr() == reinterpret_cast<PyObject*>(&PyBool_Type)) return ValueKind::Bool;
    if (t.ptr() == reinterpret_cast<PyObject*>(&PyLong_Type)) return ValueKind::Int;
    if (t.ptr() == reinterpret_cast<PyObject*>(&PyFloat_Type)) return ValueKind::Real;
    if (t.ptr() == reinterpret_cast<PyObject*>(&PyUnicode_Type)) return ValueKind::Text;
    if (t.is(py::type::of<Blob>())) return ValueKind::Blob;
    if (PyType_Check(t.ptr())) {
      throw SchemaError(owner + "." + name, "type " + std::string(py::str(t.attr("__name__"))) +
                                                " cannot be a parameter kind; use int, float, bool, str or vwg.Blob");
    }
    return std::nullopt;
  };
  if (py::isinstance<py::dict>(spec)) {
    for (auto item : py::reinterpret_borrow<py::dict>(spec)) {
      const std::string name = py::str(item.first);
      ParamSpec p;
      p.name = name;
      if (auto kind = kind_of_type(item.second, name)) {
        p.kind = *kind;  // a type: required
      } else {
        const Datum d = datum_from_python(item.second, nullptr, owner + "." + name);
        p.kind = d.kind();
        p.default_value = d;
      }
      schema.params.push_back(std::move(p));
    }
    return schema;
  }
  if (py::isinstance<py::list>(spec) || py::isinstance<py::tuple>(spec)) {
    for (auto item : spec) {
      if (!PyUnicode_Check(item.ptr())) throw SchemaError(owner, "a list of parameters holds names (str), got " + describe_python(item));
      schema.params.push_back(ParamSpec{item.cast<std::string>(), ValueKind::Real, std::nullopt});
    }
    return schema;
  }
  throw SchemaError(owner, "parameters are declared as None, a dict {name: default or type} or a list of names; got " + describe_python(spec));
}

py::dict schema_to_python(const Schema& schema) {
  py::dict out;
  for (const ParamSpec& p : schema.params) {
    out[py::str(p.name)] = py::make_tuple(std::string(kind_name(p.kind)),
                                          p.default_value ? datum_to_python(*p.default_value) : py::object(py::none()));
  }
  return out;
}

namespace {

/// Datums in schema order from positional and named Python values.
std::vector<Datum> params_from_python(const SymbolInfo& info, py::handle positional, py::handle named, const std::string& what) {
  std::vector<Datum> out;
  const Schema& schema = info.schema;
  const std::size_t npos = positional.is_none() ? 0 : py::len(positional);
  if (schema.variadic) {
    if (!named.is_none() && py::len(named) > 0) throw SchemaError(what, info.name + " declares no parameter names; pass its values by position");
    std::size_t i = 0;
    for (auto v : positional) out.push_back(datum_from_python(v, nullptr, info.name + "[" + std::to_string(i++) + "]"));
    return out;
  }
  if (npos > schema.params.size()) {
    throw SchemaError(info.name, "takes " + std::to_string(schema.params.size()) + " values, got " + std::to_string(npos));
  }
  std::vector<std::optional<Datum>> slots(schema.params.size());
  std::size_t i = 0;
  if (npos) {
    for (auto v : positional) {
      slots[i] = datum_from_python(v, &schema.params[i], info.name + "." + schema.params[i].name);
      ++i;
    }
  }
  if (!named.is_none()) {
    for (auto item : py::reinterpret_borrow<py::dict>(named)) {
      const std::string key = py::str(item.first);
      const int k = schema.index_of(key);
      if (k < 0) throw SchemaError(info.name + "." + key, "no such " + std::string(info.kind == SymbolKind::Actor ? "attribute" : "parameter"));
      if (slots[static_cast<std::size_t>(k)]) throw SchemaError(info.name + "." + key, "given twice");
      slots[static_cast<std::size_t>(k)] = datum_from_python(item.second, &schema.params[static_cast<std::size_t>(k)], info.name + "." + key);
    }
  }
  for (std::size_t k = 0; k < slots.size(); ++k) {
    if (slots[k]) {
      out.push_back(std::move(*slots[k]));
    } else if (schema.params[k].default_value) {
      out.push_back(*schema.params[k].default_value);
    } else {
      throw SchemaError(info.name + "." + schema.params[k].name, "missing (it has no default)");
    }
  }
  return out;
}

void append_one(StringBuilder& out, py::handle obj, const std::string& what, const py::object& actor_base,
                const py::object& sym_class, int depth) {
  if (depth > 1000) throw SchemaError(what, "the returned value nests more than 1000 levels");
  const Alphabet& A = out.alphabet();
  if (PyUnicode_Check(obj.ptr())) {
    const std::string text = obj.cast<std::string>();
    out.append(parse_string(out.alphabet_ptr(), text, "<" + what + ">"));
    return;
  }
  if (py::isinstance<WorldString>(obj)) {
    out.append(obj.cast<const WorldString&>());
    return;
  }
  if (PyObject_IsInstance(obj.ptr(), actor_base.ptr()) == 1) {
    const std::string name = py::str(py::type::handle_of(obj).attr("name"));
    const SymbolId id = A.symbol_id(name, SymbolKind::Actor);
    py::tuple values = obj.attr("_v");
    const SymbolInfo& info = A.symbol(id);
    if (py::len(values) != info.schema.params.size()) {
      throw SchemaError(what, "actor " + name + " has " + std::to_string(py::len(values)) + " values, its type declares " +
                                  std::to_string(info.schema.params.size()));
    }
    std::vector<Datum> attrs;
    attrs.reserve(info.schema.params.size());
    for (std::size_t k = 0; k < info.schema.params.size(); ++k) {
      attrs.push_back(datum_from_python(values[k], &info.schema.params[k], name + "." + info.schema.params[k].name));
    }
    out.actor(id, attrs);
    return;
  }
  if (PyObject_IsInstance(obj.ptr(), sym_class.ptr()) == 1) {
    const std::string name = py::str(obj.attr("name"));
    const auto id = A.find_symbol(name);
    if (!id) throw SchemaError(what, "unknown symbol '" + name + "' (not in the alphabet)");
    const SymbolInfo& info = A.symbol(*id);
    const auto params = params_from_python(info, obj.attr("params"), obj.attr("named"), what);
    py::object children = obj.attr("children");
    switch (info.kind) {
      case SymbolKind::Primitive:
        if (!children.is_none()) throw SchemaError(what, "'" + name + "' is a primitive; only transformations take children");
        out.primitive(*id, params);
        return;
      case SymbolKind::Actor:
        if (!children.is_none()) throw SchemaError(what, "'" + name + "' is an actor; only transformations take children");
        out.actor(*id, params);
        return;
      case SymbolKind::Transformation:
        if (children.is_none() || py::len(children) == 0) {
          throw SchemaError(what, "transformation '" + name + "' needs children: Sym(\"" + name + "\", ...)(child, ...)");
        }
        out.open(*id, params);
        for (auto child : children) append_one(out, child, what, actor_base, sym_class, depth + 1);
        out.close();
        return;
    }
  }
  if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
    for (auto item : obj) append_one(out, item, what, actor_base, sym_class, depth + 1);
    return;
  }
  if (obj.is_none()) {
    throw SchemaError(what, "returned None; return self to stay unchanged, \"\" or [] for the empty string ε, "
                            "or a string, vwg.Sym or actor for anything else");
  }
  throw SchemaError(what, "returned " + describe_python(obj) +
                              "; expected text, a vwg.String, an actor, a vwg.Sym, or a list of these");
}

}  // namespace

void append_python(StringBuilder& out, py::handle obj, const std::string& what) {
  // The pure-Python classes are looked up once; the stored objects live as long as the process.
  struct Classes {
    py::object actor, sym;
  };
  PYBIND11_CONSTINIT static py::gil_safe_call_once_and_store<Classes> storage;
  const Classes& c = storage
                         .call_once_and_store_result([] {
                           return Classes{python_class("vwg.model.actor", "Actor"), python_class("vwg.model.actor", "Sym")};
                         })
                         .get_stored();
  append_one(out, obj, what, c.actor, c.sym, 0);
}

}  // namespace vwg::bindings
