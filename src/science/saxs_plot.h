// saxs.png: the powder pattern as a line plot, log10 intensity against q, with the present
// reflections' q marked and labelled by sqrt(s) (drawn with render/'s image and text).
#pragma once

#include <string>

#include "render/image.h"
#include "science/scattering.h"

namespace cmcsurf {

Image draw_saxs_plot(const PowderPattern& pattern, const std::string& title, int width = 900,
                     int height = 540);

}  // namespace cmcsurf
