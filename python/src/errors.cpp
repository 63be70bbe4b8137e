#include "errors.hpp"

#include <exception>
#include <string>

#include "cubecal/error.hpp"
#include "cubecal/field.hpp"

namespace py = pybind11;

namespace cubecal::python {

namespace {

// Raises `type(message)` with the given attributes set on the instance.
void raise(PyObject* type, const std::string& message, const py::dict& attributes) {
  py::object instance = py::reinterpret_borrow<py::object>(type)(message);
  for (const auto& item : attributes) py::setattr(instance, item.first, item.second);
  PyErr_SetObject(type, instance.ptr());
}

// The message of a UsageError in Python's words; one that leaves its field
// for the face to name (Named::in_front, as the CLI's "--rate: ...") starts
// with the keyword, "rate: the sampling rate ...", unless it names it first.
std::string usage_message(const UsageError& e, const std::string& keyword) {
  std::string text = python_words(e.text());
  if (keyword.empty() || e.named() != UsageError::Named::in_front) return text;
  const bool names_it = text.starts_with(keyword) && (text.size() == keyword.size() || text[keyword.size()] == ' ' ||
                                                      text[keyword.size()] == ':' || text[keyword.size()] == '=');
  return names_it ? text : keyword + ": " + text;
}

}  // namespace

std::string_view python_keyword(Field f) noexcept {
  switch (f) {
    case Field::counts_per_unit: return "lsb";
    case Field::reject_sigma: return "reject";
    case Field::mag_columns: return "columns";
    case Field::min_frequency: return "fmin";
    default: return field_name(f);
  }
}

std::string python_words(const std::string& text) {
  // The subject of the message ("{noise} must be positive") as the keyword,
  // an argument to give ("leave out {stream}") as `keyword=`.
  std::string out;
  std::string rest = text;
  for (std::size_t i = 0; i < kFieldCount; ++i) {
    const auto f = static_cast<Field>(i);
    if (text.starts_with(marker(f))) {
      out = python_keyword(f);
      rest = text.substr(marker(f).size());
      break;
    }
  }
  return out + render_fields(rest, [](Field f) { return std::string(python_keyword(f)) + "="; });
}

void bind_errors(py::module_& m) {
  // Handles that live as long as the interpreter (pybind11's own idiom for
  // exception types: never decremented).
  static py::exception<std::runtime_error> error(m, "Error", PyExc_ValueError);
  static py::exception<InputError> input_error(m, "InputError", error.ptr());
  static py::exception<UsageError> usage_error(m, "UsageError", error.ptr());
  static py::exception<CalibrationError> calibration_error(m, "CalibrationError", error.ptr());
  error.doc() = "Base of cubecal's errors (a ValueError): what the caller or the data can fix.";
  input_error.doc() =
      "The data are wrong at a place: .file, .line and .column (1-based; 0 when not applicable), "
      ".problem and .hint.";
  usage_error.doc() = "What was asked cannot be done as asked; .option names the argument at fault (or is empty).";
  calibration_error.doc() = "The data cannot determine the calibration or model; .reason says why.";

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      py::dict a;
      a["file"] = e.file();
      a["line"] = e.line();
      a["column"] = e.column();
      a["problem"] = python_words(e.problem());
      a["hint"] = python_words(e.hint());
      raise(input_error.ptr(), python_words(e.text()), a);
    } catch (const ArgumentError& e) {
      py::dict a;
      a["option"] = e.argument();
      raise(usage_error.ptr(), python_words(e.text()), a);
    } catch (const UsageError& e) {
      py::dict a;
      const std::string keyword = e.field() ? std::string(python_keyword(*e.field())) : std::string();
      a["option"] = keyword;
      raise(usage_error.ptr(), usage_message(e, keyword), a);
    } catch (const CalibrationError& e) {
      py::dict a;
      a["reason"] = std::string(to_string(e.reason()));
      raise(calibration_error.ptr(), python_words(e.text()), a);
    } catch (const Error& e) {
      raise(error.ptr(), python_words(e.text()), py::dict());
    }
  });
}

}  // namespace cubecal::python
