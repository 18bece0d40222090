// The heatmaps' legend: a colour bar with its end values, drawn under a map so that a PNG can be
// read on its own.
#pragma once

#include "oitref/core/image.h"

namespace oitref {

// `map` (RGBA8) with a legend strip under it: the colour scale from 0 to `scaleMax`, "0" at its
// left end and scaleMax (%.3g) at its right, in a 3×5 pixel font drawn at twice its size. The
// canvas is widened (black) when the map is narrower than the legend.
Image withLegend(const Image& map, double scaleMax);

}  // namespace oitref
