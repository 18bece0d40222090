// How many fragments a transparent pass produces at the least, from the geometry alone: what a
// method that stores every fragment (the A-buffer) can check against the memory limit before it
// allocates anything.
#pragma once

#include <cstdint>

#include "oitref/oit/scene_geometry.h"

namespace oitref::methods {

// A lower bound of the transparent fragments that pass the opaque depth test in a width × height
// frame of `geometry` (with its camera). See fragment_bound.cpp for why it is one.
uint64_t transparentFragmentsAtLeast(const SceneGeometry& geometry, int width, int height);

}  // namespace oitref::methods
