// The order in which the `sorted` method draws the transparent triangles (sorted.cpp), on its
// own so that glcheck's GL version draws the same sequence.
#pragma once

#include <cstddef>
#include <vector>

#include "oitref/oit/method.h"

namespace oitref::methods {

struct SortedTriangle {
  size_t part, index;  // triangle `index` of context.geometry.parts[part]
  double depth;        // view depth of its centroid (or its object's, sorting by object)
};

// Every transparent triangle, farthest centroid first; equal depths keep submission order.
// byTriangle: each triangle's own centroid; else its object's (the centroid of the part's
// vertices), which keeps each object's triangles together and in their order.
std::vector<SortedTriangle> sortedTriangleOrder(const FrameContext& context, bool byTriangle);

}  // namespace oitref::methods
