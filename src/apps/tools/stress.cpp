#include "tools/stress.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <thread>

#include "oitref/oit/metrics.h"
#include "oitref/oit/frame.h"
#include "util/seeded_random.h"

namespace oitref::tools {

std::string StressConfig::label() const {
  std::string s = method;
  for (const auto& [k, v] : options) s += " " + k + "=" + v;
  return s;
}

std::vector<StressCondition> stressConditions() {
  std::vector<StressCondition> c;
  c.push_back({"base", "layers spread over view distances 1…10, near 0.1, far 100, colours in [0, 1], dark background"});
  StressCondition colocated = c[0];
  colocated.name = "colocated", colocated.description = "every layer at view distance 5";
  colocated.firstDistance = colocated.lastDistance = 5;
  c.push_back(colocated);
  StressCondition wide = c[0];
  wide.name = "wide", wide.description = "near 1e-3, far 1e5, layers spread over 1e-2…1e4";
  wide.nearPlane = 1e-3f, wide.farPlane = 1e5f, wide.firstDistance = 1e-2f, wide.lastDistance = 1e4f;
  c.push_back(wide);
  StressCondition distant = c[0];
  distant.name = "distant", distant.description = "near 0.1, far 1e5, layers spread over 1e3…5e4";
  distant.farPlane = 1e5f, distant.firstDistance = 1e3f, distant.lastDistance = 5e4f;
  c.push_back(distant);
  for (float s : {100.0f, 0.01f}) {
    StressCondition scaled = c[0];
    scaled.name = s > 1 ? "scaled_x100" : "scaled_x0.01";
    scaled.description = std::string("the base scene with every length (positions, near, far) × ") + (s > 1 ? "100" : "0.01") +
                         ": the same image for an exact method";
    scaled.sceneScale = s;
    c.push_back(scaled);
  }
  StressCondition hdr = c[0];
  hdr.name = "hdr", hdr.description = "the base scene with colours × 16 (HDR)";
  hdr.colourScale = 16;
  c.push_back(hdr);
  StressCondition bright = c[0];
  bright.name = "bright", bright.description = "the base scene over a white background";
  bright.background = glm::vec3(1.0f);
  c.push_back(bright);
  return c;
}

std::vector<StressConfig> stressConfigs() {
  std::vector<StressConfig> out;
  for (const MethodInfo& info : allMethods())
    for (const OptionValues& options : info.stressVariants) out.push_back({info.name, options});
  return out;
}

namespace {

// Layer i (0 = nearest) is at distances[i]; submission order is a fixed shuffle of the layers.
std::vector<float> layerDistances(const StressCondition& c, int layers) {
  std::vector<float> d(static_cast<size_t>(layers));
  for (int i = 0; i < layers; ++i) {
    const double t = layers > 1 ? double(i) / (layers - 1) : 0.0;
    d[size_t(i)] = float(double(c.firstDistance) * std::pow(double(c.lastDistance) / double(c.firstDistance), t));
  }
  return d;
}

std::vector<int> submissionOrder(int layers) {
  std::vector<int> order(static_cast<size_t>(layers));
  std::iota(order.begin(), order.end(), 0);
  util::SeededRandom random(1234);
  for (int i = layers - 1; i > 0; --i) std::swap(order[size_t(i)], order[random.below(uint32_t(i + 1))]);
  return order;
}

glm::vec3 layerColour(const StressCondition& c, int layer) {
  return (layer % 2 ? glm::vec3(0.1f, 0.4f, 1.0f) : glm::vec3(1.0f, 0.2f, 0.1f)) * c.colourScale;
}

bool finite(const glm::vec4& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w); }

}  // namespace

Scene stressScene(const StressCondition& c, int layers, float alpha, int width, int height) {
  Scene scene;
  scene.width = width, scene.height = height;
  scene.background = c.background;
  scene.camera.position = glm::vec3(0.0f);
  scene.camera.target = glm::vec3(0.0f, 0.0f, -c.sceneScale);
  scene.camera.fovYDegrees = 60.0f;
  scene.camera.nearPlane = c.nearPlane * c.sceneScale;
  scene.camera.farPlane = c.farPlane * c.sceneScale;
  const std::vector<float> distance = layerDistances(c, layers);
  for (int layer : submissionOrder(layers)) {
    SceneObject o;
    o.type = ObjectType::Mesh;
    o.transparentOverride = true;  // α = 1 layers stay in the transparent passes
    o.colorOverride = glm::vec4(layerColour(c, layer), alpha);
    const float z = -distance[size_t(layer)] * c.sceneScale, h = -z * 2.0f;  // twice the view's half-width
    o.mesh.positions = {{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}};
    o.mesh.colors.assign(4, glm::vec4(1.0f));
    o.mesh.indices = {0, 1, 2, 0, 2, 3};
    scene.objects.push_back(std::move(o));
  }
  return scene;
}

glm::dvec3 stressExact(const Scene& scene) {
  // Front to back by distance; equal distances keep submission order, the earlier submitted in
  // front — the tie rule of both ground truths (src/oit/methods/abuffer.cpp, src/oit/groundtruth/raycast.cpp).
  std::vector<size_t> order(scene.objects.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return scene.objects[a].mesh.positions[0].z > scene.objects[b].mesh.positions[0].z;
  });
  glm::dvec3 c(scene.background);
  for (size_t k = order.size(); k-- > 0;) {  // OVER, back to front
    const glm::dvec4 s(*scene.objects[order[k]].colorOverride);
    c = glm::dvec3(s) * s.a + c * (1.0 - s.a);
  }
  return c;
}

StressCell stressCell(const StressConfig& config, const StressCondition& condition, int layers, float alpha, int size,
                      Renderer& renderer) {
  const SceneFrames frames(stressScene(condition, layers, alpha, size, size), renderer);
  const Scene& scene = frames.scene();
  std::unique_ptr<Method> method = makeMethod(config.method, config.options);
  const FrameResult frame = frames.render(*method);
  const glm::dvec3 exact = stressExact(scene);
  double transmittance = 1;
  for (int i = 0; i < layers; ++i) transmittance *= 1.0 - double(alpha);
  StressCell cell;
  cell.layers = layers, cell.alpha = alpha;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const glm::vec4 v = frame.finalFloat.fetch(x, y);
      if (!finite(v)) {
        ++cell.nonFinitePixels;
        continue;
      }
      for (int k = 0; k < 3; ++k) cell.error = std::max(cell.error, std::fabs(double(v[k]) - exact[k]));
    }
  for (const auto& [name, image] : frame.dump) {
    bool bad = false;
    for (int y = 0; y < image.height() && !bad; ++y)
      for (int x = 0; x < image.width() && !bad; ++x) {
        const glm::vec4 v = image.fetch(x, y);
        for (int k = 0; k < image.format().channels; ++k) bad = bad || !std::isfinite(v[k]);
      }
    if (bad) cell.infIn.push_back(name);
    if (name == "reveal" && image.fetch(0, 0).r == 0.0f) {
      Image exactReveal(image.format(), 1, 1);
      exactReveal.store(0, 0, glm::vec4(float(transmittance)), exactProfile());
      cell.revealUnderflow = exactReveal.fetch(0, 0).r != 0.0f;
    }
  }
  cell.momentFallbacks = frame.stats.momentFallbacks.value_or(0);
  return cell;
}

std::vector<StressRow> stressRowsFor(const StressOptions& o) {
  auto wantedName = [](const std::vector<std::string>& list, const std::string& name) {
    return list.empty() || std::find(list.begin(), list.end(), name) != list.end();
  };
  std::vector<StressCondition> conditions;
  for (const StressCondition& c : stressConditions())
    if (wantedName(o.conditions, c.name)) conditions.push_back(c);
  for (const std::string& name : o.conditions)
    if (std::none_of(conditions.begin(), conditions.end(), [&](const StressCondition& c) { return c.name == name; }))
      throw std::invalid_argument("no stress condition '" + name + "'");
  std::vector<StressConfig> configs;
  for (const StressConfig& c : stressConfigs())
    if (wantedName(o.methods, c.method)) configs.push_back(c);
  for (const std::string& m : o.methods) makeMethod(m);  // unknown names fail with a suggestion
  std::vector<StressRow> rows;
  for (const StressCondition& condition : conditions)
    for (const StressConfig& config : configs) rows.push_back({config, condition, {}});
  return rows;
}

void renderStressRow(StressRow& row, const StressOptions& o, Renderer& renderer) {
  row.cells.assign(o.layers.size() * o.alphas.size(), StressCell{});
  // Cells are tiny (a 4×4 image is one tile, one worker), so the workers take whole cells,
  // each with a one-thread renderer of its own; a cell's bits do not depend on who renders it.
  std::atomic<size_t> next{0};
  auto work = [&] {
    Renderer own(RendererOptions{1, renderer.options().tileSize});
    for (size_t i; (i = next.fetch_add(1)) < row.cells.size();)
      row.cells[i] = stressCell(row.config, row.condition, o.layers[i / o.alphas.size()], o.alphas[i % o.alphas.size()], o.size, own);
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < renderer.threads(); ++t) workers.emplace_back(work);
  work();
  for (std::thread& w : workers) w.join();
}

std::vector<StressRow> runStress(const StressOptions& o, Renderer& renderer, const StressProgress& progress) {
  std::vector<StressRow> rows = stressRowsFor(o);
  for (size_t i = 0; i < rows.size(); ++i) {
    progress(rows[i].condition.name + ": " + rows[i].config.label(), int(i) + 1, int(rows.size()));
    renderStressRow(rows[i], o, renderer);
  }
  return rows;
}

}  // namespace oitref::tools
