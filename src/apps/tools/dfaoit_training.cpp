#include "tools/dfaoit_training.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "methods/det_math.h"
#include "oitref/oit/frame.h"
#include "util/seeded_random.h"

namespace oitref::tools {

using methods::kDfaoitHidden1;
using methods::kDfaoitHidden2;
using methods::kDfaoitInputs;
using methods::kDfaoitOutputs;
using methods::kDfaoitParameters;

std::vector<Scene> dfaoitTrainingScenes() {
  util::SeededRandom random(2024);
  std::vector<Scene> scenes;
  for (int s = 0; s < 8; ++s) {
    Scene scene;
    scene.width = scene.height = 128;
    scene.background = glm::vec3(0.0f);
    scene.camera.position = {0, 0, 5};
    scene.camera.target = {0, 0, 0};
    scene.camera.fovYDegrees = 40;
    const int clouds = 1 + s % 3;
    for (int c = 0; c < clouds; ++c) {
      SceneObject o;
      o.type = ObjectType::Particles;
      o.particleCount = 60 + int(random.below(140));
      o.seed = uint32_t(100 * s + c + 1);
      o.position = {random.uniformFloat(-0.4f, 0.4f), random.uniformFloat(-0.4f, 0.4f), random.uniformFloat(-0.5f, 0.5f)};
      o.scale = random.uniformFloat(0.8f, 1.3f);
      o.particleSize = random.uniformFloat(0.5f, 1.0f);
      o.colorOverride = glm::vec4(random.uniformFloat(0, 1), random.uniformFloat(0, 1), random.uniformFloat(0, 1),
                                  random.uniformFloat(0.01f, 0.85f));
      scene.objects.push_back(o);
    }
    scenes.push_back(scene);
  }
  // Eight scenes of 20 to 60 flat quads, each its own colour and α in [0.01, 0.85], at random
  // places and angles in a box: hard-edged layers of uniform opacity, as the paper's objects.
  for (int s = 0; s < 8; ++s) {
    Scene scene;
    scene.width = scene.height = 128;
    scene.background = glm::vec3(0.0f);
    scene.camera.position = {0, 0, 5};
    scene.camera.target = {0, 0, 0};
    scene.camera.fovYDegrees = 40;
    const int quads = 20 + int(random.below(41));
    for (int q = 0; q < quads; ++q) {
      SceneObject o;
      o.type = ObjectType::Mesh;
      o.mesh.positions = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
      o.mesh.colors.assign(4, glm::vec4(1.0f));
      o.mesh.indices = {0, 1, 2, 0, 2, 3};
      o.position = {random.uniformFloat(-0.8f, 0.8f), random.uniformFloat(-0.8f, 0.8f), random.uniformFloat(-1.0f, 1.0f)};
      o.rotationDegrees = {random.uniformFloat(-50, 50), random.uniformFloat(-50, 50), random.uniformFloat(0, 90)};
      o.scale = random.uniformFloat(0.8f, 2.5f);
      o.colorOverride = glm::vec4(random.uniformFloat(0, 1), random.uniformFloat(0, 1), random.uniformFloat(0, 1),
                                  random.uniformFloat(0.01f, 0.85f));
      scene.objects.push_back(o);
    }
    scenes.push_back(scene);
  }
  return scenes;
}

std::vector<DfaoitSample> dfaoitDataset(const std::vector<Scene>& scenes, Renderer& renderer) {
  std::vector<DfaoitSample> samples;
  for (const Scene& scene : scenes) {
    const FrameResult frame = SceneFrames(scene, renderer).render(*makeMethod("abuffer", {{"lists", "keep"}}));
    const FragmentLists& lists = frame.fragmentLists;
    for (int pixel = 0; pixel < lists.width * lists.height; ++pixel) {
      const auto stored = lists.at(pixel % lists.width, pixel / lists.width);
      std::vector<TransparentFragment> f(stored.begin(), stored.end());
      if (f.size() <= 2) continue;
      std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.windowDepth < b.windowDepth; });
      const glm::vec4 c1 = f[0].color, c2 = f[1].color;
      const glm::vec3 g = glm::vec3(c1) * c1.a + glm::vec3(c2) * ((1.0f - c1.a) * c2.a);
      glm::vec3 rest(0.0f), premultiplied(0.0f);
      float restAlpha = 0;
      for (size_t i = 0; i < f.size(); ++i) {
        premultiplied += glm::vec3(f[i].color) * f[i].color.a;
        if (i >= 2) rest += glm::vec3(f[i].color), restAlpha += f[i].color.a;
      }
      DfaoitSample s;
      methods::dfaoitFeatures(g, rest, restAlpha, float(f.size()), premultiplied, s.x);
      glm::dvec3 target(0.0);
      double transmittance = 1;
      for (const auto& fr : f) {
        target += glm::dvec3(glm::vec3(fr.color)) * double(fr.color.a) * transmittance;
        transmittance *= 1.0 - fr.color.a;
      }
      for (int k = 0; k < 3; ++k) s.target[k] = float(target[k]);
      samples.push_back(s);
    }
  }
  return samples;
}

namespace {

// Offsets of the parameter blocks (dfaoit_network.h's order).
constexpr size_t kW1 = 0, kB1 = kW1 + kDfaoitHidden1 * kDfaoitInputs, kW2 = kB1 + kDfaoitHidden1,
                 kB2 = kW2 + kDfaoitHidden2 * kDfaoitHidden1, kW3 = kB2 + kDfaoitHidden2,
                 kB3 = kW3 + kDfaoitOutputs * kDfaoitHidden2;

// The weights of each layer transposed (column j of W as a row), refreshed after every step:
// the forward pass adds input j's term to every unit at once, a vector of units, instead of
// summing one unit's inputs in a chain of dependent additions. Each unit's sum still starts at
// its bias and adds its inputs in the order j = 0, 1, …: the same bits as unit by unit.
struct TransposedWeights {
  double w1[kDfaoitInputs][kDfaoitHidden1], w2[kDfaoitHidden1][kDfaoitHidden2], w3[kDfaoitHidden2][kDfaoitOutputs];
  void from(const std::vector<double>& p) {
    for (int i = 0; i < kDfaoitHidden1; ++i)
      for (int j = 0; j < kDfaoitInputs; ++j) w1[j][i] = p[kW1 + size_t(i * kDfaoitInputs + j)];
    for (int i = 0; i < kDfaoitHidden2; ++i)
      for (int j = 0; j < kDfaoitHidden1; ++j) w2[j][i] = p[kW2 + size_t(i * kDfaoitHidden1 + j)];
    for (int i = 0; i < kDfaoitOutputs; ++i)
      for (int j = 0; j < kDfaoitHidden2; ++j) w3[j][i] = p[kW3 + size_t(i * kDfaoitHidden2 + j)];
  }
};

// Unit i of a layer: v[i] = bias[i] + Σ_j w[j][i]·in[j], the terms added in the order of j.
template <int Inputs, int Units>
void layer(const double* bias, const double (&w)[Inputs][Units], const double* in, double* v) {
  for (int i = 0; i < Units; ++i) v[i] = bias[i];
  for (int j = 0; j < Inputs; ++j)
    for (int i = 0; i < Units; ++i) v[i] += w[j][i] * in[j];
}

// One sample's forward pass up to the output layer's sums z3, in double.
struct Activations {
  double z1[kDfaoitHidden1], h1[kDfaoitHidden1], z2[kDfaoitHidden2], h2[kDfaoitHidden2], z3[kDfaoitOutputs];
};
void forward(const double* p, const TransposedWeights& t, const DfaoitSample& s, Activations& a) {
  double x[kDfaoitInputs];
  for (int j = 0; j < kDfaoitInputs; ++j) x[j] = s.x[j];
  layer(p + kB1, t.w1, x, a.z1);
  for (int i = 0; i < kDfaoitHidden1; ++i) a.h1[i] = std::max(a.z1[i], 0.0);
  layer(p + kB2, t.w2, a.h1, a.z2);
  for (int i = 0; i < kDfaoitHidden2; ++i) a.h2[i] = std::max(a.z2[i], 0.0);
  layer(p + kB3, t.w3, a.h2, a.z3);
}

// The rest of a sample's pass from its outputs' e^(−z3): y = 1 / (1 + e^(−z3)), the backward
// pass adding dLoss/dparameter to `gradient`; returns the sample's squared error summed over
// the outputs.
double backward(const double* __restrict p, const Activations& a, const DfaoitSample& s, const double* expMinusZ3,
                double scale, double* __restrict gradient) {
  double error = 0, y[kDfaoitOutputs], dz3[kDfaoitOutputs];
  for (int i = 0; i < kDfaoitOutputs; ++i) {
    y[i] = 1.0 / (1.0 + expMinusZ3[i]);
    const double d = y[i] - s.target[i];
    error += d * d;
    dz3[i] = scale * 2.0 * d * y[i] * (1.0 - y[i]);
  }
  double dh2[kDfaoitHidden2] = {};
  for (int i = 0; i < kDfaoitOutputs; ++i) {
    gradient[kB3 + i] += dz3[i];
    for (int j = 0; j < kDfaoitHidden2; ++j) {
      gradient[kW3 + i * kDfaoitHidden2 + j] += dz3[i] * a.h2[j];
      dh2[j] += p[kW3 + i * kDfaoitHidden2 + j] * dz3[i];
    }
  }
  double dh1[kDfaoitHidden1] = {};
  for (int i = 0; i < kDfaoitHidden2; ++i) {
    if (a.z2[i] <= 0) continue;
    gradient[kB2 + i] += dh2[i];
    for (int j = 0; j < kDfaoitHidden1; ++j) {
      gradient[kW2 + i * kDfaoitHidden1 + j] += dh2[i] * a.h1[j];
      dh1[j] += p[kW2 + i * kDfaoitHidden1 + j] * dh2[i];
    }
  }
  for (int i = 0; i < kDfaoitHidden1; ++i) {
    if (a.z1[i] <= 0) continue;
    gradient[kB1 + i] += dh1[i];
    for (int j = 0; j < kDfaoitInputs; ++j) gradient[kW1 + i * kDfaoitInputs + j] += dh1[i] * s.x[j];
  }
  return error;
}

}  // namespace

methods::DfaoitParameters trainDfaoit(const std::vector<DfaoitSample>& samples, const DfaoitTraining& o,
                                      const std::function<void(int, double)>& progress) {
  if (samples.empty()) throw std::invalid_argument("train-dfaoit: no training samples");
  util::SeededRandom random(o.seed);
  // He initialisation (uniform, ±√(6 / fan-in)) for the weights, zero biases.
  std::vector<double> p(kDfaoitParameters, 0.0);
  auto init = [&](size_t offset, int rows, int fanIn) {
    const double limit = std::sqrt(6.0 / fanIn);
    for (int i = 0; i < rows * fanIn; ++i) p[offset + size_t(i)] = random.uniform(-limit, limit);
  };
  init(kW1, kDfaoitHidden1, kDfaoitInputs);
  init(kW2, kDfaoitHidden2, kDfaoitHidden1);
  init(kW3, kDfaoitOutputs, kDfaoitHidden2);
  // Adam (Kingma & Ba 2014): β1 = 0.9, β2 = 0.999, ε = 1e-8.
  std::vector<double> m(kDfaoitParameters, 0.0), v(kDfaoitParameters, 0.0), gradient(kDfaoitParameters);
  const double beta1 = 0.9, beta2 = 0.999, epsilon = 1e-8;
  double beta1Power = 1, beta2Power = 1;  // β^t by products: no pow
  std::vector<uint32_t> order(samples.size());
  std::iota(order.begin(), order.end(), 0u);
  TransposedWeights transposed;
  transposed.from(p);
  constexpr size_t kGroup = 4;
  for (int epoch = 1; epoch <= o.epochs; ++epoch) {
    for (size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[random.below(uint32_t(i))]);
    double loss = 0;
    for (size_t start = 0; start < order.size(); start += size_t(o.batch)) {
      const size_t end = std::min(order.size(), start + size_t(o.batch));
      std::fill(gradient.begin(), gradient.end(), 0.0);
      const double scale = 1.0 / double((end - start) * kDfaoitOutputs);  // the mean over the batch
      // Four samples at a time: their forward passes (the parameters change only between
      // batches), their twelve sigmoids' exponentials side by side (detExpMany: each a chain of
      // sixteen divisions), then their backward passes one after another, in the batch's order.
      for (size_t k = start; k < end; k += kGroup) {
        const int g = int(std::min(kGroup, end - k));
        // The samples come in a random order from 7.5 MB: the next group's are asked for now
        // (waiting for each sample's first line was a quarter of the training's time).
        for (size_t a = k + kGroup; a < std::min(order.size(), k + 2 * kGroup); ++a) {
          const char* ahead = reinterpret_cast<const char*>(&samples[order[a]]);
          __builtin_prefetch(ahead), __builtin_prefetch(ahead + sizeof(DfaoitSample) - 1);
        }
        Activations act[kGroup];
        double minusZ3[kGroup * kDfaoitOutputs], e[kGroup * kDfaoitOutputs];
        for (int q = 0; q < g; ++q) {
          forward(p.data(), transposed, samples[order[k + size_t(q)]], act[q]);
          for (int i = 0; i < kDfaoitOutputs; ++i) minusZ3[q * kDfaoitOutputs + i] = -act[q].z3[i];
        }
        methods::detExpMany(minusZ3, e, g * kDfaoitOutputs);  // det_math.h: the same bits on every machine
        for (int q = 0; q < g; ++q)
          loss += backward(p.data(), act[q], samples[order[k + size_t(q)]], e + q * kDfaoitOutputs, scale, gradient.data());
      }
      beta1Power *= beta1, beta2Power *= beta2;
      const double c1 = 1.0 - beta1Power, c2 = 1.0 - beta2Power;
      for (size_t i = 0; i < p.size(); ++i) {
        m[i] = beta1 * m[i] + (1 - beta1) * gradient[i];
        v[i] = beta2 * v[i] + (1 - beta2) * gradient[i] * gradient[i];
        p[i] -= o.learningRate * (m[i] / c1) / (std::sqrt(v[i] / c2) + epsilon);
      }
      transposed.from(p);
    }
    progress(epoch, loss / double(order.size() * kDfaoitOutputs));
  }
  methods::DfaoitParameters out{};
  for (size_t i = 0; i < p.size(); ++i) out[i] = float(p[i]);
  return out;
}

std::string dfaoitWeightsHeader(const methods::DfaoitParameters& p, const std::string& provenance) {
  std::ostringstream o;
  o << "// The trained DFAOIT network (methods/dfaoit_network.h): 931 fp32 parameters in the order W1\n"
       "// (32×10, row-major), b1, W2 (16×32), b2, W3 (3×16), b3, written as hex floats so they load\n"
       "// bit for bit. Generated by `oitref train-dfaoit`; do not edit by hand.\n";
  std::istringstream lines(provenance);
  for (std::string line; std::getline(lines, line);) o << "// " << line << "\n";
  o << "#pragma once\n\nnamespace oitref::methods {\n\ninline constexpr float kDfaoitWeights[931] = {\n";
  for (size_t i = 0; i < p.size(); ++i) {
    char text[40];
    std::snprintf(text, sizeof text, "%a", double(p[i]));
    o << (i % 6 == 0 ? "    " : " ") << text << "f" << (i + 1 < p.size() ? "," : "") << (i % 6 == 5 || i + 1 == p.size() ? "\n" : "");
  }
  o << "};\n\n}  // namespace oitref::methods\n";
  return o.str();
}

}  // namespace oitref::tools
