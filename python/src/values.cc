// Values: Python objects <-> graph::Value.
//
// Default mapping (a new attribute): bool -> bool, int -> int64 (uint64 above INT64_MAX),
// float -> double, str -> string, bytes/bytearray -> bytes, numpy scalars keep their width
// (np.float32 -> float, np.int32 -> int32, ...); arrays: float32 1-D -> float_vec, other 1-D
// numbers (and lists) -> double_vec, uint64 1-D -> uint64_vec, 4x4 -> mat4d.
// An attribute that already holds a value keeps its type when the object converts to it
// (an int written over an int32 stays int32, a 3-vector over a vec3f stays vec3f).
// quiver.Value("vec3f", [1, 2, 3]) forces a type. Reads: integers -> int, floats -> float,
// vectors -> 1-D numpy arrays (float32 for the float kinds), mat4d -> a 4x4 float64 array.

#include <array>
#include <cmath>
#include <limits>

#include "common.h"

namespace quiver::python {
namespace {

using graph::Value;
using graph::ValueType;

[[noreturn]] void type_error(const std::string& msg) {
  PyErr_SetString(PyExc_TypeError, msg.c_str());
  throw py::error_already_set();
}
[[noreturn]] void value_error(const std::string& msg) {
  PyErr_SetString(PyExc_ValueError, msg.c_str());
  throw py::error_already_set();
}

// numpy's scalar classes, looked up once (bind_values()).
PyObject* g_np_bool = nullptr;
PyObject* g_np_integer = nullptr;
PyObject* g_np_floating = nullptr;
PyObject* g_np_generic = nullptr;

bool is_instance(py::handle obj, PyObject* cls) { return PyObject_IsInstance(obj.ptr(), cls) == 1; }

std::string py_type_name(py::handle obj) { return Py_TYPE(obj.ptr())->tp_name; }

bool is_array_like(py::handle obj) {
  return py::isinstance<py::array>(obj) || PyList_Check(obj.ptr()) || PyTuple_Check(obj.ptr());
}

template <class T>
py::array_t<T> as_array(py::handle obj) {
  return py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(obj);
}

template <class T>
T int_in_range(py::handle obj, ValueType t) {
  int overflow = 0;
  long long v = PyLong_AsLongLongAndOverflow(obj.ptr(), &overflow);
  if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
  if (std::is_unsigned_v<T>) {
    if (overflow > 0) {
      unsigned long long u = PyLong_AsUnsignedLongLong(obj.ptr());
      if (PyErr_Occurred()) {
        PyErr_Clear();
      } else if (u <= std::numeric_limits<T>::max()) {
        return static_cast<T>(u);
      }
    } else if (overflow == 0 && v >= 0 && static_cast<unsigned long long>(v) <= std::numeric_limits<T>::max()) {
      return static_cast<T>(v);
    }
  } else if (overflow == 0 && v >= static_cast<long long>(std::numeric_limits<T>::min()) &&
             v <= static_cast<long long>(std::numeric_limits<T>::max())) {
    return static_cast<T>(v);
  }
  PyErr_SetString(PyExc_OverflowError, (std::string(py::str(obj)) + " does not fit a " + graph::to_string(t)).c_str());
  throw py::error_already_set();
}

template <std::size_t N>
std::optional<Value> fixed_vec(py::handle obj, ValueType t, bool strict) {
  auto a = as_array<float>(obj);
  if (!a || a.ndim() != 1 || a.size() != static_cast<py::ssize_t>(N)) {
    if (!a) PyErr_Clear();
    if (strict) value_error(std::string(graph::to_string(t)) + " takes " + std::to_string(N) + " numbers");
    return std::nullopt;
  }
  std::array<float, N> v{};
  std::copy(a.data(), a.data() + N, v.begin());
  return Value(v);
}

template <class T>
std::optional<Value> dyn_vec(py::handle obj, ValueType t, bool strict) {
  auto a = as_array<T>(obj);
  if (!a || a.ndim() != 1) {
    if (!a) PyErr_Clear();
    if (strict) value_error(std::string(graph::to_string(t)) + " takes a 1-D sequence of numbers");
    return std::nullopt;
  }
  return Value(std::vector<T>(a.data(), a.data() + a.size()));
}

/// `obj` as type `t`: nullopt when its kind cannot become `t` (strict: TypeError/ValueError).
std::optional<Value> convert(py::handle obj, ValueType t, bool strict) {
  PyObject* o = obj.ptr();
  const bool is_bool = PyBool_Check(o) || is_instance(obj, g_np_bool);
  const bool is_int = !is_bool && (PyLong_Check(o) || is_instance(obj, g_np_integer));
  const bool is_float = PyFloat_Check(o) || is_instance(obj, g_np_floating);
  auto mismatch = [&]() -> std::optional<Value> {
    if (strict) type_error("cannot store a Python " + py_type_name(obj) + " as " + graph::to_string(t));
    return std::nullopt;
  };
  switch (t) {
    case ValueType::kBool:
      if (!is_bool) return mismatch();
      return Value(PyObject_IsTrue(o) == 1);
    case ValueType::kInt32:
    case ValueType::kInt64:
    case ValueType::kUInt32:
    case ValueType::kUInt64: {
      if (!is_int) return mismatch();
      PyObject* idx = PyNumber_Index(o);
      if (idx == nullptr) throw py::error_already_set();
      auto i = py::reinterpret_steal<py::object>(idx);
      if (t == ValueType::kInt32) return Value::int32(int_in_range<std::int32_t>(i, t));
      if (t == ValueType::kInt64) return Value(int_in_range<std::int64_t>(i, t));
      if (t == ValueType::kUInt32) return Value::uint32(int_in_range<std::uint32_t>(i, t));
      return Value(int_in_range<std::uint64_t>(i, t));
    }
    case ValueType::kFloat:
    case ValueType::kDouble: {
      if (!is_float && !is_int) return mismatch();
      double d = PyFloat_AsDouble(o);
      if (d == -1.0 && PyErr_Occurred()) throw py::error_already_set();
      return t == ValueType::kFloat ? Value(static_cast<float>(d)) : Value(d);
    }
    case ValueType::kString:
      if (!PyUnicode_Check(o)) return mismatch();
      {
        Py_ssize_t n = 0;
        const char* s = PyUnicode_AsUTF8AndSize(o, &n);
        if (s == nullptr) throw py::error_already_set();
        return Value(std::string(s, static_cast<std::size_t>(n)));
      }
    case ValueType::kBytes:
      if (PyBytes_Check(o)) {
        std::string_view s(PyBytes_AS_STRING(o), static_cast<std::size_t>(PyBytes_GET_SIZE(o)));
        return Value(graph::Bytes(s.begin(), s.end()));
      }
      if (PyByteArray_Check(o)) {
        const auto* p = reinterpret_cast<const std::uint8_t*>(PyByteArray_AS_STRING(o));
        return Value(graph::Bytes(p, p + PyByteArray_GET_SIZE(o)));
      }
      return mismatch();
    default:
      break;
  }
  if (!is_array_like(obj)) return mismatch();
  switch (t) {
    case ValueType::kFloatVec: return dyn_vec<float>(obj, t, strict);
    case ValueType::kDoubleVec: return dyn_vec<double>(obj, t, strict);
    case ValueType::kUInt64Vec: return dyn_vec<std::uint64_t>(obj, t, strict);
    case ValueType::kVec2f: return fixed_vec<2>(obj, t, strict);
    case ValueType::kVec3f: return fixed_vec<3>(obj, t, strict);
    case ValueType::kVec4f: return fixed_vec<4>(obj, t, strict);
    case ValueType::kVec6f: return fixed_vec<6>(obj, t, strict);
    case ValueType::kMat4d: {
      auto a = as_array<double>(obj);
      if (!a) PyErr_Clear();
      if (!a || a.size() != 16 || !(a.ndim() == 1 || (a.ndim() == 2 && a.shape(0) == 4))) {
        if (strict) value_error("mat4d takes a 4x4 array (or 16 numbers, row-major)");
        return std::nullopt;
      }
      graph::Mat4d m;
      std::copy(a.data(), a.data() + 16, m.m.begin());
      return Value(m);
    }
    default: return mismatch();
  }
}

ValueType default_type(py::handle obj) {
  PyObject* o = obj.ptr();
  if (PyFloat_Check(o)) return ValueType::kDouble;
  if (PyBool_Check(o)) return ValueType::kBool;
  if (PyLong_Check(o)) {
    int overflow = 0;
    PyLong_AsLongLongAndOverflow(o, &overflow);
    return overflow > 0 ? ValueType::kUInt64 : ValueType::kInt64;
  }
  if (PyUnicode_Check(o)) return ValueType::kString;
  if (PyBytes_Check(o) || PyByteArray_Check(o)) return ValueType::kBytes;
  if (is_instance(obj, g_np_generic)) {
    std::string kind = py::str(obj.attr("dtype").attr("name"));
    if (kind == "bool") return ValueType::kBool;
    if (kind == "float32" || kind == "float16") return ValueType::kFloat;
    if (kind == "int32" || kind == "int16" || kind == "int8") return ValueType::kInt32;
    if (kind == "uint32" || kind == "uint16" || kind == "uint8") return ValueType::kUInt32;
    if (kind == "uint64") return ValueType::kUInt64;
    if (kind.rfind("int", 0) == 0) return ValueType::kInt64;
    if (kind.rfind("float", 0) == 0) return ValueType::kDouble;
  }
  if (is_array_like(obj)) {
    py::array a = py::array::ensure(obj);
    if (!a) {
      PyErr_Clear();
      type_error("cannot convert this " + py_type_name(obj) + " to a quiver value (not an array of numbers)");
    }
    if (a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4) return ValueType::kMat4d;
    std::string kind = py::str(a.dtype().attr("name"));
    if (kind == "float32") return ValueType::kFloatVec;
    if (kind == "uint64") return ValueType::kUInt64Vec;
    return ValueType::kDoubleVec;
  }
  type_error("cannot convert a Python " + py_type_name(obj) +
             " to a quiver value (bool, int, float, str, bytes, numpy arrays or quiver.Value)");
}

template <class T>
py::array_t<T> copy_array(const T* data, std::size_t n) {
  return py::array_t<T>(static_cast<py::ssize_t>(n), data);
}

}  // namespace

Value to_value(py::handle obj, const Value* existing) {
  // Fast paths for the common scalars of a new attribute.
  PyObject* o = obj.ptr();
  if (existing == nullptr) {
    if (PyFloat_CheckExact(o)) return Value(PyFloat_AS_DOUBLE(o));
    if (PyLong_CheckExact(o)) {
      int overflow = 0;
      long long v = PyLong_AsLongLongAndOverflow(o, &overflow);
      if (overflow == 0) return Value(static_cast<std::int64_t>(v));
    }
  }
  if (py::isinstance<Value>(obj)) return obj.cast<const Value&>();
  if (existing != nullptr) {
    if (existing->type() == ValueType::kDouble && PyFloat_CheckExact(o)) return Value(PyFloat_AS_DOUBLE(o));
    if (auto v = convert(obj, existing->type(), false)) return std::move(*v);
    if (PyErr_Occurred()) throw py::error_already_set();
  }
  return *convert(obj, default_type(obj), true);
}

py::object from_value(const Value& v) {
  switch (v.type()) {
    case ValueType::kString: {
      const std::string& s = *v.get_if<std::string>();
      PyObject* u = PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "surrogateescape");
      if (u == nullptr) throw py::error_already_set();
      return py::reinterpret_steal<py::object>(u);
    }
    case ValueType::kBool: return py::bool_(*v.get_if<bool>());
    case ValueType::kInt32: return py::int_(*v.get_if<std::int32_t>());
    case ValueType::kInt64: return py::int_(*v.get_if<std::int64_t>());
    case ValueType::kUInt32: return py::int_(*v.get_if<std::uint32_t>());
    case ValueType::kUInt64: return py::int_(*v.get_if<std::uint64_t>());
    case ValueType::kFloat: return py::float_(*v.get_if<float>());
    case ValueType::kDouble: return py::float_(*v.get_if<double>());
    case ValueType::kBytes: {
      const auto& b = *v.get_if<graph::Bytes>();
      return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
    }
    case ValueType::kFloatVec: {
      const auto& x = *v.get_if<graph::FloatVec>();
      return copy_array(x.data(), x.size());
    }
    case ValueType::kDoubleVec: {
      const auto& x = *v.get_if<graph::DoubleVec>();
      return copy_array(x.data(), x.size());
    }
    case ValueType::kUInt64Vec: {
      const auto& x = *v.get_if<graph::UInt64Vec>();
      return copy_array(x.data(), x.size());
    }
    case ValueType::kVec2f: return copy_array(v.get_if<graph::Vec2f>()->data(), 2);
    case ValueType::kVec3f: return copy_array(v.get_if<graph::Vec3f>()->data(), 3);
    case ValueType::kVec4f: return copy_array(v.get_if<graph::Vec4f>()->data(), 4);
    case ValueType::kVec6f: return copy_array(v.get_if<graph::Vec6f>()->data(), 6);
    case ValueType::kMat4d: return py::array_t<double>({4, 4}, v.get_if<graph::Mat4d>()->m.data());
  }
  return py::none();
}

namespace {
// Names come back again and again (attribute names are usually literals, which Python interns):
// a small direct-mapped cache from the str object to its symbol skips the UTF-8 conversion and
// the symbol table. Each slot holds a reference to its str, so an address is never reused while
// it is a key. Only exact str objects are cached (a subclass could change what it compares as).
struct SymbolSlot {
  PyObject* key = nullptr;
  graph::Symbol sym;
};
std::array<SymbolSlot, 256> g_symbol_cache;
}  // namespace

graph::Symbol to_symbol(py::handle name) {
  PyObject* o = name.ptr();
  const bool exact = PyUnicode_CheckExact(o);
  SymbolSlot& slot = g_symbol_cache[(reinterpret_cast<std::uintptr_t>(o) >> 4) % g_symbol_cache.size()];
  if (exact && slot.key == o) return slot.sym;
  if (PyUnicode_Check(o)) {
    Py_ssize_t n = 0;
    const char* s = PyUnicode_AsUTF8AndSize(o, &n);
    if (s == nullptr) throw py::error_already_set();
    graph::Symbol sym = unwrap(graph::Symbol::make(std::string_view(s, static_cast<std::size_t>(n))));
    if (exact) {
      Py_INCREF(o);
      Py_XDECREF(slot.key);
      slot.key = o;
      slot.sym = sym;
    }
    return sym;
  }
  type_error("a name must be a str, not " + py_type_name(name));
}

void bind_values(py::module_& m) {
  py::module_ np = py::module_::import("numpy");
  g_np_bool = py::object(np.attr("bool_")).release().ptr();
  g_np_integer = py::object(np.attr("integer")).release().ptr();
  g_np_floating = py::object(np.attr("floating")).release().ptr();
  g_np_generic = py::object(np.attr("generic")).release().ptr();
  py::class_<Value>(m, "Value",
                    "A value with an explicit graph type, e.g. Value('vec3f', [1, 2, 3]) or Value('int32', 7).\n"
                    "Types: " "string bool int32 int64 uint32 uint64 float double bytes float_vec double_vec "
                    "uint64_vec vec2f vec3f vec4f vec6f mat4d.")
      .def(py::init([](const std::string& type, py::handle obj) {
             auto t = graph::value_type_from_string(type);
             if (!t) value_error("Value(): unknown type '" + type + "'");
             return *convert(obj, *t, true);
           }),
           py::arg("type"), py::arg("value"))
      .def_property_readonly("type", [](const Value& v) { return std::string(graph::to_string(v.type())); })
      .def_property_readonly("value", &from_value)
      .def("__eq__", [](const Value& a, const Value& b) { return a == b; })
      .def("__repr__", [](const Value& v) {
        return std::string("quiver.Value('") + graph::to_string(v.type()) + "', " + v.to_string() + ")";
      });
  m.def("value_type", [](py::handle obj) { return std::string(graph::to_string(to_value(obj).type())); },
        py::arg("value"), "The graph type a Python object is stored as (for a new attribute).");
}

}  // namespace quiver::python
