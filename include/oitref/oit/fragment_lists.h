// The A-buffer's fragment lists (src/oit/methods/abuffer.cpp): every transparent fragment that passed
// the opaque depth test, per pixel, in submission order — what a ground truth or a training set
// reads beside the A-buffer's image (FrameResult::fragmentLists).
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include <glm/vec4.hpp>

namespace oitref {

// One transparent fragment as the A-buffer stores it.
struct TransparentFragment {
  float windowDepth, viewDepth;
  glm::vec4 color;  // straight RGBA from the object's shading
  uint32_t object, primitive;
};

struct FragmentLists {
  int width = 0, height = 0;
  // Pixel p = y·width + x owns fragments[start[p] .. start[p + 1]); start has width·height + 1
  // entries (none when the frame kept no lists: the A-buffer keeps them with lists=keep).
  std::vector<uint64_t> start;
  std::vector<TransparentFragment> fragments;

  bool empty() const { return start.empty(); }
  // The fragments of pixel (x, y), in submission order.
  std::span<const TransparentFragment> at(int x, int y) const {
    if (empty()) throw std::logic_error("FragmentLists::at: the frame kept no lists (the A-buffer keeps them with lists=keep)");
    const size_t p = size_t(y) * size_t(width) + size_t(x);
    return {fragments.data() + start[p], size_t(start[p + 1] - start[p])};
  }
};

}  // namespace oitref
