#include "tools/study_jobs.h"

#include <algorithm>
#include <filesystem>
#include <cstdio>
#include <stdexcept>

#include "oitref/core/memory_limit.h"
#include "oitref/core/profile.h"
#include "oitref/oit/scene.h"
#include "tools/number_parse.h"
#include "tools/study_report.h"
#include "tools/suite.h"

namespace oitref::tools {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A job's default share: about this many pixel-frames (pixels × the frames each configuration
// renders). The built-in scenes at their sizes make one job per scene (a minute or two of a
// core); at 1920×1080 with five runs, 21 configurations a job; at 3840×2160, 5.
constexpr double kJobPixelFrames = double(1 << 28);

int configurationsPerJob(const StudyPlanRequest& r, int width, int height, int total) {
  if (r.configurationsPerJob > 0) return std::min(r.configurationsPerJob, total);
  const double perConfiguration = double(width) * double(height) * double(r.options.runs + 1);
  return std::clamp(int(kJobPixelFrames / perConfiguration), 1, total);
}

json variantJson(const StudyVariant& v) {
  json options = json::object();
  for (const auto& [k, value] : v.options) options[k] = value;
  return {{"method", v.method}, {"options", options}};
}

json studyRowJson(const StudyRow& r) {
  json runs = json::array();
  for (double ms : r.runMs) runs.push_back(exactNumber(ms));
  return {{"variant", variantJson(r.variant)}, {"ms", exactNumber(r.ms)}, {"run_ms", runs},
          {"fragments_shaded", r.fragmentsShaded}, {"fragments_per_second", exactNumber(r.fragmentsPerSecond)},
          {"bytes_per_pixel", r.bytesPerPixel}, {"passes", r.passes}, {"rmse", exactNumber(r.rmse)},
          {"psnr", exactNumber(r.psnr)}, {"flip", exactNumber(r.flip)}, {"max_error", exactNumber(r.maxError)},
          {"non_finite_pixels", r.nonFinitePixels}, {"note", r.note}, {"image", r.image}, {"heatmap", r.heatmap}};
}

StudyRow studyRowOf(const json& j) {
  StudyRow r;
  r.variant.method = j.at("variant").at("method").get<std::string>();
  for (const auto& [k, value] : j.at("variant").at("options").items()) r.variant.options[k] = value.get<std::string>();
  r.ms = exactNumberOf(j.at("ms"));
  for (const json& ms : j.at("run_ms")) r.runMs.push_back(exactNumberOf(ms));
  r.fragmentsShaded = j.at("fragments_shaded").get<uint64_t>();
  r.fragmentsPerSecond = exactNumberOf(j.at("fragments_per_second"));
  r.bytesPerPixel = j.at("bytes_per_pixel").get<int>();
  r.passes = j.at("passes").get<int>();
  r.rmse = exactNumberOf(j.at("rmse")), r.psnr = exactNumberOf(j.at("psnr"));
  r.flip = exactNumberOf(j.at("flip")), r.maxError = exactNumberOf(j.at("max_error"));
  r.nonFinitePixels = j.at("non_finite_pixels").get<size_t>();
  r.note = j.at("note").get<std::string>();
  r.image = j.at("image").get<std::string>(), r.heatmap = j.at("heatmap").get<std::string>();
  return r;
}

// The study's options as the plan records them, and back (the profile and memory limit parsed
// again on the node that runs the job).
json studyOptionsJson(const StudyPlanRequest& r) {
  const StudyOptions& o = r.options;
  return {{"out", fs::absolute(o.outDir).lexically_normal().string()}, {"width", o.width}, {"height", o.height},
          {"runs", o.runs}, {"heatmap_scale", exactNumber(o.heatmapScale)}, {"profile", r.profileText},
          {"memory_limit", r.memoryLimitText}, {"methods", o.methods}};
}

StudyOptions studyOptionsOf(const Plan& plan) {
  const json& j = plan.options;
  StudyOptions o;
  o.outDir = j.at("out").get<std::string>();
  o.width = j.at("width").get<int>(), o.height = j.at("height").get<int>();
  o.runs = j.at("runs").get<int>();
  o.heatmapScale = exactNumberOf(j.at("heatmap_scale"));
  o.profile = parseProfile(j.at("profile").get<std::string>());
  const std::string limit = j.at("memory_limit").get<std::string>();
  o.memoryLimit = limit.empty() ? defaultMemoryLimit() : parseByteSize(limit, "--memory-limit");
  o.methods = j.at("methods").get<std::vector<std::string>>();
  for (const PlanInput& in : plan.inputs) o.scenes.push_back(in.path);
  return o;
}

// Job i's scene and its run of the study's configurations.
struct StudyShare {
  size_t scene = 0;
  int first = 0, count = 0;
};
StudyShare studyShareOf(const Plan& plan, int index) {
  const json& j = plan.jobs.at(size_t(index));
  return {j.at("scene").get<size_t>(), j.at("first").get<int>(), j.at("count").get<int>()};
}

}  // namespace


Plan planStudy(const StudyPlanRequest& r, const std::string& dir) {
  const std::vector<StudyVariant> variants = studyVariantsFor(r.options);
  const int total = int(variants.size());
  Plan plan;
  plan.dir = dir, plan.kind = "study", plan.planner = ProgramIdentity::ofThisProcess();
  plan.options = studyOptionsJson(r);
  json list = json::array();
  for (const StudyVariant& v : variants) list.push_back(variantJson(v));
  plan.options["configurations"] = list;  // what every job checks it would render
  for (size_t s = 0; s < r.options.scenes.size(); ++s) {
    const std::string path = fs::absolute(r.options.scenes[s]).lexically_normal().string();
    plan.inputs.push_back({path, sceneInputsSha256(path)});
    int width = r.options.width, height = r.options.height;
    if (width <= 0) {
      const Scene scene = loadScene(path, r.options.memoryLimit);
      width = scene.width, height = scene.height;
    }
    for (const JobRun& run : evenRuns(total, configurationsPerJob(r, width, height, total)))
      plan.jobs.push_back({{"scene", s}, {"first", run.first}, {"count", run.count}});
  }
  writePlan(plan);
  return plan;
}

namespace {

json runStudyJob(const Plan& plan, int index, const std::string& staging, Renderer& renderer, bool quiet) {
  const StudyProgress printer = studyProgressPrinter(quiet);
  const std::string prefix = plan.jobName(index) + " of " + std::to_string(plan.jobCount()) + ": ";
  const StudyProgress progress = [&](const std::string& what, int i, int n) { printer(prefix + what, i, n); };
  const StudyShare share = studyShareOf(plan, index);
  requireInputUnchanged(plan, share.scene);
  StudyOptions o = studyOptionsOf(plan);
  const std::vector<StudyVariant> all = studyVariantsFor(o);
  json list = json::array();
  for (const StudyVariant& v : all) list.push_back(variantJson(v));
  if (list != plan.options.at("configurations"))
    throw std::invalid_argument(plan.dir + ": this oitref's study configurations are not the plan's; plan again");
  if (share.first < 0 || share.count < 1 || share.first + share.count > int(all.size()))
    throw std::invalid_argument(plan.dir + ": " + plan.jobName(index) + " names configurations outside the study's");
  const std::vector<StudyVariant> mine(all.begin() + share.first, all.begin() + share.first + share.count);
  o.outDir = staging;
  const StudyScene s = runStudyScene(o, o.scenes[share.scene], mine, renderer, progress, 1, share.count);
  json rows = json::array();
  for (const StudyRow& r : s.rows) rows.push_back(studyRowJson(r));
  json scene = {{"name", s.name}, {"width", s.width}, {"height", s.height}, {"fragments", s.fragments},
                {"depth_complexity_max", s.depthComplexityMax}};
  if (s.hasRaycast)
    scene["raycast"] = {{"rmse", exactNumber(s.raycastRmse)}, {"max", exactNumber(s.raycastMax)},
                        {"share_within", exactNumber(s.raycastShareWithin)}};
  return {{"threads", renderer.threads()}, {"scene", scene}, {"rows", rows}};
}

StudyResult collectStudy(const Plan& plan, const std::vector<json>& results, const std::string& outDir) {
  const StudyOptions o = studyOptionsOf(plan);
  StudyResult result;
  result.runs = o.runs, result.heatmapScale = o.heatmapScale, result.profile = o.profile.name;
  result.jobs = plan.jobCount();
  result.scenes.resize(plan.inputs.size());
  std::vector<int> sceneJobs(plan.inputs.size(), 0);
  const JobsRan ran = jobsRan(results);
  result.threads = ran.threads, result.totalSeconds = ran.seconds, result.nodes = ran.nodes;
  for (int i = 0; i < plan.jobCount(); ++i) {
    const json& r = results.at(size_t(i));
    const StudyShare share = studyShareOf(plan, i);
    StudyScene& s = result.scenes.at(share.scene);
    const json& scene = r.at("scene");
    // Every job of a scene rendered its A-buffer: the figures must agree, or frames were not
    // the same bits in two processes.
    StudyScene figures;
    figures.name = scene.at("name").get<std::string>();
    figures.width = scene.at("width").get<int>(), figures.height = scene.at("height").get<int>();
    figures.fragments = scene.at("fragments").get<uint64_t>();
    figures.depthComplexityMax = scene.at("depth_complexity_max").get<int>();
    if (sceneJobs[share.scene]++ == 0) {
      s.name = figures.name, s.width = figures.width, s.height = figures.height;
      s.fragments = figures.fragments, s.depthComplexityMax = figures.depthComplexityMax;
    } else if (figures.name != s.name || figures.width != s.width || figures.height != s.height ||
               figures.fragments != s.fragments || figures.depthComplexityMax != s.depthComplexityMax) {
      throw std::runtime_error(plan.dir + ": " + plan.jobName(i) + " rendered scene " + s.name +
                               " differently from an earlier job (its A-buffer's fragment counts differ)");
    }
    if (scene.contains("raycast")) {
      const json& rc = scene.at("raycast");
      s.raycastRmse = exactNumberOf(rc.at("rmse")), s.raycastMax = exactNumberOf(rc.at("max"));
      s.raycastShareWithin = exactNumberOf(rc.at("share_within")), s.hasRaycast = true;
    }
    const std::string node = r.at("node").get<std::string>();
    for (const json& row : r.at("rows")) {
      StudyRow studyRow = studyRowOf(row);
      studyRow.job = i, studyRow.node = node;
      for (const std::string& file : {studyRow.image, studyRow.heatmap}) {
        const fs::path to = fs::path(outDir) / file;
        fs::create_directories(to.parent_path());
        fs::copy_file(fs::path(plan.resultDir(i)) / file, to, fs::copy_options::overwrite_existing);
      }
      s.rows.push_back(std::move(studyRow));
    }
  }
  return result;
}

int collectStudyReport(const Plan& plan, const std::vector<json>& results, const std::string& out) {
  const std::string dir = out.empty() ? plan.options.at("out").get<std::string>() : out;
  const StudyResult result = collectStudy(plan, results, dir);
  writeStudyReport(result, dir);
  std::printf("oitref collect: %zu scenes × %zu configurations from %d jobs on %zu node%s, %.1f s of jobs\nreport: %s\n",
              result.scenes.size(), result.scenes.empty() ? size_t(0) : result.scenes[0].rows.size(), result.jobs,
              result.nodes.size(), result.nodes.size() == 1 ? "" : "s", result.totalSeconds,
              (fs::absolute(dir) / "index.html").lexically_normal().c_str());
  return 0;
}

}  // namespace

const PlanKind& studyPlanKind() {
  static const PlanKind kind{"study", runStudyJob, collectStudyReport};
  return kind;
}

}  // namespace oitref::tools
