// Lines and markers of the charts drawn with render/ (the properties chart, families.png):
// anti-aliased and alpha-blended into an Image, coordinates in pixels.
#pragma once

#include "render/image.h"

namespace cmcsurf {

// An anti-aliased line of width ~1.5 px; `on`/`off` > 0 make it dashed (lengths in pixels),
// the pattern running on from `*phase` (the arc length drawn so far along a polyline).
void draw_line(Image& img, double x0, double y0, double x1, double y1, Rgb c, double on = 0,
               double off = 0, double* phase = nullptr, float width = 1.0f);

// A disc of radius r (filled) or its ring.
void draw_disc(Image& img, double x, double y, double r, Rgb c, bool filled);

}  // namespace cmcsurf
