#include "tools/demo_scene.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "oitref/core/fp_environment.h"
#include "util/seeded_random.h"

namespace oitref::tools {
namespace {

constexpr int kColor = 0;  // attribute slots: rgba, then uv for the floor

Geometry transformed(const std::vector<glm::vec3>& positions, const std::vector<glm::vec4>& attributes,
                     const glm::mat4& viewProjection) {
  return Geometry::fromVertexShader(positions.size(), 4, [&](size_t v, float* out) {
    for (int k = 0; k < 4; ++k) out[k] = attributes[v][k];
    return viewProjection * glm::vec4(positions[v], 1.0f);
  });
}

Geometry floorGeometry(const glm::mat4& vp) {
  const float s = 12.0f;
  const std::vector<glm::vec3> p = {{-s, 0, -s}, {s, 0, -s}, {s, 0, s}, {-s, 0, -s}, {s, 0, s}, {-s, 0, s}};
  std::vector<glm::vec4> a;
  for (const auto& q : p) a.emplace_back(q.x, q.z, 0.0f, 1.0f);  // floor uv in attribute slots 0, 1
  return transformed(p, a, vp);
}

Geometry cloudGeometry(const glm::mat4& vp, int count, uint32_t seed) {
  util::SeededRandom rng(seed);
  std::vector<glm::vec3> p;
  std::vector<glm::vec4> a;
  for (int t = 0; t < count; ++t) {
    // Every eighth triangle is large and reaches past the camera, so it crosses the near plane.
    const bool big = t % 8 == 7;
    const glm::vec3 c(rng.uniformFloat(-3, 3), rng.uniformFloat(0.3f, 2.5f), big ? rng.uniformFloat(2, 4.5f) : rng.uniformFloat(-5, 2));
    const float r = big ? 3.0f : rng.uniformFloat(0.6f, 1.6f);
    const glm::vec4 color(rng.uniformFloat(0.1f, 1), rng.uniformFloat(0.1f, 1), rng.uniformFloat(0.1f, 1), rng.uniformFloat(0.25f, 0.75f));
    for (int k = 0; k < 3; ++k) {
      const float angle = rng.uniformFloat(0, 6.2831853f);
      p.push_back(c + r * glm::vec3(std::cos(angle), std::sin(angle), big ? rng.uniformFloat(-1, 2) : rng.uniformFloat(-0.5f, 0.5f)));
      a.push_back(color);
    }
  }
  return transformed(p, a, vp);
}

FragmentProgram floorProgram() {
  return {[](const FragmentInput& in, FragmentOutput& out) {
            const glm::vec2 uv = in.vec2At(0);
            const bool odd = (int(std::floor(uv.x)) + int(std::floor(uv.y))) & 1;
            const float v = odd ? 0.75f : 0.35f;
            out.write(0, {v, v, v * 0.9f, 1.0f});
          },
          false, false, false};
}

FragmentProgram overProgram() {
  return {[](const FragmentInput& in, FragmentOutput& out) { out.write(0, in.vec4At(kColor)); }, false, false, false};
}

// McGuire–Bavoil eq. 7 weight on view depth, colour premultiplied (JCGT 2013, listing 3).
FragmentProgram accumulateProgram() {
  return {[](const FragmentInput& in, FragmentOutput& out) {
            const glm::vec4 c = in.vec4At(kColor);
            const float z = in.viewDepth;
            const float d = 1e-5f + (z / 5.0f) * (z / 5.0f) + std::pow(z / 200.0f, 6.0f);
            const float w = c.a * std::clamp(10.0f / d, 1e-2f, 3e3f);
            out.write(0, glm::vec4(glm::vec3(c) * c.a, c.a) * w);
            out.write(1, glm::vec4(c.a));
          },
          false, false, false};
}

}  // namespace

DemoResult renderDemo(Renderer& renderer, const DemoOptions& o) {
  const DefaultFloatingPoint fp;  // the camera and scene set-up too, not just the pipeline
  const glm::mat4 proj = glm::perspective(glm::radians(60.0f), float(o.width) / float(o.height), 0.1f, 100.0f);
  const glm::mat4 view = glm::lookAt(glm::vec3(0, 1.6f, 5), glm::vec3(0, 1, 0), glm::vec3(0, 1, 0));
  const glm::mat4 vp = proj * view;
  const Geometry floor = floorGeometry(vp);
  const Geometry cloud = cloudGeometry(vp, o.triangles, o.seed);
  const glm::vec4 background(0.1f, 0.12f, 0.16f, 1.0f);

  DemoResult result;
  PipelineState opaque;
  opaque.profile = o.profile;
  opaque.depth = {true, CompareFunc::Less, true, false};
  PipelineState over = opaque;
  over.depth.writeMask = false;
  over.blend[0] = BlendState::separate(BlendEquation::Add, BlendEquation::Add, BlendFactor::SrcAlpha,
                                       BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::OneMinusSrcAlpha);

  for (const char* name : {"over_rgba8", "over_rgba16f"}) {
    Image target(parseFormat(name == std::string("over_rgba8") ? "rgba8" : "rgba16f"), o.width, o.height);
    DepthBuffer depth(DepthFormat::D24, o.width, o.height);
    target.clear(background, o.profile);
    Framebuffer fb;
    fb.color[0] = &target;
    fb.depth = &depth;
    result.passes.emplace_back(std::string(name) + " opaque", renderer.draw(fb, opaque, floor, floorProgram()));
    result.passes.emplace_back(std::string(name) + " transparent", renderer.draw(fb, over, cloud, overProgram()));
    result.images.push_back({name, std::move(target)});
  }

  // Weighted blended OIT: opaque pass, accumulation pass (MRT), full-screen resolve.
  Image opaqueColor(makeFormat(FormatId::RGBA8), o.width, o.height);
  Image accum(makeFormat(FormatId::RGBA16F), o.width, o.height);
  Image reveal(makeFormat(FormatId::R16F), o.width, o.height);
  Image resolved(makeFormat(FormatId::RGBA8), o.width, o.height);
  DepthBuffer depth(DepthFormat::D24, o.width, o.height);
  opaqueColor.clear(background, o.profile);
  accum.clear(glm::vec4(0.0f), o.profile);
  reveal.clear(glm::vec4(1.0f), o.profile);
  Framebuffer opaqueFb;
  opaqueFb.color[0] = &opaqueColor;
  opaqueFb.depth = &depth;
  result.passes.emplace_back("accum opaque", renderer.draw(opaqueFb, opaque, floor, floorProgram()));

  PipelineState accumulate = over;
  accumulate.blend[0] = BlendState::same(BlendEquation::Add, BlendFactor::One, BlendFactor::One);
  accumulate.blend[1] = BlendState::same(BlendEquation::Add, BlendFactor::Zero, BlendFactor::OneMinusSrcColor);
  Framebuffer accumFb;
  accumFb.color[0] = &accum;
  accumFb.color[1] = &reveal;
  accumFb.depth = &depth;
  result.passes.emplace_back("accum transparent", renderer.draw(accumFb, accumulate, cloud, accumulateProgram()));

  PipelineState resolve;
  resolve.profile = o.profile;
  Framebuffer resolveFb;
  resolveFb.color[0] = &resolved;
  const FragmentProgram resolveProgram{[&](const FragmentInput& in, FragmentOutput& out) {
                                         const glm::vec4 a = accum.fetch(in.x, in.y);
                                         const float r = reveal.fetch(in.x, in.y).r;
                                         const glm::vec4 c0 = opaqueColor.fetch(in.x, in.y);
                                         const glm::vec3 avg = glm::vec3(a) / std::clamp(a.a, 1e-4f, 5e4f);
                                         out.write(0, glm::vec4(avg * (1.0f - r) + glm::vec3(c0) * r, 1.0f));
                                       },
                                       false, false, false};
  result.passes.emplace_back("accum resolve", renderer.drawFullscreen(resolveFb, resolve, resolveProgram));
  result.images.push_back({"accum_rgba16f", std::move(accum)});
  result.images.push_back({"reveal_r16f", std::move(reveal)});
  result.images.push_back({"accum_resolved_rgba8", std::move(resolved)});
  return result;
}

}  // namespace oitref::tools
