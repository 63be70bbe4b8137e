#include "json_value.hpp"

#include <pybind11/numpy.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace cubecal::python {

namespace py = pybind11;

namespace {

using Type = nlohmann::json::value_t;

py::object scalar(const nlohmann::json& j) {
  switch (j.type()) {
    case Type::null:
    case Type::discarded: return py::none();
    case Type::boolean: return py::bool_(j.get<bool>());
    case Type::number_integer: return py::int_(j.get<std::int64_t>());
    case Type::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case Type::number_float: {
      const double v = j.get<double>();
      return std::isfinite(v) ? py::object(py::float_(v)) : py::object(py::none());
    }
    case Type::string: return py::str(j.get_ref<const std::string&>());
    default: break;
  }
  throw std::invalid_argument("a JSON value of no Python type");
}

// What a JSON array holds, for its NumPy form.
enum class Kind { none, integers, floats, booleans };

bool fits_int64(const nlohmann::json& x) {
  return x.type() != Type::number_unsigned ||
         x.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
}

// integers: only integers that fit an int64; floats: numbers and nulls, at
// least one number; booleans: only booleans; else none.
Kind kind_of(const nlohmann::json& a) {
  if (!a.is_array() || a.empty()) return Kind::none;
  bool any_number = false, any_float = false, any_null = false, any_bool = false;
  for (const nlohmann::json& x : a) {
    if (x.is_boolean()) {
      any_bool = true;
    } else if (x.is_null()) {
      any_null = true;
    } else if (x.is_number_float()) {
      any_number = any_float = true;
    } else if (x.is_number() && fits_int64(x)) {
      any_number = true;
    } else {
      return Kind::none;
    }
  }
  if (any_bool) return any_number || any_null ? Kind::none : Kind::booleans;
  if (!any_number) return Kind::none;
  return any_float || any_null ? Kind::floats : Kind::integers;
}

double as_double(const nlohmann::json& x) {
  if (x.is_null()) return std::numeric_limits<double>::quiet_NaN();
  const double v = x.get<double>();
  return std::isfinite(v) ? v : std::numeric_limits<double>::quiet_NaN();
}

// The rows of `a` (an array of arrays) as one (rows, columns) array when
// they are all arrays of numbers of one length (floats if any row needs
// them; a row of only nulls is a row of NaN) or all arrays of booleans;
// else none.
Kind matrix_kind(const nlohmann::json& a, std::size_t& columns) {
  if (!a.is_array() || a.empty() || !a.front().is_array()) return Kind::none;
  columns = a.front().size();
  if (columns == 0) return Kind::none;
  Kind k = Kind::none;
  bool null_row = false;
  for (const nlohmann::json& row : a) {
    if (!row.is_array() || row.size() != columns) return Kind::none;
    if (std::all_of(row.begin(), row.end(), [](const nlohmann::json& x) { return x.is_null(); })) {
      null_row = true;
      continue;
    }
    const Kind r = kind_of(row);
    if (r == Kind::none) return Kind::none;
    if (k == Kind::none || k == r) {
      k = r;
    } else if (r != Kind::booleans && k != Kind::booleans) {
      k = Kind::floats;  // integers and floats
    } else {
      return Kind::none;
    }
  }
  if (null_row && k == Kind::booleans) return Kind::none;
  if (null_row && k == Kind::integers) return Kind::floats;
  return k;
}

// A new read-only C-contiguous array of `n` dimensions `dims` of NumPy type
// `type`, filled by fill(pointer to its data), straight through NumPy's C
// API (py::array_t's constructor costs more than a list of a few numbers,
// and a document holds hundreds of short arrays).
template <class T, class Fill>
py::object new_array(int type, int n, const Py_intptr_t* dims, Fill fill) {
  const auto& api = py::detail::npy_api::get();
  PyObject* descr = api.PyArray_DescrFromType_(type);  // the array steals this reference
  PyObject* a = api.PyArray_NewFromDescr_(api.PyArray_Type_, descr, n, dims, nullptr, nullptr, 0, nullptr);
  if (!a) throw py::error_already_set();
  py::object out = py::reinterpret_steal<py::object>(a);
  fill(reinterpret_cast<T*>(py::detail::array_proxy(a)->data));
  py::detail::array_proxy(a)->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return out;
}

template <class T, class Get>
py::object filled(int type, const nlohmann::json& a, bool matrix, std::size_t columns, Get get) {
  const Py_intptr_t dims[2] = {static_cast<Py_intptr_t>(a.size()), static_cast<Py_intptr_t>(columns)};
  return new_array<T>(type, matrix ? 2 : 1, dims, [&](T* p) {
    if (matrix) {
      for (const nlohmann::json& row : a)
        for (const nlohmann::json& x : row) *p++ = get(x);
    } else {
      for (const nlohmann::json& x : a) *p++ = get(x);
    }
  });
}

py::object numeric_array(const nlohmann::json& a, Kind k, bool matrix, std::size_t columns) {
  using api = py::detail::npy_api;
  switch (k) {
    case Kind::integers:
      return filled<std::int64_t>(api::NPY_INT64_, a, matrix, columns,
                                  [](const nlohmann::json& x) { return x.get<std::int64_t>(); });
    case Kind::floats: return filled<double>(api::NPY_DOUBLE_, a, matrix, columns, as_double);
    case Kind::booleans:
      return filled<bool>(api::NPY_BOOL_, a, matrix, columns, [](const nlohmann::json& x) { return x.get<bool>(); });
    case Kind::none: break;
  }
  throw std::logic_error("numeric_array of no kind");
}

template <bool Arrays>
py::object convert(const nlohmann::json& j) {
  if (j.is_array()) {
    if constexpr (Arrays) {
      if (const Kind k = kind_of(j); k != Kind::none) return numeric_array(j, k, false, 0);
      std::size_t columns = 0;
      if (const Kind k = matrix_kind(j, columns); k != Kind::none) return numeric_array(j, k, true, columns);
    }
    py::list out(j.size());
    std::size_t i = 0;
    for (const nlohmann::json& v : j) out[i++] = convert<Arrays>(v);
    return out;
  }
  if (j.is_object()) {
    py::dict out;
    for (const auto& [key, v] : j.items()) out[py::str(key)] = convert<Arrays>(v);
    return out;
  }
  return scalar(j);
}

}  // namespace

py::object to_python(const nlohmann::json& j) { return convert<false>(j); }

py::object to_python_arrays(const nlohmann::json& j) { return convert<true>(j); }

}  // namespace cubecal::python
