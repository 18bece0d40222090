// 16-bit storage of MBOIT's moments: the fixed matrices and offsets that map normalised moments
// into [0, 1] for UNORM16, and the bias vectors the moments are pulled towards. The numbers are
// the ones published with the paper's code (Münstermann, Krumpen, Klein, Peters 2018, CC0).
#include <algorithm>

#include "methods/moment_math.h"

namespace oitref::methods {
namespace {

// Quantisation tables: odd moments (b1, b3, …) and even moments (b2, b4, …) separately. For 4
// and 6 moments the code multiplies a row vector by the matrix (q_i = Σ_j b_j·M[j][i]), for 8 the
// matrix by a column vector (q_i = Σ_j M[i][j]·b_j); the tests check that each pair inverts and
// maps point masses anywhere in [−1, 1] into [0, 1].
constexpr double kSqrt3 = 1.73205080756887729353;
constexpr float kQ4Odd[2][2] = {{1.5f, float(kSqrt3 * 0.5)}, {-2.0f, float(-kSqrt3 * 2.0 / 9.0)}};
constexpr float kQ4Even[2][2] = {{4.0f, 0.5f}, {-4.0f, 0.5f}};
constexpr float kD4Odd[2][2] = {{float(-1.0 / 3.0), -0.75f}, {float(kSqrt3), float(0.75 * kSqrt3)}};
constexpr float kD4Even[2][2] = {{0.125f, -0.125f}, {1.0f, 1.0f}};
constexpr float kQ6Odd[3][3] = {{2.5f, -1.87499864450f, 1.26583039016f},
                                {-10.0f, 4.20757543111f, -1.47644882902f},
                                {8.0f, -1.83257678661f, 0.71061660238f}};
constexpr float kQ6Even[3][3] = {{4.0f, 9.0f, -0.57759806484f}, {-4.0f, -24.0f, 4.61936647543f}, {0.0f, 16.0f, -3.07953906655f}};
constexpr float kD6Odd[3][3] = {{-0.02877789192f, 0.09995235706f, 0.25893353755f},
                                {0.47635550422f, 0.84532580931f, 0.90779616657f},
                                {1.55242808973f, 1.05472570761f, 0.83327335647f}};
constexpr float kD6Even[3][3] = {{0.00001253044f, -0.24998746956f, -0.37498825271f},
                                 {0.16668494186f, 0.16668494186f, 0.21876713299f},
                                 {0.86602540579f, 0.86602540579f, 0.81189881793f}};
constexpr float kQ8Odd[4][4] = {{3.48044635732474f, -27.5760737514826f, 55.1267384344761f, -31.5311110403183f},
                                {1.26797185782836f, -0.928755808743913f, -2.07520453231032f, 1.23598848322588f},
                                {-2.1671560004294f, 6.17950199592966f, -0.276515571579297f, -4.23583042392097f},
                                {0.974332879165755f, -0.443426830933027f, -0.360491648368785f, 0.310149466050223f}};
constexpr float kQ8Even[4][4] = {{0.280504133158527f, -0.757633844606942f, 0.392179589334688f, -0.887531871812237f},
                                 {-2.01362265883247f, 0.221551373038988f, -1.06107954265125f, 2.83887201588367f},
                                 {-7.31010494985321f, 13.9855979699139f, -0.114305766176437f, -7.4361899359832f},
                                 {-15.8954215629556f, 79.6186327084103f, -127.457278992502f, 63.7349456687829f}};
constexpr float kD8Odd[4][4] = {{-0.00482399708502382f, -0.423201508674231f, 0.0348312382605129f, 1.67179208266592f},
                                {-0.0233402218644408f, -0.832829097046478f, 0.0193406040499625f, 1.21021509068975f},
                                {-0.010888537031885f, -0.926393772997063f, -0.11723394414779f, 0.983723301818275f},
                                {-0.0308713357806732f, -0.937989172670245f, -0.218033377677099f, 0.845991731322996f}};
constexpr float kD8Even[4][4] = {{-0.976220278891035f, -0.456139260269401f, -0.0504335521016742f, 0.000838800390651085f},
                                 {-1.04828341778299f, -0.229726640510149f, 0.0259608334616091f, -0.00133632693205861f},
                                 {-1.03115268628604f, -0.077844420809897f, 0.00443408851014257f, -0.0103744938457406f},
                                 {-0.996038443434636f, 0.0175438624416783f, -0.0361414253243963f, -0.00317839994022725f}};
constexpr float kOffset6Even[3] = {0.0f, 0.0f, 0.018888946f};
constexpr float kOffset8Even[4] = {0.972481993925964f, 1.0f, 0.999179192513328f, 0.991778293073131f};

// y = v·M (rowVector) or M·v, for an n×n matrix given as rows.
template <int N>
void multiply(const float (&m)[N][N], const float* v, float* y, bool rowVector) {
  for (int i = 0; i < N; ++i) {
    float s = 0.0f;
    for (int j = 0; j < N; ++j) s += (rowVector ? v[j] * m[j][i] : m[i][j] * v[j]);
    y[i] = s;
  }
}

// b (b1…bN in order) as its odd and even halves and back.
void split(int count, const float* b, float* odd, float* even) {
  for (int i = 0; i < count / 2; ++i) odd[i] = b[2 * i], even[i] = b[2 * i + 1];
}
void join(int count, const float* odd, const float* even, float* b) {
  for (int i = 0; i < count / 2; ++i) b[2 * i] = odd[i], b[2 * i + 1] = even[i];
}

template <int N>
void mapHalves(int count, const float (&mo)[N][N], const float (&me)[N][N], const float* in, float* out, bool rowVector) {
  float odd[4], even[4], qo[4], qe[4];
  split(count, in, odd, even);
  multiply(mo, odd, qo, rowVector);
  multiply(me, even, qe, rowVector);
  join(count, qo, qe, out);
}

}  // namespace

void quantiseMoments(const MomentSet& set, const float* b, float* q) {
  if (set.trigonometric) {
    for (int k = 0; k < set.reals(); ++k) q[k] = b[k] * 0.5f;
    return;
  }
  if (set.count == 4) mapHalves(4, kQ4Odd, kQ4Even, b, q, true);
  else if (set.count == 6) mapHalves(6, kQ6Odd, kQ6Even, b, q, true);
  else mapHalves(8, kQ8Odd, kQ8Even, b, q, false);
}

void offsetQuantised(const MomentSet& set, float* q, float sign) {
  if (set.trigonometric) {
    for (int k = 0; k < set.reals(); ++k) q[k] += 0.5f * sign;
    return;
  }
  for (int i = 0; i < set.count / 2; ++i) {
    q[2 * i] += 0.5f * sign;
    if (set.count == 6) q[2 * i + 1] += kOffset6Even[i] * sign;
    if (set.count == 8) q[2 * i + 1] += kOffset8Even[i] * sign;
  }
}

void dequantiseMoments(const MomentSet& set, const float* stored, float* b) {
  if (set.trigonometric) {
    for (int k = 0; k < set.reals(); ++k) b[k] = stored[k] * 2.0f - 1.0f;
    return;
  }
  float q[8];
  std::copy(stored, stored + set.count, q);
  offsetQuantised(set, q, -1.0f);
  if (set.count == 4) mapHalves(4, kD4Odd, kD4Even, q, b, true);
  else if (set.count == 6) mapHalves(6, kD6Odd, kD6Even, q, b, true);
  else mapHalves(8, kD8Odd, kD8Even, q, b, false);
}

const float* powerBiasVector(int count, bool quantised) {
  static const float v4[4] = {0, 0.375f, 0, 0.375f}, v4q[4] = {0, 0.628f, 0, 0.628f};
  static const float v6[6] = {0, 0.48f, 0, 0.451f, 0, 0.45f}, v6q[6] = {0, 0.5566f, 0, 0.489f, 0, 0.47869382f};
  static const float v8[8] = {0, 0.75f, 0, 0.67666666666666664f, 0, 0.63f, 0, 0.60030303030303034f};
  static const float v8q[8] = {0, 0.42474916387959866f, 0, 0.22407802675585284f, 0, 0.15369230769230768f, 0, 0.12900440529089119f};
  if (count == 4) return quantised ? v4q : v4;
  return count == 6 ? (quantised ? v6q : v6) : (quantised ? v8q : v8);
}

}  // namespace oitref::methods
