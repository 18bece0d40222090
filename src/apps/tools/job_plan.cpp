#include "tools/job_plan.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "frame/sha256.h"
#include "oitref/oit/image_io.h"
#include "oitref/oit/scene.h"

#ifndef OITREF_VERSION
#define OITREF_VERSION "unknown"
#endif

namespace oitref::tools {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr int kPlanFormat = 1;  // plan.json's layout; a reader refuses others

void hashFile(util::Sha256& hash, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    hash.update(buffer, size_t(in.gcount()));
  }
}

// A whole file's bytes ("" when it cannot be read: the callers check existence first).
std::string fileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string fileSha256(const std::string& path) {
  util::Sha256 hash;
  hashFile(hash, path);
  return hash.hex();
}

std::string hostName() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return text;
}

std::string jobFolderName(int index) {
  char name[16];
  std::snprintf(name, sizeof name, "%04d", index);
  return name;
}

// The manifest without its id: what the id hashes.
json manifestBody(const Plan& p) {
  json inputs = json::array();
  for (const PlanInput& in : p.inputs) inputs.push_back({{"path", in.path}, {"sha256", in.sha256}});
  return {{"oitref_plan", kPlanFormat},
          {"kind", p.kind},
          {"version", p.planner.version},
          {"executable_sha256", p.planner.executableSha256},
          {"inputs", inputs},
          {"options", p.options},
          {"jobs", p.jobs}};
}

std::string idOf(const Plan& p) {
  const std::string text = manifestBody(p).dump();
  util::Sha256 hash;
  hash.update(text.data(), text.size());
  return hash.hex();
}

// The material libraries an OBJ file names (`mtllib a.mtl b.mtl`, relative to its folder) that
// exist: their materials decide its textures and colours. None for other formats.
std::vector<std::string> objMaterialLibraries(const std::string& path) {
  std::vector<std::string> out;
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".obj") return out;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string keyword, name;
    if (!(words >> keyword) || keyword != "mtllib") continue;
    while (words >> name) {
      const fs::path library = (fs::path(path).parent_path() / name).lexically_normal();
      if (fs::is_regular_file(library)) out.push_back(library.string());
    }
  }
  return out;
}

}  // namespace

ProgramIdentity ProgramIdentity::ofThisProcess() {
  static const ProgramIdentity identity{OITREF_VERSION, fileSha256("/proc/self/exe")};
  return identity;
}

std::string ProgramIdentity::describe() const {
  return "oitref " + version + " (executable sha256 " + executableSha256.substr(0, 16) + "…)";
}

std::string sceneInputsSha256(const std::string& scenePath) {
  util::Sha256 hash;
  hashFile(hash, scenePath);
  const Scene scene = loadScene(scenePath);
  std::set<std::string> named;  // each file once, in a fixed order
  for (const SceneObject& o : scene.objects) {
    if (!o.filePath.empty()) {
      named.insert(o.filePath);
      for (const std::string& library : objMaterialLibraries(o.filePath)) named.insert(library);
    }
    if (!o.textureFile.empty() && fs::is_regular_file(o.textureFile)) named.insert(o.textureFile);
  }
  for (const std::string& path : named) {
    hash.update(path.data(), path.size() + 1);
    hashFile(hash, path);
  }
  return hash.hex();
}

std::string Plan::jobName(int index) const { return "job " + std::to_string(index); }
std::string Plan::resultDir(int index) const { return (fs::path(dir) / "jobs" / jobFolderName(index)).string(); }

void writePlan(Plan& p) {
  const fs::path manifest = fs::path(p.dir) / "plan.json";
  if (fs::exists(manifest))
    throw std::invalid_argument(p.dir + ": already holds a plan (plan.json); plan into a new folder, or remove this one first");
  fs::create_directories(fs::path(p.dir) / "jobs");
  p.id = idOf(p);
  json j = manifestBody(p);
  j["id"] = p.id;
  j["planned_on"] = hostName();
  j["planned_at"] = utcNow();
  writeTextFile(manifest.string(), j.dump(1) + "\n");
}

std::string plannedMessage(const std::string& command, const Plan& p, const std::string& collectWrites) {
  return "oitref " + command + ": planned " + std::to_string(p.jobCount()) + " jobs in " + p.dir + "\nrun each with `oitref job " +
         p.dir + " INDEX` (INDEX 0–" + std::to_string(p.jobCount() - 1) + "; on Slurm: scripts/slurm/submit.sh " + p.dir +
         "), then `oitref collect " + p.dir + "` writes " + collectWrites + "\n";
}

Plan readPlan(const std::string& dir) {
  const fs::path manifest = fs::path(dir) / "plan.json";
  if (!fs::is_directory(dir)) throw std::invalid_argument(dir + ": no such plan folder");
  if (!fs::is_regular_file(manifest))
    throw std::invalid_argument(dir + ": not an oitref plan folder (no plan.json; `oitref study … --plan " + dir + "` makes one)");
  const std::string text = fileText(manifest);
  Plan p;
  p.dir = dir;
  try {
    const json j = json::parse(text);
    if (j.at("oitref_plan").get<int>() != kPlanFormat)
      throw std::invalid_argument("field 'oitref_plan': layout " + j.at("oitref_plan").dump() + ", this oitref reads " +
                                  std::to_string(kPlanFormat));
    p.kind = j.at("kind").get<std::string>();
    p.planner = {j.at("version").get<std::string>(), j.at("executable_sha256").get<std::string>()};
    for (const json& input : j.at("inputs")) p.inputs.push_back({input.at("path").get<std::string>(), input.at("sha256").get<std::string>()});
    p.options = j.at("options");
    for (const json& job : j.at("jobs")) p.jobs.push_back(job);
    p.id = j.at("id").get<std::string>();
  } catch (const json::exception& e) {
    throw std::invalid_argument(manifest.string() + ": not a valid plan (" + e.what() + ")");
  }
  if (p.id != idOf(p))
    throw std::invalid_argument(manifest.string() + ": its content does not match its id (edited after planning?); plan again");
  if (p.jobs.empty()) throw std::invalid_argument(manifest.string() + ": the plan has no jobs");
  return p;
}

void requirePlanner(const Plan& p) {
  const ProgramIdentity self = ProgramIdentity::ofThisProcess();
  if (!(self == p.planner))
    throw std::invalid_argument(p.dir + ": planned by " + p.planner.describe() + ", but this is " + self.describe() +
                                "; run and collect a plan with the oitref that made it, or plan again");
}

void requireInputUnchanged(const Plan& p, size_t i) {
  const PlanInput& in = p.inputs.at(i);
  if (!fs::is_regular_file(in.path)) throw std::invalid_argument(p.dir + ": input " + in.path + " is gone since the plan was made");
  if (sceneInputsSha256(in.path) != in.sha256)
    throw std::invalid_argument(p.dir + ": input " + in.path + " (or a file it names) changed since the plan was made; plan again");
}

void requireJobIndex(const Plan& p, long long index) {
  if (index < 0 || index >= p.jobCount())
    throw std::invalid_argument(p.dir + ": there is no job " + std::to_string(index) + "; the plan has jobs 0–" +
                                std::to_string(p.jobCount() - 1));
}

void runPlanJob(const Plan& p, int index, const std::function<json(const std::string&)>& work) {
  const fs::path final = p.resultDir(index), failed = final.string() + ".failed";
  // A name no other attempt shares (another node, or a re-run on this one), beside the result.
  const fs::path staging = final.parent_path() / ("." + final.filename().string() + "." + hostName() + "." +
                                                  std::to_string(getpid()) + ".partial");
  const auto start = std::chrono::steady_clock::now();
  fs::remove_all(staging);
  fs::create_directories(staging);
  try {
    json result = work(staging.string());
    result["plan"] = p.id;
    result["job"] = index;
    result["node"] = hostName();
    result["executable_sha256"] = ProgramIdentity::ofThisProcess().executableSha256;
    result["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result["finished_at"] = utcNow();
    writeTextFile((staging / "result.json").string(), result.dump(1) + "\n");
    // An earlier result of this job (a re-submission) gives way; then the new one appears whole.
    fs::remove_all(final);
    fs::rename(staging, final);
    fs::remove(failed);
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    const json record = {{"job", index}, {"plan", p.id}, {"node", hostName()}, {"error", e.what()}, {"failed_at", utcNow()}};
    try {
      writeTextFile(failed.string(), record.dump(1) + "\n");
    } catch (const std::exception&) {  // the job's own error is the one to report
    }
    throw;
  }
}

JobState readJobState(const Plan& p, int index) {
  JobState s;
  const fs::path dir = p.resultDir(index), resultFile = dir / "result.json", failed = dir.string() + ".failed";
  if (fs::is_directory(dir)) {
    s.kind = JobState::Damaged;
    if (!fs::is_regular_file(resultFile)) return s.error = resultFile.string() + " is missing", s;
    try {
      s.result = json::parse(fileText(resultFile));
      if (s.result.at("plan").get<std::string>() != p.id)
        return s.error = resultFile.string() + " belongs to another plan (id " + s.result.at("plan").get<std::string>().substr(0, 12) + "…)", s;
      if (s.result.at("job").get<int>() != index)
        return s.error = resultFile.string() + " is the result of job " + s.result.at("job").dump(), s;
      if (s.result.at("executable_sha256").get<std::string>() != p.planner.executableSha256)
        return s.error = resultFile.string() + " was written by another oitref executable", s;
    } catch (const json::exception& e) {
      return s.error = resultFile.string() + " is damaged (" + e.what() + ")", s;
    }
    s.kind = JobState::Done;
    return s;
  }
  if (fs::is_regular_file(failed)) {
    s.kind = JobState::Failed;
    try {
      const json record = json::parse(fileText(failed));
      s.error = record.at("error").get<std::string>() + " (on " + record.at("node").get<std::string>() + ", " +
                record.at("failed_at").get<std::string>() + ")";
    } catch (const json::exception&) {
      s.error = "failed; its record " + failed.string() + " is unreadable";
    }
    return s;
  }
  return s;
}

std::string describeJobState(const Plan& p, int index, const JobState& s) {
  switch (s.kind) {
    case JobState::Done: return p.jobName(index) + ": done";
    case JobState::Failed: return p.jobName(index) + ": failed: " + s.error;
    case JobState::Damaged: return p.jobName(index) + ": damaged result: " + s.error;
    case JobState::Missing: break;
  }
  return p.jobName(index) + ": missing (not run yet, still running, or killed before it finished)";
}

std::vector<JobRun> evenRuns(int total, int atMost) {
  std::vector<JobRun> runs;
  if (total <= 0) return runs;
  const int count = (total + std::max(atMost, 1) - 1) / std::max(atMost, 1);
  for (int k = 0, first = 0; k < count; ++k) {
    const int length = total / count + (k < total % count ? 1 : 0);
    runs.push_back({first, length});
    first += length;
  }
  return runs;
}

std::string indexRanges(const std::vector<int>& v) {
  std::string out;
  for (size_t i = 0; i < v.size();) {
    size_t j = i;
    while (j + 1 < v.size() && v[j + 1] == v[j] + 1) ++j;
    out += (out.empty() ? "" : ",") + std::to_string(v[i]) + (j > i ? "-" + std::to_string(v[j]) : "");
    i = j + 1;
  }
  return out;
}

json exactNumber(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

double exactNumberOf(const json& v) {
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    throw std::invalid_argument("'" + s + "' is not a number");
  }
  return v.get<double>();
}

}  // namespace oitref::tools
