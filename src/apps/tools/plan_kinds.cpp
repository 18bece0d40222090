#include "tools/plan_kinds.h"

#include <algorithm>
#include <stdexcept>

namespace oitref::tools {

const PlanKind& planKindOf(const Plan& plan) {
  for (const PlanKind* kind : {&studyPlanKind(), &stressPlanKind(), &suitePlanKind(), &referencePlanKind()})
    if (plan.kind == kind->name) return *kind;
  throw std::invalid_argument(plan.dir + ": a plan of kind '" + plan.kind + "', which this oitref does not know");
}

JobsRan jobsRan(const std::vector<nlohmann::json>& results) {
  JobsRan ran;
  for (size_t i = 0; i < results.size(); ++i) {
    const int threads = results[i].at("threads").get<int>();
    ran.threads = i == 0 || ran.threads == threads ? threads : 0;
    ran.seconds += results[i].at("seconds").get<double>();
    ran.nodes.push_back(results[i].at("node").get<std::string>());
  }
  std::sort(ran.nodes.begin(), ran.nodes.end());
  ran.nodes.erase(std::unique(ran.nodes.begin(), ran.nodes.end()), ran.nodes.end());
  return ran;
}

std::string jobsProvenance(int jobs, const std::vector<std::string>& nodes, bool threadsDiffer) {
  if (jobs == 0) return "";
  std::string list;
  for (const std::string& n : nodes) list += (list.empty() ? "" : ", ") + n;
  return "Run as " + std::to_string(jobs) + " jobs (oitref job, put together by oitref collect) on " +
         std::to_string(nodes.size()) + (nodes.size() == 1 ? " node: " : " nodes: ") + list +
         (threadsDiffer ? "; the jobs had different thread counts" : "") + ". Its times come from different processes" +
         (nodes.size() > 1 ? " on different nodes" : "") +
         ", measured at different times: compare times within a job; a total is the sum of the jobs' times. Everything "
         "else is what one process would have written.";
}

}  // namespace oitref::tools
