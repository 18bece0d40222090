// `oitref demo`: renders the pipeline's demo scene and writes every target.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "tools/commands.h"
#include "tools/demo_scene.h"
#include "oitref/oit/image_io.h"

namespace oitref::tools {
namespace {

struct DemoCommandOptions {
  DemoOptions demo;
  std::string out = "out", profile = "exact";
  int threads = 0;
};

int runDemo(DemoCommandOptions& o) {
  o.demo.profile = parseProfile(o.profile);
  std::filesystem::create_directories(o.out);
  Renderer renderer(RendererOptions{.threads = o.threads});
  const auto t0 = std::chrono::steady_clock::now();
  DemoResult r = renderDemo(renderer, o.demo);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  std::printf("oitref demo  %dx%d  %d triangles  seed %u  threads %d  profile %s\n", o.demo.width, o.demo.height,
              o.demo.triangles, o.demo.seed, renderer.threads(), o.demo.profile.describe().c_str());
  std::printf("%-28s %10s %10s %12s %12s %9s\n", "pass", "tris in", "tris rast", "fragments", "written", "ms");
  for (const auto& [name, s] : r.passes)
    std::printf("%-28s %10llu %10llu %12llu %12llu %9.2f\n", name.c_str(), (unsigned long long)s.trianglesSubmitted,
                (unsigned long long)s.trianglesRasterized, (unsigned long long)s.fragmentsRasterized,
                (unsigned long long)s.fragmentsWritten, s.setupMs + s.rasterMs);
  std::printf("total %.2f ms\n", ms);
  for (const DemoImage& img : r.images) {
    const bool png = img.image.format().encoding() == ChannelEncoding::Unorm && !img.image.format().isPacked();
    const std::string path = (std::filesystem::path(o.out) / (img.name + (png ? ".png" : ".exr"))).string();
    writeImage(path, img.image);
    std::printf("wrote %s (%s, %dx%d)\n", path.c_str(), img.image.format().name().c_str(), img.image.width(),
                img.image.height());
  }
  return 0;
}

}  // namespace

void addDemoCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<DemoCommandOptions>();
  CLI::App* cmd = app.add_subcommand("demo", "Render the pipeline's demo scene (OVER into rgba8/rgba16f, WBOIT-style accumulate)");
  nonEmptyPath(cmd->add_option("--out", o->out, "Output folder"))->capture_default_str();
  cmd->add_option("--width", o->demo.width, "Width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", o->demo.height, "Height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--triangles", o->demo.triangles, "Translucent triangles")->check(CLI::Range(0, 10000000))->capture_default_str();
  cmd->add_option("--seed", o->demo.seed, "Random seed")->capture_default_str();
  addThreadsOption(cmd, o->threads)->capture_default_str();
  addProfileOption(cmd, o->profile);
  cmd->callback([o, &exitCode] {
    exitCode = runReportingErrors("demo", [&] {
      return runDemo(*o);
    });
  });
}

}  // namespace oitref::tools
