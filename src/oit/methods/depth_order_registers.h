// The A-buffer's front-to-back order (depth_order.h) in AVX-512 registers, for lists whose
// fragments lie near their place in it. Keys of 64 bits (the view depth's bits made to order as
// unsigned integers, the list position below: distinct, so they have one sorted order, the order by
// view depth with ties in list order) go through a window of 32: blocks of 32 sorted by a bitonic
// network and merged with the 32 largest keys before them (a list of up to 8 or 16 fragments is
// sorted whole in one or two registers). A network makes the same comparisons
// whatever the keys, so it has no branch to mispredict, where an insertion mispredicts about once
// per fragment that moves; `dense`'s lists are not sorted (43 % of neighbouring fragments descend)
// but every fragment has fewer than 32 larger ones before it. Whether the window sorted a list is
// known at its end (each key against the one before it); it did whenever no fragment has more than
// 32 larger ones before it.
#pragma once

#include <cstdint>


namespace oitref::methods {

// A fragment's two depths, as the A-buffer's bands store them apart from its colour: what the
// order reads, eight fragments to a 64-byte line.
struct FragmentDepths {
  float windowDepth, viewDepth;
};

// Whether this CPU has AVX-512F; without it orderInRegisters does nothing.
bool registerOrderAvailable();

// order[0, n): the list positions by view depth (== : −0 and +0 tie), ties in list order; `tie`:
// whether two fragments have equal view depths (their window depths still to be ordered). False,
// with order and tie unspecified, when the window did not sort the list, a view or window depth is
// NaN, n is 0, or the CPU lacks AVX-512F.
bool orderInRegisters(const FragmentDepths* list, uint32_t n, uint32_t* order, bool& tie);

}  // namespace oitref::methods
