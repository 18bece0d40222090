// The kinds of work a plan folder can hold (job_plan.h): `study`, `stress`, `suite` and
// `reference`, each planned by its command's --plan. A kind says how one of its jobs runs and how
// the jobs' results become what its command writes on one machine.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "oitref/oit/frame.h"
#include "tools/job_plan.h"

namespace oitref::tools {

struct PlanKind {
  const char* name;
  // Runs job `index` of the plan, writing its files under `staging`; returns its result.
  nlohmann::json (*runJob)(const Plan& plan, int index, const std::string& staging, Renderer& renderer, bool quiet);
  // From every job's result (results[i] of job i): writes what the command writes (into `out`, or
  // where the plan says when it is empty) and prints its summary; returns the command's exit status.
  int (*collect)(const Plan& plan, const std::vector<nlohmann::json>& results, const std::string& out);
};

const PlanKind& studyPlanKind();      // study_jobs.cpp
const PlanKind& stressPlanKind();     // stress_jobs.cpp
const PlanKind& suitePlanKind();      // suite_jobs.cpp
const PlanKind& referencePlanKind();  // suite_jobs.cpp

// The plan's kind; an error naming the folder where this oitref knows no such kind.
const PlanKind& planKindOf(const Plan& plan);

// Where and how the jobs ran, from their results: the nodes (sorted, each once), the jobs' thread
// count (0 where they differ) and the sum of their times.
struct JobsRan {
  std::vector<std::string> nodes;
  int threads = 0;
  double seconds = 0;
};
JobsRan jobsRan(const std::vector<nlohmann::json>& results);

// One sentence for a report that was run as jobs: how many, on which nodes, and that its times
// come from separate processes (and nodes); "" for jobs == 0 (one process).
std::string jobsProvenance(int jobs, const std::vector<std::string>& nodes, bool threadsDiffer);

}  // namespace oitref::tools
