#include "json_value.hpp"

#include <cmath>
#include <string>

namespace cubecal::python {

namespace py = pybind11;

py::object to_python(const nlohmann::json& j) {
  using Type = nlohmann::json::value_t;
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
    case Type::array: {
      py::list out(j.size());
      std::size_t i = 0;
      for (const nlohmann::json& v : j) out[i++] = to_python(v);
      return out;
    }
    case Type::object: {
      py::dict out;
      for (const auto& [key, v] : j.items()) out[py::str(key)] = to_python(v);
      return out;
    }
    case Type::binary: break;
  }
  throw std::invalid_argument("a JSON value of no Python type");
}

}  // namespace cubecal::python
