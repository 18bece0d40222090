// Polynomial roots for MBOIT's reconstruction (polynomial_roots.cpp).
#pragma once

#include <complex>
#include <cstddef>

namespace oitref::methods {

// The real roots of a real-rooted polynomial Σ c_k x^k of degree n ≤ 4 (ascending order), and
// the roots of a complex polynomial of degree n ≤ 4 (any order): deterministic iterations in
// double (see polynomial_roots.cpp). Exposed for the tests.
// The roots come in a fixed-capacity list: these run once per fragment, where a heap allocation
// would cost as much as the iterations.
template <typename T>
struct RootList {
  T values[4];
  int count = 0;
  void push_back(const T& v) { values[count++] = v; }
  size_t size() const { return size_t(count); }
  const T& operator[](size_t i) const { return values[i]; }
  T* begin() { return values; }
  T* end() { return values + count; }
  const T* begin() const { return values; }
  const T* end() const { return values + count; }
};
RootList<double> realRootsOfRealRooted(const double* c, int n);
// realRootsOfRealRooted of `count` ≤ 4 polynomials c[l] of degree n in vector lanes (each lane the
// scalar operations, so the same bits): out[l].
void realRootsOfRealRooted4(const double* const* c, int n, int count, RootList<double>* out);
RootList<std::complex<double>> complexRoots(const std::complex<double>* c, int n);
// complexRoots of `count` polynomials c[p] of degree n, four at a time in vector lanes (each lane
// iterates as complexRoots would, so the same bits): roots[p·4 + i].
void complexRootsBatch(const std::complex<double>* const* c, int n, int count, std::complex<double>* roots);

}  // namespace oitref::methods
