// The methods' deterministic exp and log (src/oit/methods/det_math.h), one thread: nanoseconds a
// value for MBOIT's and MT's batches — float(detExp) of the weights, float(detLog) of the optical
// depths, in batches of 64 as the shaders call them — beside the one-at-a-time functions they
// stand for. Numbers are printed, never asserted; the batches' bits are compared and the count of
// differing values printed (0: the tests check the same).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "methods/det_math.h"

using namespace oitref::methods;

namespace {

constexpr int kBatch = 64;
volatile float sink;  // keeps the scalar loops' results alive

template <typename F>
double nsPerValue(int repeat, size_t n, F&& run) {
  std::vector<double> ns;
  run();  // warm-up
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    ns.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / double(n));
  }
  std::sort(ns.begin(), ns.end());
  return ns[ns.size() / 2];
}

size_t differing(const std::vector<float>& a, const std::vector<float>& b) {
  size_t d = 0;
  for (size_t i = 0; i < a.size(); ++i) d += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 5;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else {
      std::fprintf(stderr, "usage: oitref_det_math_bench [--repeat N]\n");
      return 2;
    }
  }
  constexpr size_t n = size_t(1) << 21;
  std::mt19937_64 rng(1);
  // MBOIT's weight exponents −b0·absorbance, and 1 − α of its optical depths.
  std::vector<double> exponents(n), logArguments(n), oneAlpha(n, 1.0 - 0.35);
  for (double& x : exponents) x = std::uniform_real_distribution<double>(-20.0, 0.0)(rng);
  for (double& x : logArguments) x = std::uniform_real_distribution<double>(0x1p-20, 1.0)(rng);
  std::vector<float> batched(n), single(n);

  std::printf("oitref det_math benchmark, %zu values, batches of %d, median of %d runs, one thread\n", n, kBatch, repeat);
  std::printf("%-34s %10s %10s\n", "case", "ns/value", "differing");
  auto row = [](const char* name, double ns, long diff) {
    if (diff < 0) std::printf("%-34s %10.2f %10s\n", name, ns, "");
    else std::printf("%-34s %10.2f %10ld\n", name, ns, diff);
  };

  const double expBatch = nsPerValue(repeat, n, [&] {
    for (size_t i = 0; i < n; i += kBatch) detExpFloatBatch(exponents.data() + i, batched.data() + i, kBatch);
  });
  const double expOne = nsPerValue(repeat, n, [&] {
    for (size_t i = 0; i < n; ++i) single[i] = float(detExp(exponents[i]));
  });
  row("float(detExp), detExpFloatBatch", expBatch, long(differing(batched, single)));
  row("float(detExp), one at a time", expOne, -1);

  const double logBatch = nsPerValue(repeat, n, [&] {
    for (size_t i = 0; i < n; i += kBatch) detLogFloatBatch(logArguments.data() + i, batched.data() + i, kBatch);
  });
  const double logOne = nsPerValue(repeat, n, [&] {
    for (size_t i = 0; i < n; ++i) single[i] = float(detLog(logArguments[i]));
  });
  row("float(detLog), detLogFloatBatch", logBatch, long(differing(batched, single)));
  row("float(detLog), one at a time", logOne, -1);
  const double logConstant = nsPerValue(repeat, n, [&] {
    for (size_t i = 0; i < n; i += kBatch) detLogFloatBatch(oneAlpha.data() + i, batched.data() + i, kBatch);
  });
  row("float(detLog), one alpha a batch", logConstant, -1);
  sink = batched[n / 2] + single[n / 2];
  return 0;
}
