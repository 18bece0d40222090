#include "glcheck/raster_check.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ostream>
#include <random>
#include <stdexcept>

#include "oitref/core/renderer.h"

namespace oitref::glcheck {
namespace {

// What each class of triangles puts to the test. Window coordinates are exact in fp32 where a
// class places them on a grid (w = 1 and a power-of-two viewport: ndc = x · 2/size − 1 is exact).
//   random  perspective (w in [0.3, 3]), a few crossing the near or far plane
//   grid    w = 1, vertices on the half-pixel grid: edges through pixel centres (the fill rule)
//   snap    w = 1, vertices on a 1/512-pixel grid: half of them halfway between two 1/256 steps
//           (how snapping rounds a tie)
//   wide    vertices up to 30 viewports away: clipping and the guard band
//   sliver  thin and sub-pixel triangles, half of them in perspective
const char* const kClasses[] = {"random", "grid", "snap", "wide", "sliver"};
constexpr int kClassCount = 5;

struct Triangle {
  int cls = 0;
  glm::vec4 clip[3];
  float attribute[3] = {};
};

// Uniform in [lo, hi) from 24 random bits, the same on every standard library.
struct Random {
  std::mt19937 engine;
  double uniform(double lo, double hi) { return lo + (hi - lo) * double(engine() >> 8) * 0x1p-24; }
  int integer(int lo, int hi) { return lo + int(engine() % uint32_t(hi - lo + 1)); }
};

glm::vec4 clipOf(double ndcX, double ndcY, double ndcZ, double w) {
  return {float(ndcX * w), float(ndcY * w), float(ndcZ * w), float(w)};
}

std::vector<Triangle> generateTriangles(int count, uint32_t seed, int size) {
  Random r{std::mt19937(seed)};
  const double toNdc = 2.0 / size;
  std::vector<Triangle> out(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    Triangle& t = out[size_t(i)];
    t.cls = i % kClassCount;
    for (float& a : t.attribute) a = float(r.uniform(-2.0, 2.0));
    switch (t.cls) {
      case 0:
        for (glm::vec4& v : t.clip) v = clipOf(r.uniform(-1.2, 1.2), r.uniform(-1.2, 1.2), r.uniform(-1.1, 1.1), r.uniform(0.3, 3.0));
        break;
      case 1:
        for (glm::vec4& v : t.clip)
          v = clipOf(r.integer(-4, 2 * size + 4) * 0.5 * toNdc - 1.0, r.integer(-4, 2 * size + 4) * 0.5 * toNdc - 1.0,
                     r.uniform(-0.95, 0.95), 1.0);
        break;
      case 2:
        for (glm::vec4& v : t.clip)
          v = clipOf(r.integer(-1024, (size + 2) * 512) / 512.0 * toNdc - 1.0,
                     r.integer(-1024, (size + 2) * 512) / 512.0 * toNdc - 1.0, r.uniform(-0.95, 0.95), 1.0);
        break;
      case 3:
        for (glm::vec4& v : t.clip) v = clipOf(r.uniform(-30, 30), r.uniform(-30, 30), r.uniform(-1.2, 1.2), r.uniform(0.5, 2.0));
        break;
      default: {
        const bool tiny = (i / kClassCount) % 2 == 0;
        const double cx = r.uniform(2, size - 2), cy = r.uniform(2, size - 2);
        double x[3], y[3];
        x[0] = cx, y[0] = cy;
        x[1] = cx + r.uniform(-1.5, 1.5), y[1] = cy + r.uniform(-1.5, 1.5);
        if (tiny) x[2] = cx + r.uniform(-1.5, 1.5), y[2] = cy + r.uniform(-1.5, 1.5);
        else x[2] = r.uniform(-4, size + 4), y[2] = r.uniform(-4, size + 4);
        const bool perspective = (i / (2 * kClassCount)) % 2 == 0;
        for (int k = 0; k < 3; ++k)
          t.clip[k] = clipOf(x[k] * toNdc - 1.0, y[k] * toNdc - 1.0, r.uniform(-0.95, 0.95),
                             perspective ? r.uniform(0.5, 2.0) : 1.0);
      }
    }
  }
  return out;
}

const char* kVertexShader = R"(#version 430 core
layout(location = 0) in vec4 clipPosition;
layout(location = 1) in float value;
out float vAttribute;
void main() {
  gl_Position = clipPosition;
  vAttribute = value;
})";

// viewDepth as glcheck scene's prelude writes it (1 / gl_FragCoord.w); alpha 1 marks coverage.
const char* kFragmentShader = R"(#version 430 core
in float vAttribute;
layout(location = 0) out vec4 o0;
void main() {
  o0 = vec4(vAttribute, gl_FragCoord.z, 1.0 / gl_FragCoord.w, 1.0);
})";

// One triangle's pixels: RGBA32F (attribute, z, viewDepth, covered) and the D32F depth, row 0 at
// the bottom (glReadPixels' order and oitref's).
struct Pixels {
  std::vector<float> colour;
  std::vector<uint32_t> depth;
};

std::vector<Pixels> drawOnGl(const GlContext& context, const std::vector<Triangle>& triangles, uint32_t seed, int size) {
  const GlFunctions& gl = context.gl();
  std::vector<float> vertices;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 4; ++c) vertices.push_back(t.clip[k][c]);
      vertices.push_back(t.attribute[k]);
    }
  GLuint textures[2], framebuffer, vao, buffer;
  gl.GenTextures(2, textures);
  gl.BindTexture(GL_TEXTURE_2D, textures[0]);
  gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, size, size);
  gl.BindTexture(GL_TEXTURE_2D, textures[1]);
  gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, size, size);
  gl.GenFramebuffers(1, &framebuffer);
  gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, textures[0], 0);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, textures[1], 0);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("the RGBA32F + D32F framebuffer is not complete");
  const GLenum drawBuffer = GL_COLOR_ATTACHMENT0;
  gl.DrawBuffers(1, &drawBuffer);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.GenVertexArrays(1, &vao);
  gl.BindVertexArray(vao);
  gl.GenBuffers(1, &buffer);
  gl.BindBuffer(GL_ARRAY_BUFFER, buffer);
  gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * 4), vertices.data(), GL_STATIC_DRAW);
  gl.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 20, reinterpret_cast<const void*>(0));
  gl.VertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 20, reinterpret_cast<const void*>(16));
  gl.EnableVertexAttribArray(0);
  gl.EnableVertexAttribArray(1);
  const unsigned program = linkProgram(gl, kVertexShader, kFragmentShader);
  gl.UseProgram(program);
  gl.Viewport(0, 0, size, size);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_ALWAYS);
  gl.DepthMask(GL_TRUE);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  context.check("glcheck raster set-up");

  // First, the options themselves, cleared into the target and read back (exact in RGBA32F): reads
  // recorded with other options are then an error, not a comparison of other triangles.
  const float header[4] = {float(seed >> 16), float(seed & 0xffffu), float(triangles.size()), float(size)};
  float echoed[4] = {};
  gl.ClearBufferfv(GL_COLOR, 0, header);
  gl.ReadPixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, echoed);
  if (std::memcmp(header, echoed, sizeof header) != 0) {
    char text[200];
    std::snprintf(text, sizeof text, "the GL reads are of seed %.0f, %.0f triangles, size %.0f; these options ask for seed %u, %zu, %d",
                  double(echoed[0]) * 65536.0 + double(echoed[1]), double(echoed[2]), double(echoed[3]), seed, triangles.size(), size);
    throw std::runtime_error(text);
  }
  const float zero[4] = {0, 0, 0, 0}, one = 1.0f;
  std::vector<Pixels> out(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    gl.ClearBufferfv(GL_COLOR, 0, zero);
    gl.ClearBufferfv(GL_DEPTH, 0, &one);
    gl.DrawArrays(GL_TRIANGLES, GLint(3 * t), 3);
    out[t].colour.resize(size_t(size) * size * 4);
    out[t].depth.resize(size_t(size) * size);
    gl.ReadPixels(0, 0, size, size, GL_RGBA, GL_FLOAT, out[t].colour.data());
    gl.ReadPixels(0, 0, size, size, GL_DEPTH_COMPONENT, GL_FLOAT, out[t].depth.data());
  }
  context.check("glcheck raster draws");
  gl.DeleteProgram(program);
  gl.DeleteBuffers(1, &buffer);
  gl.DeleteVertexArrays(1, &vao);
  gl.DeleteFramebuffers(1, &framebuffer);
  gl.DeleteTextures(2, textures);
  return out;
}

struct Rule {
  std::string label, profileText;
  PipelineState state;
};

// The fragment shader of kFragmentShader: (attribute, gl_FragCoord.z, viewDepth, 1).
const FragmentProgram& oitrefProgram() {
  static const FragmentProgram program = programOf([](const FragmentInput& in, FragmentOutput& out) {
    out.write(0, {in.attribute(0), in.depth, in.viewDepth, 1.0f});
  });
  return program;
}

Pixels drawOnOitref(Renderer& renderer, const Rule& rule, const Triangle& t, int size, Image& colour, DepthBuffer& depth) {
  Geometry g;
  g.attributeCount = 1;
  g.clipPositions.assign(t.clip, t.clip + 3);
  g.attributes.assign(t.attribute, t.attribute + 3);
  Framebuffer fb;
  fb.color[0] = &colour;
  fb.depth = &depth;
  fb.clearColor[0] = glm::vec4(0.0f);
  fb.clearDepth = 1.0;
  renderer.draw(fb, rule.state, g, oitrefProgram());
  Pixels p;
  p.colour.resize(size_t(size) * size * 4);
  p.depth.resize(size_t(size) * size);
  std::memcpy(p.colour.data(), colour.bytes().data(), p.colour.size() * 4);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) p.depth[size_t(y) * size + x] = depth.load(x, y);
  return p;
}

void keepLargest(double& largest, float a, float b) { largest = std::max(largest, std::fabs(double(a) - double(b))); }

void tally(RasterCheckRow& row, const Pixels& gl, const Pixels& ours) {
  ++row.triangles;
  bool coverageDiffers = false;
  for (size_t i = 0; i < gl.depth.size(); ++i) {
    const float* g = &gl.colour[4 * i];
    const float* o = &ours.colour[4 * i];
    const bool glCovers = g[3] == 1.0f, weCover = o[3] == 1.0f;
    row.glCovered += glCovers;
    row.oitrefCovered += weCover;
    if (glCovers != weCover) {
      ++row.coverageDiffers;
      coverageDiffers = true;
      continue;
    }
    if (!glCovers) continue;
    ++row.both;
    row.depthEqual += gl.depth[i] == ours.depth[i];
    keepLargest(row.depthMaxError, std::bit_cast<float>(gl.depth[i]), std::bit_cast<float>(ours.depth[i]));
    row.fragZEqual += std::bit_cast<uint32_t>(g[1]) == std::bit_cast<uint32_t>(o[1]);
    row.attributeEqual += std::bit_cast<uint32_t>(g[0]) == std::bit_cast<uint32_t>(o[0]);
    keepLargest(row.attributeMaxError, g[0], o[0]);
    row.viewDepthEqual += std::bit_cast<uint32_t>(g[2]) == std::bit_cast<uint32_t>(o[2]);
    keepLargest(row.viewDepthMaxError, g[2], o[2]);
  }
  row.trianglesWithCoverageDiffering += coverageDiffers;
}

void add(RasterCheckRow& sum, const RasterCheckRow& r) {
  sum.triangles += r.triangles, sum.glCovered += r.glCovered, sum.oitrefCovered += r.oitrefCovered;
  sum.coverageDiffers += r.coverageDiffers, sum.trianglesWithCoverageDiffering += r.trianglesWithCoverageDiffering;
  sum.both += r.both, sum.depthEqual += r.depthEqual, sum.fragZEqual += r.fragZEqual;
  sum.attributeEqual += r.attributeEqual, sum.viewDepthEqual += r.viewDepthEqual;
  sum.depthMaxError = std::max(sum.depthMaxError, r.depthMaxError);
  sum.attributeMaxError = std::max(sum.attributeMaxError, r.attributeMaxError);
  sum.viewDepthMaxError = std::max(sum.viewDepthMaxError, r.viewDepthMaxError);
}

std::string share(uint64_t part, uint64_t whole) {
  char s[32];
  std::snprintf(s, sizeof s, "%.2f %%", whole ? 100.0 * double(part) / double(whole) : 100.0);
  return s;
}

void printRows(std::ostream& out, const std::vector<RasterCheckRow>& rows) {
  char line[256];
  // Shares of the pixels both cover; "max diff": the largest |GL − oitref| there (attributes lie
  // in [−2, 2], window depth in [0, 1]).
  std::snprintf(line, sizeof line, "%-8s %5s %7s %15s %9s %10s %9s %9s %10s %9s %10s\n", "class", "tris", "GL px",
                "coverage diff", "depth eq", "max diff", "frag z eq", "attr eq", "max diff", "1/w eq", "max diff");
  out << line;
  for (const RasterCheckRow& r : rows) {
    const std::string cov = std::to_string(r.coverageDiffers) + " px (" + std::to_string(r.trianglesWithCoverageDiffering) + ")";
    std::snprintf(line, sizeof line, "%-8s %5llu %7llu %15s %9s %10.2e %9s %9s %10.2e %9s %10.2e\n", r.triangleClass.c_str(),
                  (unsigned long long)r.triangles, (unsigned long long)r.glCovered, cov.c_str(),
                  share(r.depthEqual, r.both).c_str(), r.depthMaxError, share(r.fragZEqual, r.both).c_str(),
                  share(r.attributeEqual, r.both).c_str(), r.attributeMaxError, share(r.viewDepthEqual, r.both).c_str(),
                  r.viewDepthMaxError);
    out << line;
  }
}

std::vector<Rule> rulesOf(const std::vector<std::string>& profiles, int size) {
  std::vector<Rule> rules;
  for (const std::string& text : profiles) {
    Rule rule;
    rule.profileText = text;
    rule.state.profile = parseProfile(text);
    rule.state.depth.testEnabled = true;
    rule.state.depth.func = CompareFunc::Always;
    rule.state.viewport = {0, 0, size, size};
    // Where the profile decides the fill rule (llvmpipe's, the NVIDIA GPU's), the state's is unused.
    if (rule.state.profile.raster == Rasterization::Llvmpipe || rule.state.profile.fill != FillRule::State) {
      rule.label = text;
      rules.push_back(rule);
      continue;
    }
    for (FillConvention fill : {FillConvention::TopLeft, FillConvention::BottomLeft}) {
      rule.state.raster.fill = fill;
      rule.label = text + ", fill " + toString(fill);
      rules.push_back(rule);
    }
  }
  return rules;
}

}  // namespace

RasterCheckResult runRasterCheck(const GlContext& context, const RasterCheckOptions& o, std::ostream& out) {
  if (o.size < 8 || o.size > 1024 || (o.size & (o.size - 1)))
    throw std::invalid_argument("--size must be a power of two from 8 to 1024, got " + std::to_string(o.size));
  const std::vector<Rule> rules = rulesOf(o.profiles, o.size);
  bool requireFound = o.require.empty();
  for (const Rule& r : rules) requireFound |= r.profileText == o.require;
  if (!requireFound) throw std::invalid_argument("--require " + o.require + " is not among --profiles");

  const std::vector<Triangle> triangles = generateTriangles(o.triangles, o.seed, o.size);
  const std::vector<Pixels> gl = drawOnGl(context, triangles, o.seed, o.size);
  out << triangles.size() << " triangles (seed " << o.seed << "), each alone in " << o.size << "x" << o.size
      << " pixels: D32F depth with test ALWAYS, RGBA32F (attribute, gl_FragCoord.z, 1/gl_FragCoord.w)\n";

  RasterCheckResult result;
  for (const Pixels& p : gl)
    for (size_t i = 0; i < p.depth.size(); ++i)
      if (p.colour[4 * i + 3] == 1.0f) {
        ++result.glPixels;
        result.glDepthIsFragZ += p.depth[i] == std::bit_cast<uint32_t>(p.colour[4 * i + 1]);
      }
  out << "the driver's stored depth equals its own gl_FragCoord.z at " << share(result.glDepthIsFragZ, result.glPixels)
      << " of " << result.glPixels << " covered pixels\n";

  RendererOptions ro;
  ro.threads = 1;
  Renderer renderer(ro);
  Image colour(parseFormat("rgba32f"), o.size, o.size);
  DepthBuffer depth(DepthFormat::D32F, o.size, o.size);
  bool requiredEqual = o.require.empty();
  for (const Rule& rule : rules) {
    std::vector<RasterCheckRow> rows(kClassCount + 1);
    for (int c = 0; c < kClassCount; ++c) rows[size_t(c)].triangleClass = kClasses[c];
    rows.back().triangleClass = "all";
    for (size_t t = 0; t < triangles.size(); ++t)
      tally(rows[size_t(triangles[t].cls)], gl[t], drawOnOitref(renderer, rule, triangles[t], o.size, colour, depth));
    for (int c = 0; c < kClassCount; ++c) add(rows.back(), rows[size_t(c)]);
    for (RasterCheckRow& r : rows) r.rule = rule.label;
    out << "\noitref " << rule.label << ":\n";
    printRows(out, rows);
    const RasterCheckRow& all = rows.back();
    if (rule.profileText == o.require && (o.requireCoverageOnly ? all.coverageDiffers == 0 : all.allEqual()))
      requiredEqual = true;
    result.rows.insert(result.rows.end(), rows.begin(), rows.end());
  }
  result.pass = requiredEqual;
  return result;
}

}  // namespace oitref::glcheck
