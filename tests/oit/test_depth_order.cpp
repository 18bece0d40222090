// The A-buffer's front-to-back order (methods/depth_order.h) against std::stable_sort over the
// same keys, on lists that take each of its ways: short, nearly sorted (each fragment up to a few
// places from where it belongs: the lanes), displaced further (the scalar step), reversed and
// shuffled (the budget runs out: std::stable_sort finishes), with ties in view depth, in both
// depths, and between −0 and +0; NaN keys take the scalar way and must agree with it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "methods/depth_order.h"
#include "methods/depth_order_registers.h"
#include "support.h"

using namespace oitref;
using methods::FragmentDepths;

namespace {

std::vector<uint32_t> stableOrder(const std::vector<FragmentDepths>& list) {
  std::vector<uint32_t> order(list.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const FragmentDepths &x = list[a], &y = list[b];
    return x.viewDepth != y.viewDepth ? x.viewDepth < y.viewDepth : x.windowDepth < y.windowDepth;
  });
  return order;
}

// n fragments whose keys come from `levels` distinct values (ties when small), in depth order,
// then each moved up to `displacement` places (or shuffled when negative, reversed when 0).
std::vector<FragmentDepths> makeList(test::BitStream& rng, uint32_t n, uint32_t levels, int displacement) {
  std::vector<FragmentDepths> list(n);
  for (FragmentDepths& f : list) {
    const uint32_t v = rng.next() % levels;
    f.viewDepth = v == 0 ? (rng.next() % 2 ? -0.0f : 0.0f) : float(v);
    f.windowDepth = float(rng.next() % 3) * 0.25f;
  }
  std::vector<uint32_t> sorted = stableOrder(list);
  std::vector<FragmentDepths> out(n);
  for (uint32_t i = 0; i < n; ++i) out[i] = list[sorted[i]];
  if (displacement == 0) std::reverse(out.begin(), out.end());
  else if (displacement < 0)
    for (uint32_t i = n; i > 1; --i) std::swap(out[i - 1], out[rng.next() % i]);
  else
    for (uint32_t i = 0; i + 1 < n; ++i) {
      const uint32_t j = std::min<uint32_t>(n - 1, i + rng.next() % uint32_t(displacement + 1));
      std::swap(out[i], out[j]);
    }
  return out;
}

}  // namespace

TEST_CASE("depth order: the stable order by view depth, window depth and position, every way", "[methods]") {
  test::BitStream rng(11);
  methods::DepthOrder order;
  int lists = 0;
  for (uint32_t n : {0u, 1u, 2u, 7u, 8u, 9u, 17u, 64u, 300u})
    for (uint32_t levels : {1u, 3u, 40u, 100000u})
      for (int displacement : {1, 3, 7, 8, 12, 40, 0, -1}) {
        const std::vector<FragmentDepths> list = makeList(rng, n, levels, displacement);
        const std::vector<uint32_t> expected = stableOrder(list);
        std::vector<uint32_t> got(n), scalar(n);
        order.sort(list.data(), n, got.data());
        order.sortScalar(list.data(), n, scalar.data());
        INFO("n " << n << ", levels " << levels << ", displacement " << displacement);
        REQUIRE(got == expected);
        REQUIRE(scalar == expected);
        ++lists;
      }
  CHECK(lists == 9 * 4 * 8);
}

TEST_CASE("depth order: keys with NaN take the scalar way", "[methods]") {
  test::BitStream rng(12);
  methods::DepthOrder order;
  std::vector<FragmentDepths> list = makeList(rng, 50, 20, 3);
  list[17].viewDepth = std::nanf("");
  list[31].windowDepth = std::nanf("");
  std::vector<uint32_t> got(50), scalar(50);
  order.sort(list.data(), 50, got.data());
  order.sortScalar(list.data(), 50, scalar.data());
  CHECK(got == scalar);
}

TEST_CASE("depth order: two lists side by side give each list's own order", "[methods]") {
  // sortPair inserts two lists' keys in one loop while both have keys, then the longer one's rest;
  // either may run out of its budget (std::stable_sort finishes it) while the other goes on, and a
  // list with NaN or of fewer than two fragments takes sort() alone.
  test::BitStream rng(13);
  methods::DepthOrder order;
  const std::vector<uint32_t> lengths = {0u, 1u, 2u, 9u, 64u, 300u};
  const std::vector<int> displacements = {1, 7, 12, 0, -1};
  int pairs = 0;
  for (uint32_t na : lengths)
    for (uint32_t nb : lengths)
      for (int da : displacements)
        for (int db : displacements) {
          std::vector<FragmentDepths> a = makeList(rng, na, 40, da), b = makeList(rng, nb, 3, db);
          if (pairs % 7 == 3 && nb > 5) b[nb / 2].viewDepth = std::nanf("");
          std::vector<uint32_t> gotA(na), gotB(nb), expectedB(nb);
          order.sortPair(a.data(), na, gotA.data(), b.data(), nb, gotB.data());
          order.sortScalar(b.data(), nb, expectedB.data());
          INFO("lengths " << na << ", " << nb << "; displacements " << da << ", " << db);
          REQUIRE(gotA == stableOrder(a));
          REQUIRE(gotB == expectedB);
          ++pairs;
        }
  CHECK(pairs == 6 * 6 * 5 * 5);
}

namespace {

// The most fragments before each one that belong after it (by view depth, then list position).
uint32_t largestDisplacement(const std::vector<FragmentDepths>& list) {
  uint32_t most = 0;
  for (size_t i = 0; i < list.size(); ++i) {
    uint32_t larger = 0;
    for (size_t j = 0; j < i; ++j) larger += list[j].viewDepth > list[i].viewDepth;
    most = std::max(most, larger);
  }
  return most;
}

}  // namespace

TEST_CASE("depth order: the AVX-512 window sorts every list within its reach and says when it did not", "[methods]") {
  if (!methods::registerOrderAvailable()) {
    WARN("this CPU has no AVX-512F: the window is not run (DepthOrder inserts)");
    return;
  }
  // Distinct view depths (ties are DepthOrder's to order afterwards), so that the expected order is
  // the stable one; lists displaced by up to 60 places, some within the window's reach (no
  // fragment with more than 32 larger ones before it) and some not; lengths whose last block holds
  // one or two registers of keys (33, 40, 41, 48, 71, 100, 300) take lastShortBlock.
  test::BitStream rng(14);
  int within = 0, refused = 0;
  for (uint32_t n : {1u, 2u, 8u, 9u, 31u, 32u, 33u, 40u, 41u, 48u, 49u, 63u, 64u, 65u, 71u, 100u, 300u})
    for (int displacement : {1, 7, 16, 24, 31, 40, 60, -1}) {
      std::vector<FragmentDepths> list = makeList(rng, n, 1000000, displacement);
      for (uint32_t i = 0; i < n; ++i) list[i].viewDepth += float(i) * 0x1p-4f;  // distinct
      std::vector<uint32_t> got(n);
      bool tie = true;
      const bool sorted = methods::orderInRegisters(list.data(), n, got.data(), tie);
      const uint32_t reach = largestDisplacement(list);
      INFO("n " << n << ", displacement " << displacement << ", largest displacement " << reach);
      if (reach <= 32) REQUIRE(sorted);
      if (sorted) {
        REQUIRE(got == stableOrder(list));
        REQUIRE_FALSE(tie);
      }
      within += reach <= 32, refused += !sorted;
    }
  CHECK(within > 40);
  CHECK(refused > 10);
  // The smallest fragment after 64 larger ones: the window has emitted 32 of them by then.
  std::vector<FragmentDepths> late(65);
  for (uint32_t i = 0; i < 65; ++i) late[i].viewDepth = float(i + 1);
  late[64].viewDepth = 0.0f;
  std::vector<uint32_t> order(65);
  bool tie = false;
  CHECK_FALSE(methods::orderInRegisters(late.data(), 65, order.data(), tie));
  // Equal view depths (−0 and +0 among them) are reported as a tie, in list order.
  std::vector<FragmentDepths> ties(20);
  for (uint32_t i = 0; i < 20; ++i) ties[i].viewDepth = i == 3 ? -0.0f : i == 11 ? 0.0f : float(20 - i);
  REQUIRE(methods::orderInRegisters(ties.data(), 20, order.data(), tie));
  CHECK(tie);
  CHECK(order[0] == 3);
  CHECK(order[1] == 11);
  // NaN in either depth refuses the list.
  ties[7].windowDepth = std::nanf("");
  CHECK_FALSE(methods::orderInRegisters(ties.data(), 20, order.data(), tie));
}
