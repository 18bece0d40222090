// A plan folder: a long command's work cut into independent jobs that a cluster runs one by one
// (`oitref job DIR INDEX`, e.g. as the tasks of a Slurm job array) and that `oitref collect DIR`
// puts back together into the report the command writes on one machine.
//
//   DIR/plan.json         the manifest: what kind of work, the oitref that planned it (version and
//                         the SHA-256 of its executable), the inputs with their hashes, the
//                         command's options and each job's share of the work
//   DIR/jobs/NNNN/        a finished job: result.json and the files it wrote; built under another
//                         name and renamed into place whole, so a job killed half-way leaves
//                         nothing here that could pass for a result
//   DIR/jobs/NNNN.failed  why job NNNN failed (its error, node, time); removed when it succeeds
//
// A job runs only with the executable that planned it, and only on the inputs the plan hashed:
// frames are the same bits in every process, so a collected report is the single machine's.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace oitref::tools {

// Which oitref made or runs a plan: its version and the SHA-256 of its executable (two builds of
// one version differ in bits where their code differs; the plan must not mix them).
struct ProgramIdentity {
  std::string version, executableSha256;
  static ProgramIdentity ofThisProcess();
  std::string describe() const;  // "oitref 0.1.0 (executable sha256 1a2b3c4d…)"
  bool operator==(const ProgramIdentity&) const = default;
};

// An input file (a scene) and the SHA-256 of it and of every file it names (meshes, the material
// libraries of OBJ meshes, textures).
struct PlanInput {
  std::string path, sha256;
};
std::string sceneInputsSha256(const std::string& scenePath);

struct Plan {
  std::string dir;    // the folder, as the user named it (errors name it so)
  std::string kind;   // "study"
  std::string id;     // SHA-256 of the manifest's content: every result names the plan it belongs to
  ProgramIdentity planner;
  std::vector<PlanInput> inputs;
  nlohmann::json options;             // the command's options, as its kind reads them
  std::vector<nlohmann::json> jobs;   // each job's share of the work, as its kind reads it

  int jobCount() const { return int(jobs.size()); }
  std::string jobName(int index) const;   // "job 7"
  std::string resultDir(int index) const; // DIR/jobs/0007
};

// Writes DIR/plan.json (DIR must not hold a plan already); fills plan.id.
void writePlan(Plan& plan);
// What a command says after planning: how many jobs, how to run them, what collect will write.
std::string plannedMessage(const std::string& command, const Plan& plan, const std::string& collectWrites);
// Reads DIR/plan.json; errors name the folder and what is wrong with it.
Plan readPlan(const std::string& dir);
// Throws unless this process is the oitref that made the plan.
void requirePlanner(const Plan& plan);
// Throws unless input i still has the hash the plan recorded.
void requireInputUnchanged(const Plan& plan, size_t input);
// Throws unless `index` names one of the plan's jobs.
void requireJobIndex(const Plan& plan, long long index);

// Runs job `index`: `work(staging)` writes its files under the staging folder and returns its
// result; the result (with the plan's id, the job's index, the node, the executable) is written
// to staging/result.json and the folder renamed to DIR/jobs/NNNN. When `work` throws, nothing is
// left but DIR/jobs/NNNN.failed with the error, and the exception goes on.
void runPlanJob(const Plan& plan, int index, const std::function<nlohmann::json(const std::string& staging)>& work);

// What collect finds of a job.
struct JobState {
  enum Kind { Done, Failed, Missing, Damaged } kind = Missing;
  std::string error;       // Failed: the job's error (and its node); Damaged: what is wrong
  nlohmann::json result;   // Done: result.json
};
JobState readJobState(const Plan& plan, int index);
std::string describeJobState(const Plan& plan, int index, const JobState& state);  // one line for the user

// 0…total−1 cut into runs of at most `atMost`, as few as that allows and of nearly equal length
// (the first total % runs one longer): the jobs' shares of a list of work items.
struct JobRun {
  int first = 0, count = 0;
};
std::vector<JobRun> evenRuns(int total, int atMost);

// "0-3,7,9-10": the indices as a Slurm --array list.
std::string indexRanges(const std::vector<int>& indices);

// A double in a result file: a JSON number (nlohmann writes the shortest text that reads back to
// the same bits) or, for ±inf and NaN, which JSON lacks, a string.
nlohmann::json exactNumber(double v);
double exactNumberOf(const nlohmann::json& v);

}  // namespace oitref::tools
