// Multi-layer alpha blending (Salvi & Vaidyanathan, "Multi-Layer Alpha Blending", I3D 2014) and
// the k-buffer it generalises. Each pixel keeps k nodes sorted front to back, a node being a
// premultiplied colour, a transmittance and a depth; a fragment becomes the node
// (c·α, 1 − α, z) and is inserted at its place (behind nodes of equal depth: the earlier
// submission stays in front). When k + 1 nodes result,
//   mlab:     the two farthest merge into one, at the nearer's depth:
//               rgb = near.rgb + far.rgb · near.T,  T = near.T · far.T
//             (exact OVER when nothing later falls between them; the total transmittance
//             Π(1 − α) is kept exactly in any case);
//   kbuffer:  the farthest is dropped, so the k nearest fragments remain.
// The final pass composites the nodes front to back onto the background:
//   C = Σ_i rgb_i · Π_{j<i} T_j + C0 · Π_i T_i.
// Like hybrid.cpp, one geometry pass reads and writes the pixel's nodes in raster order (ROVs,
// pixel sync); node colours are stored in `node` format, depths in R32F cleared to 2 (empty).
#include "methods/method_common.h"
#include "methods/methods.h"

namespace oitref::methods {
namespace {

constexpr float kEmptyNode = 2.0f;  // a node depth's clear value: behind every window depth

class LayeredNodes final : public OpaqueFirstMethod {
 public:
  LayeredNodes(const MethodOptions& o, bool merge)
      : k_(o.integer("k")), merge_(merge) {
    for (int i = 0; i < k_; ++i)
      nodeDepth_.push_back(declared.color("node_depth_" + std::to_string(i), "r32f", "depth of node " + std::to_string(i)));
    for (int i = 0; i < k_; ++i)
      nodeColor_.push_back(declared.color("node_color_" + std::to_string(i), o.format("node"),
                                          "premultiplied colour and transmittance of node " + std::to_string(i)));
  }
  const MethodInfo& info() const override { return merge_ ? mlabInfo() : kbufferInfo(); }
  void drawAfterOpaque(const FrameContext& context, PassRunner& run, FrameTargets& t, FrameResult& /*result*/) override {
    const int k = k_;
    const bool merge = merge_;
    const Profile& profile = context.profile;
    std::vector<Image*> depth, color;
    for (int i = 0; i < k; ++i) {
      depth.push_back(&t[nodeDepth_[size_t(i)]]);
      color.push_back(&t[nodeColor_[size_t(i)]]);
      depth.back()->clear(glm::vec4(kEmptyNode), profile);
      color.back()->clear({0, 0, 0, 1}, profile);
    }
    Framebuffer none;
    none.depth = &t.depth();
    run.transparentPass(merge ? "insert and merge" : "insert", none, transparentState(profile, BlendState{}),
                        [&](const FragmentInput& in, const glm::vec4& c, FragmentOutput&) {
                          const glm::vec4 node(glm::vec3(c) * c.a, 1.0f - c.a);
                          int place = 0;
                          while (place < k && depth[size_t(place)]->fetch(in.x, in.y).r <= in.depth) ++place;
                          const bool full = depth[size_t(k - 1)]->fetch(in.x, in.y).r != kEmptyNode;
                          if (place == k) {  // behind every node of a full list
                            if (!merge) return;  // k-buffer: dropped
                            const glm::vec4 last = color[size_t(k - 1)]->fetch(in.x, in.y);
                            color[size_t(k - 1)]->store(in.x, in.y, mergeNodes(last, node), profile);
                            return;
                          }
                          // The list's last node falls off the end or, in MLAB, merges into
                          // the node that will precede it.
                          const glm::vec4 overflow = color[size_t(k - 1)]->fetch(in.x, in.y);
                          for (int i = k - 1; i > place; --i) {
                            depth[size_t(i)]->store(in.x, in.y, depth[size_t(i - 1)]->fetch(in.x, in.y), profile);
                            color[size_t(i)]->store(in.x, in.y, color[size_t(i - 1)]->fetch(in.x, in.y), profile);
                          }
                          depth[size_t(place)]->store(in.x, in.y, glm::vec4(in.depth), profile);
                          color[size_t(place)]->store(in.x, in.y, node, profile);
                          if (full && merge) {
                            const glm::vec4 last = color[size_t(k - 1)]->fetch(in.x, in.y);
                            color[size_t(k - 1)]->store(in.x, in.y, mergeNodes(last, overflow), profile);
                          }
                        });
    run.compositeOntoBackgrounds(t, "composite", [&](const FragmentInput& in, const glm::vec3 c0[2], glm::vec3 out[2]) {
      glm::vec3 sum(0.0f);
      float transmittance = 1.0f;
      for (int i = 0; i < k && depth[size_t(i)]->fetch(in.x, in.y).r != kEmptyNode; ++i) {
        const glm::vec4 n = color[size_t(i)]->fetch(in.x, in.y);
        sum += glm::vec3(n) * transmittance;
        transmittance *= n.a;
      }
      for (int target = 0; target < 2; ++target) out[target] = sum + c0[target] * transmittance;
      return true;
    });
  }

 private:
  // `far` behind `near`, as one node.
  static glm::vec4 mergeNodes(const glm::vec4& near, const glm::vec4& far) {
    return {glm::vec3(near) + glm::vec3(far) * near.a, near.a * far.a};
  }

  int k_;
  std::vector<ColorHandle> nodeDepth_, nodeColor_;
  bool merge_;
};

std::vector<MethodOption> nodeOptions() {
  return {{"k", "4", "nodes per pixel", {"1", "2", "4", "8", "16"}},
          {"node", "rgba32f", "format of a node's premultiplied colour and transmittance", {"rgba8", "rgba16f", "rgba32f"}}};
}

}  // namespace

const MethodInfo& mlabInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{"mlab", "multi-layer alpha blending (Salvi & Vaidyanathan 2014): k nodes, the farthest two merge",
                 nodeOptions()};
    i.studyVariants = {{{"k", "2"}}, {{"k", "8"}}, {{"node", "rgba8"}}};
    i.stressVariants = {{}, {{"node", "rgba8"}}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> mlabFactory(const MethodOptions& o) { return std::make_unique<LayeredNodes>(o, true); }

const MethodInfo& kbufferInfo() {
  static const MethodInfo info = [] {
    MethodInfo i{"kbuffer", "k-buffer: the k nearest fragments composited exactly, the rest dropped",
                 nodeOptions()};
    i.studyVariants = {{{"k", "8"}}, {{"k", "16"}}};
    i.stressVariants = {{}};
    return i;
  }();
  return info;
}
std::unique_ptr<Method> kbufferFactory(const MethodOptions& o) { return std::make_unique<LayeredNodes>(o, false); }

}  // namespace oitref::methods
