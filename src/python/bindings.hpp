#pragma once
// The parts of the `vkvo` Python module, each adding its classes and functions (module.cpp calls them in turn).
#include <pybind11/pybind11.h>

namespace vkvo::python {

void bind_features(pybind11::module_& m);  // SuperPoint, SuperGlue, NNMatcher, imread
void bind_odometry(pybind11::module_& m);  // Dataset, Odometry, run
void bind_eval(pybind11::module_& m);      // evaluate

}  // namespace vkvo::python
