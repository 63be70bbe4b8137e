// Calibrations from Python: bound in the next commit.
#include "module.hpp"
namespace cubecal::python {
void bind_calibrate(pybind11::module_&) {}
}  // namespace cubecal::python
