// The batch forms of oitref/core/shader_builtins.h: llvmpipe's log and exp over arrays, eight
// lanes at a time with AVX2 and FMA where the CPU has them and the profile fuses (each lane's
// operations are the scalar function's, in the same order: the same bits), else one at a time.
#include <bit>
#include <cstdint>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "oitref/core/shader_builtins.h"

namespace oitref::llvmpipe {
namespace {

template <bool Exp>
[[gnu::always_inline]] inline void scalarBatch(const float* x, float* out, int n, bool fused) {
  for (int i = 0; i < n; ++i) {
    // A batch's arguments are often one value (a material's alpha): computed once.
    if (i > 0 && std::bit_cast<uint32_t>(x[i]) == std::bit_cast<uint32_t>(x[i - 1])) {
      out[i] = out[i - 1];
      continue;
    }
    out[i] = Exp ? exp(x[i], fused) : log(x[i], fused);
  }
}

#if defined(__x86_64__)
// polynomial() in lanes: odd and even terms in powers of x², then odd·x + even.
template <int N>
[[gnu::target("avx2,fma")]] inline __m256 polynomial8(__m256 x, const double (&c)[N]) {
  const __m256 x2 = _mm256_mul_ps(x, x);
  __m256 even = _mm256_setzero_ps(), odd = _mm256_setzero_ps();
  bool haveEven = false, haveOdd = false;
  for (int i = N; i--;) {
    const __m256 k = _mm256_set1_ps(float(c[i]));
    __m256& term = i % 2 == 0 ? even : odd;
    bool& have = i % 2 == 0 ? haveEven : haveOdd;
    term = have ? _mm256_fmadd_ps(x2, term, k) : k;
    have = true;
  }
  return haveOdd ? _mm256_fmadd_ps(odd, x, even) : even;
}

// exp(): x·log2 e, clamped (min and max keep a NaN, as lp_build_min_ext/max_ext do), 2^⌊x⌋ from
// the exponent bits (cvttps2dq of ⌊x⌋) times the polynomial of x − ⌊x⌋.
[[gnu::target("avx2,fma")]] void expFma(const float* x, float* out, int n) {
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    __m256 v = _mm256_mul_ps(_mm256_loadu_ps(x + i), _mm256_set1_ps(float(M_LOG2E)));
    v = _mm256_max_ps(_mm256_set1_ps(-126.99999f), _mm256_min_ps(_mm256_set1_ps(128.0f), v));
    const __m256 whole = _mm256_floor_ps(v);
    const __m256 fraction = _mm256_sub_ps(v, whole);
    const __m256i exponent = _mm256_slli_epi32(_mm256_add_epi32(_mm256_cvttps_epi32(whole), _mm256_set1_epi32(127)), 23);
    _mm256_storeu_ps(out + i, _mm256_mul_ps(_mm256_castsi256_ps(exponent), polynomial8(fraction, kExp2Polynomial)));
  }
  scalarBatch<true>(x + i, out + i, n - i, true);
}

template <bool Exp>
[[gnu::target("avx2,fma")]] void fmaBatch(const float* x, float* out, int n) {
  if constexpr (Exp) expFma(x, out, n);
  else scalarBatch<false>(x, out, n, true);
}
#endif

template <bool Exp>
void batch(const float* x, float* out, int n, bool fused) {
#if defined(__x86_64__)
  static const bool fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (fused && fma) return fmaBatch<Exp>(x, out, n);
#endif
  scalarBatch<Exp>(x, out, n, fused);
}

}  // namespace

void logBatch(const float* x, float* out, int n, bool fused) { batch<false>(x, out, n, fused); }
void expBatch(const float* x, float* out, int n, bool fused) { batch<true>(x, out, n, fused); }

}  // namespace oitref::llvmpipe
