#include "tools/suite_jobs.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "oitref/core/memory_limit.h"
#include "oitref/core/profile.h"
#include "tools/number_parse.h"
#include "tools/suite.h"

namespace oitref::tools {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string absolute(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

// One job per input, each naming its scene.
void planPerScene(Plan& plan, const std::vector<std::string>& scenes) {
  for (size_t s = 0; s < scenes.size(); ++s) {
    const std::string path = absolute(scenes[s]);
    plan.inputs.push_back({path, sceneInputsSha256(path)});
    plan.jobs.push_back({{"scene", s}});
  }
}

size_t sceneOf(const Plan& plan, int index) {
  const size_t scene = plan.jobs.at(size_t(index)).at("scene").get<size_t>();
  if (scene >= plan.inputs.size()) throw std::invalid_argument(plan.dir + ": " + plan.jobName(index) + " names no input");
  requireInputUnchanged(plan, scene);
  return scene;
}

// Copies a job's files (its staging folder's content but result.json) into `to`.
void copyJobFiles(const Plan& plan, int index, const std::string& to) {
  const fs::path from = plan.resultDir(index);
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(from)) {
    if (!e.is_regular_file() || e.path() == from / "result.json") continue;
    const fs::path target = fs::path(to) / fs::relative(e.path(), from);
    fs::create_directories(target.parent_path());
    fs::copy_file(e.path(), target, fs::copy_options::overwrite_existing);
  }
}

json runSuiteJob(const Plan& plan, int index, const std::string& staging, Renderer& renderer, bool) {
  const json& o = plan.options;
  const size_t scene = sceneOf(plan, index);
  const std::string limitText = o.at("memory_limit").get<std::string>();
  const uint64_t limit = limitText.empty() ? defaultMemoryLimit() : parseByteSize(limitText, "--memory-limit");
  const bool images = !o.at("out").get<std::string>().empty();
  const SuiteScene s = runSuiteScene(plan.inputs[scene].path, renderer, parseProfile(o.at("profile").get<std::string>()),
                                     o.at("width").get<int>(), o.at("height").get<int>(), images ? staging : "", limit);
  json rows = json::array();
  for (const SuiteRow& r : s.rows)
    rows.push_back({{"method", r.method}, {"ms", exactNumber(r.ms)}, {"bytes_per_pixel", r.bytesPerPixel},
                    {"rmse", exactNumber(r.rmse)}, {"max_error", exactNumber(r.maxError)}, {"note", r.note}});
  return {{"threads", renderer.threads()}, {"name", s.name}, {"width", s.width}, {"height", s.height},
          {"fragments", s.fragments}, {"rows", rows}};
}

int collectSuite(const Plan& plan, const std::vector<json>& results, const std::string& outOverride) {
  const std::string out = outOverride.empty() ? plan.options.at("out").get<std::string>() : outOverride;
  const JobsRan ran = jobsRan(results);
  std::printf("oitref suite: %zu scenes, threads %s, profile %s\n%s\n\n", plan.inputs.size(),
              ran.threads ? std::to_string(ran.threads).c_str() : "differing",
              parseProfile(plan.options.at("profile").get<std::string>()).name.c_str(),
              jobsProvenance(plan.jobCount(), ran.nodes, ran.threads == 0).c_str());
  for (int i = 0; i < plan.jobCount(); ++i) {
    const json& r = results[size_t(i)];
    SuiteScene s;
    s.name = r.at("name").get<std::string>();
    s.width = r.at("width").get<int>(), s.height = r.at("height").get<int>();
    s.fragments = r.at("fragments").get<uint64_t>();
    for (const json& row : r.at("rows"))
      s.rows.push_back({row.at("method").get<std::string>(), exactNumberOf(row.at("ms")), row.at("bytes_per_pixel").get<int>(),
                        exactNumberOf(row.at("rmse")), exactNumberOf(row.at("max_error")), row.at("note").get<std::string>()});
    std::fputs(formatSuiteTable(s).c_str(), stdout);
    std::fputs("\n", stdout);
    if (!out.empty()) copyJobFiles(plan, i, out);
  }
  if (!out.empty()) std::printf("images in %s/<scene>/<method>.png|.exr\n", out.c_str());
  return 0;
}

json runReferenceJob(const Plan& plan, int index, const std::string& staging, Renderer& renderer, bool) {
  const size_t scene = sceneOf(plan, index);
  json entries = json::array();
  for (const ReferenceEntry& e : renderReferenceScene(plan.inputs[scene].path, renderer, staging, plan.options.at("write").get<bool>()))
    entries.push_back({{"scene", e.scene}, {"method", e.method}, {"sha256", e.hash}});
  return {{"threads", renderer.threads()}, {"entries", entries}};
}

int collectReference(const Plan& plan, const std::vector<json>& results, const std::string& outOverride) {
  const std::string dir = outOverride.empty() ? plan.options.at("dir").get<std::string>() : outOverride;
  const bool write = plan.options.at("write").get<bool>();
  std::vector<ReferenceEntry> entries;
  for (int i = 0; i < plan.jobCount(); ++i) {
    for (const json& e : results[size_t(i)].at("entries"))
      entries.push_back({e.at("scene").get<std::string>(), e.at("method").get<std::string>(), e.at("sha256").get<std::string>()});
    if (write) copyJobFiles(plan, i, dir);
  }
  if (write) writeReferenceManifest(dir, entries);
  return reportReferences(entries, dir, write);
}

}  // namespace

Plan planSuite(const SuiteRequest& r, const std::string& dir) {
  Plan plan;
  plan.dir = dir, plan.kind = "suite", plan.planner = ProgramIdentity::ofThisProcess();
  plan.options = {{"out", r.out.empty() ? "" : absolute(r.out)}, {"width", r.width}, {"height", r.height},
                  {"profile", r.profileText}, {"memory_limit", r.memoryLimitText}};
  planPerScene(plan, r.scenes);
  writePlan(plan);
  return plan;
}

Plan planReference(const std::string& scenesDir, const std::string& referenceDir, bool write, const std::string& dir) {
  if (!write) readManifest(referenceDir + "/manifest.txt");  // an unreadable manifest fails now, not after the jobs
  Plan plan;
  plan.dir = dir, plan.kind = "reference", plan.planner = ProgramIdentity::ofThisProcess();
  plan.options = {{"dir", absolute(referenceDir)}, {"write", write}};
  planPerScene(plan, sceneFiles(scenesDir));
  writePlan(plan);
  return plan;
}

const PlanKind& suitePlanKind() {
  static const PlanKind kind{"suite", runSuiteJob, collectSuite};
  return kind;
}

const PlanKind& referencePlanKind() {
  static const PlanKind kind{"reference", runReferenceJob, collectReference};
  return kind;
}

}  // namespace oitref::tools
