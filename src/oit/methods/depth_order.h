// The front-to-back order of one pixel's fragment list, as the A-buffer's resolve needs it: by
// view depth, then window depth (compared with <, so −0 and +0 tie), then list position — the
// order std::stable_sort gives with that comparison, which is unique for keys without NaN.
//
// A pixel's fragments arrive in submission order, which is often near depth order (each one a few
// places from where it belongs): insertion, while the list proves nearly sorted (a budget of
// 8n + 64 moves), then std::stable_sort from where insertion left it (insertion is stable, so the
// order is the same). With AVX2, each insertion compares the new key with the last eight sorted
// ones in vector lanes and moves them in registers, so that a fragment that belongs up to seven
// places back costs no mispredicted branch (a scalar insertion mispredicts once per fragment
// that moves); one that belongs further back takes the scalar step. The lanes compare view depths
// alone and then order each run of equal view depths by window depth, which gives the same order.
// Keys with NaN, and CPUs without AVX2, take the scalar way throughout. With AVX-512F a list goes
// to the window of depth_order_registers.h first (a sorting network, no branch per key), and only
// a list it does not sort (a fragment with more than 32 larger ones before it, roughly) is
// inserted. Every way gives the one order.
#pragma once

#include <cstdint>
#include <vector>

#include "methods/depth_order_registers.h"

namespace oitref::methods {

class DepthOrder {
 public:
  // order[k] = the list position of the k-th of the n fragments front to back; order must hold n
  // entries.
  void sort(const FragmentDepths* list, uint32_t n, uint32_t* order);
  // sort() of two lists at once (orderA, orderB: na and nb entries): the same orders, with the
  // two insertions side by side.
  void sortPair(const FragmentDepths* listA, uint32_t na, uint32_t* orderA, const FragmentDepths* listB,
                uint32_t nb, uint32_t* orderB);
  // The same order the scalar way only (the portable build's; tests compare the two).
  void sortScalar(const FragmentDepths* list, uint32_t n, uint32_t* order);

 private:
  struct Key {
    float viewDepth, windowDepth;
    uint32_t index;
  };
  // order from keys_[0, n), after a stable sort of them unless `sorted`.
  void orderFromKeys(uint32_t n, uint32_t* order, bool sorted);
  // A list's keys as lanes read them: eight sentinel slots, then the keys (laneKeys; false when
  // one is NaN, which the lanes do not order). k: which of the two lists of sortPair.
  struct LaneKeys {
    std::vector<float> view;
    std::vector<uint32_t> index;
  };
  // The order by depth_order_registers.h, for a list of two or more fragments that its window
  // sorts; false (order unspecified) otherwise.
  bool sortInRegisters(const FragmentDepths* list, uint32_t n, uint32_t* order);
  // sort() without the registers: insertion (in lanes with AVX2), then std::stable_sort.
  void sortByInsertion(const FragmentDepths* list, uint32_t n, uint32_t* order);
  static bool lanesAvailable();
  bool laneKeys(int k, const FragmentDepths* list, uint32_t n);
  void orderFromLaneKeys(int k, const FragmentDepths* list, uint32_t n, uint32_t* order, bool sorted);
  std::vector<Key> keys_;
  LaneKeys lanes_[2];
};

}  // namespace oitref::methods
