// `oitref render` and `oitref methods`.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "oitref/oit/method.h"
#include "tools/commands.h"
#include "oitref/oit/image_io.h"
#include "tools/number_parse.h"
#include "tools/suite.h"

namespace oitref::tools {
namespace {

struct RenderOptions {
  std::string scene, method = "abuffer", out, dump, size, profile = "exact", memoryLimit;
  std::vector<std::string> sets;
  int threads = 0, repeat = 1;
  bool json = false;
};

int runRender(const RenderOptions& o) {
  FrameRequest request;
  request.method = o.method;
  request.options = methodOptionsFrom(o.sets);
  makeMethod(request.method, request.options);  // a bad method or option refuses before the scene loads
  if (!o.out.empty()) checkImagePath(o.out);  // before the frame: a bad path refuses at once
  request.memoryLimit = memoryLimitFrom(o.memoryLimit);
  Scene loaded = loadScene(o.scene, request.memoryLimit);
  if (!o.size.empty()) parseSize(o.size, "--size", request.width, request.height);
  request.profile = parseProfile(o.profile);
  request.threads = o.threads;
  FrameRenderer frames(std::move(loaded), request);  // repeated frames reuse their attachments
  const Scene& scene = frames.scene();
  const Method* method = &frames.method();
  const Profile& profile = request.profile;
  Renderer& renderer = frames.renderer();
  const MethodOptions resolved(method->info(), request.options);
  // The frame's and each pass's median over the repeats (a frame's passes are the same each time;
  // one frame's pass times alone moved by a third between runs here).
  const auto medianOf = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::vector<double> frameMs;
  std::vector<std::vector<double>> passMs;
  for (int i = 0; i < o.repeat; ++i) {
    const FrameResult& frame = frames.render();
    frameMs.push_back(frame.frameMs());
    passMs.resize(frame.passes.size());
    for (size_t p = 0; p < frame.passes.size(); ++p) passMs[p].push_back(frame.passes[p].ms);
  }
  const FrameResult& result = frames.result();
  const double median = medianOf(frameMs);
  const auto passMedian = [&](size_t p) { return p < passMs.size() ? medianOf(passMs[p]) : result.passes[p].ms; };
  if (!o.out.empty()) {
    writeImage(o.out, lowerExtension(o.out) == ".png" ? result.final8 : result.finalFloat);
  }
  if (!o.dump.empty()) {
    std::filesystem::create_directories(o.dump);
    for (const auto& [name, image] : result.dump) {
      const bool png = image.format().encoding() == ChannelEncoding::Unorm && !image.format().isPacked();
      writeImage((std::filesystem::path(o.dump) / (name + (png ? ".png" : ".exr"))).string(), image);
    }
  }
  if (o.json) {
    std::printf("{\"method\": %s, \"options\": {", jsonString(o.method).c_str());
    bool first = true;
    for (const auto& [k, v] : resolved.all()) std::printf("%s%s: %s", first ? "" : ", ", jsonString(k).c_str(), jsonString(v).c_str()), first = false;
    std::printf("}, \"scene\": %s, \"width\": %d, \"height\": %d, \"profile\": %s, \"threads\": %d, \"passes\": [",
                jsonString(o.scene).c_str(), scene.width, scene.height, jsonString(profile.name).c_str(), renderer.threads());
    for (size_t i = 0; i < result.passes.size(); ++i)
      std::printf("%s{\"name\": %s, \"ms\": %.4f, \"fragments\": %llu}", i ? ", " : "", jsonString(result.passes[i].name).c_str(),
                  passMedian(i), (unsigned long long)result.passes[i].stats.fragmentsShaded);
    std::printf("], \"stats\": {");
    first = true;
    for (const FrameStats::Entry& e : result.stats.entries()) {
      std::string value = e.text();
      if (std::holds_alternative<std::string>(e.value)) value = jsonString(value);
      else if (std::holds_alternative<bool>(e.value)) value = std::get<bool>(e.value) ? "true" : "false";
      else if (std::holds_alternative<double>(e.value)) value = jsonNumber(std::get<double>(e.value));
      std::printf("%s%s: %s", first ? "" : ", ", jsonString(e.key).c_str(), value.c_str()), first = false;
    }
    std::printf("}, \"frame_ms\": %.4f, \"bytes_per_pixel\": %d, \"fragments\": %llu, \"sha256\": %s}\n", median,
                method->bytesPerPixel(), (unsigned long long)result.fragmentsShaded(), jsonString(frameHash(result)).c_str());
    return 0;
  }
  std::printf("%s  %s  %dx%d  threads %d  profile %s\n", o.scene.c_str(), o.method.c_str(), scene.width, scene.height,
              renderer.threads(), profile.describe().c_str());
  for (const auto& [k, v] : resolved.all()) std::printf("  option %s=%s\n", k.c_str(), v.c_str());
  std::printf("attachments (%d bytes per pixel):\n", method->bytesPerPixel());
  for (const AttachmentDecl& a : method->attachments())
    std::printf("  %-8s %-8s %2d B  %s\n", a.name.c_str(), a.formatName().c_str(), a.bytesPerTexel(), a.purpose.c_str());
  std::printf("passes%s:\n", o.repeat > 1 ? (" (median of " + std::to_string(o.repeat) + " each)").c_str() : "");
  for (size_t i = 0; i < result.passes.size(); ++i) {
    const PassReport& p = result.passes[i];
    std::printf("  %-16s %9.2f ms %12llu fragments shaded\n", p.name.c_str(), passMedian(i), (unsigned long long)p.stats.fragmentsShaded);
  }
  for (const auto& [k, v] : result.stats.lines()) std::printf("  %s: %s\n", k.c_str(), v.c_str());
  std::printf("pixels sha256 %s\n", frameHash(result).c_str());
  std::printf("frame %.2f ms%s\n", median, o.repeat > 1 ? (" (median of " + std::to_string(o.repeat) + ")").c_str() : "");
  if (!o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene with one OIT method");
  cmd->add_option("scene", o->scene, "Scene JSON file")->required();
  cmd->add_option("--method", o->method, "Method (see `oitref methods`)")->capture_default_str();
  addMethodSetOption(cmd, o->sets);
  addThreadsOption(cmd, o->threads);
  addSizeOption(cmd, o->size, "Override the scene's resolution, WxH");
  addProfileOption(cmd, o->profile);
  nonEmptyPath(cmd->add_option("--out", o->out, "Output image: .exr (float RGBA) or .png (the final RGBA8 bits)"));
  nonEmptyPath(cmd->add_option("--dump", o->dump, "Write every colour attachment into this folder"));
  cmd->add_option("--repeat", o->repeat, "Render N times, report the median frame and pass times")->check(CLI::Range(1, 1000));
  cmd->add_flag("--json", o->json, "Print the summary as one JSON object");
  addMemoryLimitOption(cmd, o->memoryLimit);
  cmd->callback([o, &exitCode] {
    exitCode = runReportingErrors("render", [&] {
      return runRender(*o);
    });
  });
}

void addMethodsCommand(CLI::App& app, int& exitCode) {
  CLI::App* cmd = app.add_subcommand("methods", "List the OIT methods and their options");
  cmd->callback([&exitCode] {
    for (const MethodInfo& m : allMethods()) {
      std::printf("%-10s %s\n", m.name.c_str(), m.summary.c_str());
      for (const MethodOption& opt : m.options) {
        std::string choices;
        for (const std::string& c : opt.choices) choices += (choices.empty() ? "" : "|") + c;
        if (choices.empty()) choices = opt.number.describe();
        std::printf("    %s=%s  %s%s\n", opt.key.c_str(), opt.defaultValue.c_str(), opt.meaning.c_str(),
                    choices.empty() ? "" : ("  [" + choices + "]").c_str());
      }
      std::string presets = "none";
      for (const MethodPreset& p : m.presets) presets += "|" + p.name;
      if (!m.presets.empty()) std::printf("    preset=none  [%s], the options given beside it still apply:\n", presets.c_str());
      for (const MethodPreset& p : m.presets) {
        std::string values;
        for (const auto& [key, value] : p.values) values += " " + key + "=" + value;
        std::printf("      preset=%s: %s;%s\n", p.name.c_str(), p.meaning.c_str(), values.c_str());
      }
      if (!m.nonFiniteWhen.empty()) std::printf("    non-finite pixels: %s\n", m.nonFiniteWhen.c_str());
    }
    exitCode = 0;
  });
}

}  // namespace oitref::tools
