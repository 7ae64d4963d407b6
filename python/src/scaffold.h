// cmcsurf.scaffold() and cmcsurf.morphometry(): their bindings (scaffold.cpp), registered by
// module.cpp.
#pragma once

#include <pybind11/pybind11.h>

namespace cmcsurf::python {

void register_scaffold(pybind11::module_& m);

}  // namespace cmcsurf::python
