// `oitref job DIR INDEX` (one job of a plan folder) and `oitref collect DIR` (what the command
// writes, from the jobs' results): the cluster's side of `--plan DIR` (job_plan.h, plan_kinds.h).
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>

#include "tools/commands.h"
#include "tools/job_plan.h"
#include "tools/plan_kinds.h"

namespace oitref::tools {
namespace {

struct JobCommandOptions {
  std::string dir, index, out;
  int threads = -1;  // -1: SLURM_CPUS_PER_TASK where Slurm sets it, else every hardware thread
  bool quiet = false, resume = false, missing = false;
};

// A task of a Slurm job array gets the CPUs it asked for (sbatch --cpus-per-task), no more.
int threadsFor(int requested) {
  if (requested >= 0) return requested;
  if (const char* cpus = std::getenv("SLURM_CPUS_PER_TASK")) {
    const int n = std::atoi(cpus);
    if (n > 0) return n;
  }
  return 0;
}

int parseJobIndex(const Plan& plan, const std::string& text) {
  size_t used = 0;
  long long index = -1;
  try {
    index = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw std::invalid_argument(plan.dir + ": job index '" + text + "' is not a whole number");
  requireJobIndex(plan, index);
  return int(index);
}

void runJob(const Plan& plan, const PlanKind& kind, int index, Renderer& renderer, bool quiet) {
  try {
    runPlanJob(plan, index, [&](const std::string& staging) { return kind.runJob(plan, index, staging, renderer, quiet); });
  } catch (const std::exception& e) {
    throw std::runtime_error(plan.dir + ": " + plan.jobName(index) + " failed: " + e.what());
  }
}

int runJobCommand(const JobCommandOptions& c) {
  const Plan plan = readPlan(c.dir);
  const int index = parseJobIndex(plan, c.index);
  const PlanKind& kind = planKindOf(plan);
  requirePlanner(plan);
  Renderer renderer(RendererOptions{.threads = threadsFor(c.threads)});
  runJob(plan, kind, index, renderer, c.quiet);
  if (!c.quiet) std::printf("%s: %s done, %d threads\n", c.dir.c_str(), plan.jobName(index).c_str(), renderer.threads());
  return 0;
}

int runCollectCommand(const JobCommandOptions& c) {
  const Plan plan = readPlan(c.dir);
  const PlanKind& kind = planKindOf(plan);
  requirePlanner(plan);
  std::vector<JobState> states;
  std::vector<int> notDone;
  for (int i = 0; i < plan.jobCount(); ++i) {
    states.push_back(readJobState(plan, i));
    if (states.back().kind != JobState::Done) notDone.push_back(i);
  }
  if (c.missing) {  // for a re-submission: sbatch --array=$(oitref collect DIR --missing)
    std::printf("%s\n", indexRanges(notDone).c_str());
    return 0;
  }
  if (!notDone.empty() && c.resume) {
    Renderer renderer(RendererOptions{.threads = threadsFor(c.threads)});
    for (int i : notDone) {
      if (!c.quiet) std::cerr << c.dir << ": " << describeJobState(plan, i, states[size_t(i)]) << "; running it\n";
      runJob(plan, kind, i, renderer, c.quiet);
      states[size_t(i)] = readJobState(plan, i);
    }
    notDone.clear();
  }
  if (!notDone.empty()) {
    for (int i : notDone) std::cerr << c.dir << ": " << describeJobState(plan, i, states[size_t(i)]) << "\n";
    throw std::runtime_error(c.dir + ": " + std::to_string(notDone.size()) + " of " + std::to_string(plan.jobCount()) +
                             " jobs are missing or failed (" + indexRanges(notDone) +
                             "); run just those again (scripts/slurm/submit.sh " + c.dir + ", or oitref collect " + c.dir +
                             " --resume), then collect");
  }
  std::vector<nlohmann::json> results;
  for (JobState& s : states) results.push_back(std::move(s.result));
  return kind.collect(plan, results, c.out);
}

}  // namespace

void addJobCommands(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<JobCommandOptions>();
  CLI::App* job = app.add_subcommand("job", "Run one job of a plan folder (study, stress, suite or reference --plan), e.g. as a Slurm array task");
  job->add_option("dir", o->dir, "Plan folder")->required();
  job->add_option("index", o->index, "Job index, from 0 (a Slurm array task: $SLURM_ARRAY_TASK_ID)")->required();
  addThreadsOption(job, o->threads, "Worker threads (0: all; default: $SLURM_CPUS_PER_TASK where set, else all)");
  addQuietFlag(job, o->quiet);
  job->callback([o, &exitCode] { exitCode = runReportingErrors("job", [&] { return runJobCommand(*o); }); });

  CLI::App* collect = app.add_subcommand("collect", "Check a plan folder's jobs and write what its command writes on one machine");
  collect->add_option("dir", o->dir, "Plan folder")->required();
  nonEmptyPath(collect->add_option("--out", o->out, "Report folder (default: the one the plan was made with)"));
  CLI::Option* resume = collect->add_flag("--resume", o->resume, "Run the jobs that are missing or failed in this process first");
  collect->add_flag("--missing", o->missing,
                    "Only print the indices of the jobs missing or failed, as a Slurm --array list (\"2,5-7\"; empty when none)")
      ->excludes(resume);
  addThreadsOption(collect, o->threads, "Worker threads for --resume (0: all; default: $SLURM_CPUS_PER_TASK where set, else all)");
  addQuietFlag(collect, o->quiet);
  collect->callback([o, &exitCode] { exitCode = runReportingErrors("collect", [&] { return runCollectCommand(*o); }); });
}

}  // namespace oitref::tools
