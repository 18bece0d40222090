// LDR ꟻLIP, following Andersson et al., "FLIP: A Difference Evaluator for Alternating Images"
// (HPG 2020), section by section. Everything is computed in double.
//
// 0. Input. Each image's RGB, clamped to [0, 1] (NaN → 0), is read as sRGB-encoded and decoded
//    with the sRGB transfer function (IEC 61966-2-1).
// 1. Colour pipeline (paper §4.1).
//    a. Linear RGB → XYZ (D65) → YCxCz, the opponent space of Zhang and Wandell: Y = 116·y − 16,
//       Cx = 500·(x − y), Cz = 200·(y − z), with x, y, z the XYZ values over the white point.
//    b. Each channel is convolved with its contrast sensitivity function, a sum of two Gaussians
//       in visual degrees: S(r) = a1·√(π/b1)·exp(−π²r²/b1) + a2·√(π/b2)·exp(−π²r²/b2), with
//       (a1, b1, a2, b2) = (1, 0.0047, 0, 1e-5) achromatic, (1, 0.0053, 0, 1e-5) red–green,
//       (34.1, 0.04, 13.5, 0.025) blue–yellow, sampled on the pixel grid (1/ppd degrees per
//       pixel) out to r = ⌈3·√(b_max / 2π²)·ppd⌉ pixels and normalised to sum 1. Borders repeat
//       the edge pixel.
//    c. Filtered YCxCz → linear RGB, clamped to [0, 1] (back into the displayable gamut), then
//       → CIELAB, and Hunt-adjusted: a and b scaled by 0.01·L*.
//    d. HyAB distance |ΔL| + √(Δa² + Δb²), raised to q_c = 0.7.
//    e. Mapped to [0, 1]: with c_max the same distance between Hunt-adjusted green and blue (the
//       largest between any two colours of the gamut), errors below p_c·c_max (p_c = 0.4) map
//       linearly to [0, p_t] (p_t = 0.95) and the rest linearly to (p_t, 1].
// 2. Feature pipeline (paper §4.2), on the achromatic y = (Y + 16) / 116 of the unfiltered
//    image, in [0, 1].
//    a. Edge and point detectors: the first and second x-derivatives of a Gaussian of
//       σ = 0.5·w·ppd pixels (w = 0.082°, the peak-to-trough width of human edge detection),
//       radius ⌈3σ⌉, with the positive weights normalised to sum 1 and the negative to −1; the
//       y-direction kernels are their transposes. Each detector gives a 2-vector per pixel.
//    b. ΔE_f = (max(|‖edge_ref‖ − ‖edge_test‖|, |‖point_ref‖ − ‖point_test‖|) / √2)^q_f,
//       q_f = 0.5.
// 3. ΔE = ΔE_c^(1 − ΔE_f): features sharpen the colour difference where they differ.
//
// Every kernel here is a product of a function of x and a function of y (a sum of two such
// products for blue–yellow), so the 2D correlations are done as two 1D passes; the sums are the
// same as the 2D kernel's up to rounding.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "oitref/oit/metrics.h"

namespace oitref {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double qc = 0.7, pc = 0.4, pt = 0.95, qf = 0.5, edgeWidthDegrees = 0.082;

// sRGB primaries and D65 white (IEC 61966-2-1), linear RGB → XYZ and its inverse.
constexpr double kRgbToXyz[3][3] = {{10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794},
                                    {2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897},
                                    {1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382}};

struct Vec3 {
  double v[3];
};

Vec3 multiply(const double m[3][3], const Vec3& c) {
  Vec3 r{};
  for (int i = 0; i < 3; ++i) r.v[i] = m[i][0] * c.v[0] + m[i][1] * c.v[1] + m[i][2] * c.v[2];
  return r;
}

struct ColourSpace {
  double xyzToRgb[3][3];
  Vec3 white;  // XYZ of linear RGB (1, 1, 1)

  ColourSpace() {
    white = multiply(kRgbToXyz, {{1, 1, 1}});
    // Inverse by cofactors.
    const auto& m = kRgbToXyz;
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
        xyzToRgb[i][j] = (m[a][c] * m[b][d] - m[a][d] * m[b][c]) / det;
      }
  }

  Vec3 toYCxCz(const Vec3& linear) const {
    const Vec3 xyz = multiply(kRgbToXyz, linear);
    const double x = xyz.v[0] / white.v[0], y = xyz.v[1] / white.v[1], z = xyz.v[2] / white.v[2];
    return {{116 * y - 16, 500 * (x - y), 200 * (y - z)}};
  }
  Vec3 linearFromYCxCz(const Vec3& o) const {
    const double y = (o.v[0] + 16) / 116, x = y + o.v[1] / 500, z = y - o.v[2] / 200;
    return multiply(xyzToRgb, {{x * white.v[0], y * white.v[1], z * white.v[2]}});
  }
  // CIELAB, then the Hunt adjustment (a, b scaled by 0.01·L*).
  Vec3 huntLab(const Vec3& linear) const {
    const Vec3 xyz = multiply(kRgbToXyz, linear);
    constexpr double delta = 6.0 / 29;
    auto f = [&](double t) { return t > delta * delta * delta ? std::cbrt(t) : t / (3 * delta * delta) + 4.0 / 29; };
    const double fx = f(xyz.v[0] / white.v[0]), fy = f(xyz.v[1] / white.v[1]), fz = f(xyz.v[2] / white.v[2]);
    const double L = 116 * fy - 16;
    return {{L, 0.01 * L * 500 * (fx - fy), 0.01 * L * 200 * (fy - fz)}};
  }
};

double hyab(const Vec3& a, const Vec3& b) {
  return std::fabs(a.v[0] - b.v[0]) + std::hypot(a.v[1] - b.v[1], a.v[2] - b.v[2]);
}

double srgbDecode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// f(x) with the last argument's result kept: flat regions of an image repeat a value, and their
// pixels then skip the call (the same function of the same bits, so the same result).
template <typename Arg, typename Result>
struct LastResult {
  Arg arg{};
  Result result{};
  bool held = false;
  template <typename F>
  const Result& operator()(const Arg& x, F f) {
    if (!held || std::memcmp(&x, &arg, sizeof x) != 0) arg = x, result = f(x), held = true;
    return result;
  }
};

// std::pow(x, y) for x ≥ 0 and y > 0 that is not an odd integer: +0 for x = 0 without the call
// (C17 F.10.4.4: pow(±0, y) is +0 for such y), where the images agree.
double powOfNonNegative(double x, double y) { return x == 0.0 ? 0.0 : std::pow(x, y); }

double displayed(float value) { return std::isnan(value) ? 0.0 : std::clamp(double(value), 0.0, 1.0); }

// One channel of an image, row-major.
struct Plane {
  int width, height;
  std::vector<double> v;
};

// out(x, y) = Σ_i Σ_j ky[j]·kx[i]·in(x + i − r, y + j − r), borders repeating the edge: first
// along rows, then along columns. Each output sums its taps in kernel order from 0, as a loop per
// pixel would; the loops run over whole rows (a tap at a time, x innermost) so that they vectorise.
Plane correlate(const Plane& in, const std::vector<double>& kx, const std::vector<double>& ky) {
  const int w = in.width, h = in.height;
  const int rx = int(kx.size() / 2), ry = int(ky.size() / 2);
  Plane rows{w, h, std::vector<double>(in.v.size())};
  std::vector<double> padded(size_t(w + 2 * rx));
  for (int y = 0; y < h; ++y) {
    const double* src = in.v.data() + size_t(y) * w;
    for (int x = 0; x < w + 2 * rx; ++x) padded[size_t(x)] = src[std::clamp(x - rx, 0, w - 1)];
    double* dst = rows.v.data() + size_t(y) * w;
    std::fill(dst, dst + w, 0.0);
    for (int i = 0; i < int(kx.size()); ++i) {
      const double k = kx[size_t(i)];
      const double* tap = padded.data() + i;
      for (int x = 0; x < w; ++x) dst[x] += k * tap[x];
    }
  }
  Plane out{w, h, std::vector<double>(in.v.size())};
  for (int y = 0; y < h; ++y) {
    double* dst = out.v.data() + size_t(y) * w;
    for (int j = 0; j < int(ky.size()); ++j) {
      const double k = ky[size_t(j)];
      const double* tap = rows.v.data() + size_t(std::clamp(y + j - ry, 0, h - 1)) * w;
      for (int x = 0; x < w; ++x) dst[x] += k * tap[x];
    }
  }
  return out;
}

struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kAchromatic{1, 0.0047, 0, 1e-5}, kRedGreen{1, 0.0053, 0, 1e-5}, kBlueYellow{34.1, 0.04, 13.5, 0.025};

// Step 1b for one channel: the CSF's two Gaussian terms as separable kernels, weighted so the
// whole 2D kernel sums to 1.
Plane csfFilter(const Plane& in, const Csf& csf, double ppd) {
  const double bMax = std::max({kAchromatic.b1, kAchromatic.b2, kRedGreen.b1, kRedGreen.b2, kBlueYellow.b1, kBlueYellow.b2});
  const int r = int(std::ceil(3 * std::sqrt(bMax / (2 * kPi * kPi)) * ppd));
  auto gaussian = [&](double b) {
    std::vector<double> g(2 * r + 1);
    for (int i = -r; i <= r; ++i) g[i + r] = std::exp(-kPi * kPi * (i / ppd) * (i / ppd) / b);
    return g;
  };
  const std::vector<double> g1 = gaussian(csf.b1), g2 = gaussian(csf.b2);
  double s1 = 0, s2 = 0;
  for (double w : g1) s1 += w;
  for (double w : g2) s2 += w;
  const double w1 = csf.a1 * std::sqrt(kPi / csf.b1), w2 = csf.a2 * std::sqrt(kPi / csf.b2);
  const double total = w1 * s1 * s1 + w2 * s2 * s2;  // the 2D kernel's sum
  std::vector<double> k1 = g1;
  for (double& w : k1) w *= w1 / total;
  Plane out = correlate(in, k1, g1);
  if (csf.a2 != 0) {
    std::vector<double> k2 = g2;
    for (double& w : k2) w *= w2 / total;
    const Plane second = correlate(in, k2, g2);
    for (size_t i = 0; i < out.v.size(); ++i) out.v[i] += second.v[i];
  }
  return out;
}

// Step 2a: ‖(response to the x kernel, response to its transpose)‖ per pixel.
std::vector<double> featureMagnitude(const Plane& y, double ppd, bool points) {
  const double sd = 0.5 * edgeWidthDegrees * ppd;
  const int r = int(std::ceil(3 * sd));
  std::vector<double> along(2 * r + 1), across(2 * r + 1);
  double positive = 0, negative = 0, acrossSum = 0;
  for (int i = -r; i <= r; ++i) {
    const double g = std::exp(-double(i) * i / (2 * sd * sd));
    along[i + r] = points ? (double(i) * i / (sd * sd) - 1) * g : -double(i) * g;
    across[i + r] = g;
    acrossSum += g;
    (along[i + r] > 0 ? positive : negative) += along[i + r];
  }
  // The 2D kernel is along(x)·across(y); its positive part sums to positive·acrossSum.
  for (double& w : along) w = w > 0 ? w / (positive * acrossSum) : w / (-negative * acrossSum);
  const Plane gx = correlate(y, along, across), gy = correlate(y, across, along);
  std::vector<double> magnitude(y.v.size());
  for (size_t i = 0; i < magnitude.size(); ++i) magnitude[i] = std::hypot(gx.v[i], gy.v[i]);
  return magnitude;
}

struct Opponent {
  Plane opponent[3];  // Y, Cx, Cz
  Plane achromatic;   // y = (Y + 16) / 116
};

Opponent prepare(const Image& image, const ColourSpace& space) {
  const int w = image.width(), h = image.height();
  const int channels = image.format().channels;
  Opponent p;
  for (Plane& plane : p.opponent) plane = {w, h, std::vector<double>(size_t(w) * h)};
  p.achromatic = {w, h, std::vector<double>(size_t(w) * h)};
  LastResult<double, double> decoded[3];
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec4 v = image.fetch(x, y);
      Vec3 linear{};
      for (int c = 0; c < 3; ++c) linear.v[c] = decoded[c](displayed(v[channels >= 3 ? c : 0]), srgbDecode);
      const Vec3 o = space.toYCxCz(linear);
      const size_t i = size_t(y) * w + x;
      for (int c = 0; c < 3; ++c) p.opponent[c].v[i] = o.v[c];
      p.achromatic.v[i] = (o.v[0] + 16) / 116;
    }
  return p;
}

// Steps 1b–1c: filtered, back in gamut, Hunt-adjusted CIELAB.
std::vector<Vec3> perceived(const Opponent& p, const ColourSpace& space, double ppd) {
  const Plane f[3] = {csfFilter(p.opponent[0], kAchromatic, ppd), csfFilter(p.opponent[1], kRedGreen, ppd),
                      csfFilter(p.opponent[2], kBlueYellow, ppd)};
  std::vector<Vec3> out(f[0].v.size());
  LastResult<Vec3, Vec3> lab;
  for (size_t i = 0; i < out.size(); ++i) {
    Vec3 linear = space.linearFromYCxCz({{f[0].v[i], f[1].v[i], f[2].v[i]}});
    for (double& c : linear.v) c = std::clamp(c, 0.0, 1.0);
    out[i] = lab(linear, [&](const Vec3& l) { return space.huntLab(l); });
  }
  return out;
}

}  // namespace

// What a comparison needs of the reference: its perceived colours and feature magnitudes.
struct FlipReference::Prepared {
  int width, height, channels;
  double ppd;
  std::vector<Vec3> lab;
  std::vector<double> edges, points;
};

FlipReference::FlipReference(const Image& reference, const FlipOptions& options) {
  if (!(options.pixelsPerDegree > 0) || options.pixelsPerDegree > 1000)
    throw std::invalid_argument("pixels per degree must be in (0, 1000], got " + std::to_string(options.pixelsPerDegree));
  const double ppd = options.pixelsPerDegree;
  const ColourSpace space;
  const Opponent ref = prepare(reference, space);
  prepared_ = std::make_shared<const Prepared>(Prepared{reference.width(), reference.height(),
                                                        reference.format().channels, ppd, perceived(ref, space, ppd),
                                                        featureMagnitude(ref.achromatic, ppd, false),
                                                        featureMagnitude(ref.achromatic, ppd, true)});
}

FlipResult FlipReference::compare(const Image& test) const {
  const Prepared& ref = *prepared_;
  if (ref.width != test.width() || ref.height != test.height())
    throw std::invalid_argument("images differ in size: " + std::to_string(ref.width) + "x" +
                                std::to_string(ref.height) + " and " + std::to_string(test.width()) + "x" +
                                std::to_string(test.height()));
  if (ref.channels != test.format().channels)
    throw std::invalid_argument("images differ in channel count: " + std::to_string(ref.channels) +
                                " and " + std::to_string(test.format().channels));
  const double ppd = ref.ppd;
  const ColourSpace space;
  const Opponent tst = prepare(test, space);
  const std::vector<Vec3> labTest = perceived(tst, space, ppd);
  const double cmax = std::pow(hyab(space.huntLab({{0, 1, 0}}), space.huntLab({{0, 0, 1}})), qc);
  const std::vector<double> edgeTest = featureMagnitude(tst.achromatic, ppd, false),
                            pointTest = featureMagnitude(tst.achromatic, ppd, true);

  FlipResult r;
  r.width = ref.width, r.height = ref.height;
  const size_t n = size_t(r.width) * r.height;
  r.error.resize(n), r.colour.resize(n), r.feature.resize(n);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double c = powOfNonNegative(hyab(ref.lab[i], labTest[i]), qc);
    r.colour[i] = c < pc * cmax ? pt / (pc * cmax) * c : pt + (c - pc * cmax) / (cmax - pc * cmax) * (1 - pt);
    const double featureDifference =
        std::max(std::fabs(ref.edges[i] - edgeTest[i]), std::fabs(ref.points[i] - pointTest[i]));
    r.feature[i] = powOfNonNegative(featureDifference / std::sqrt(2.0), qf);
    // pow(x, 1) is x (pow is within an ulp of the exact x^y); colour ≥ 0 and 1 − feature ≤ 1.
    const double exponent = 1 - r.feature[i];
    r.error[i] = exponent == 1.0 ? r.colour[i] : exponent > 0.0 ? powOfNonNegative(r.colour[i], exponent)
                                                                 : std::pow(r.colour[i], exponent);
    sum += r.error[i];
    r.max = std::max(r.max, r.error[i]);
  }
  r.mean = sum / double(n);
  return r;
}

FlipResult flip(const Image& reference, const Image& test, const FlipOptions& options) {
  return FlipReference(reference, options).compare(test);
}

}  // namespace oitref
