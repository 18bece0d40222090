#include "tools/stress_jobs.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "tools/stress_report.h"
#include "tools/study.h"

namespace oitref::tools {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json stressRowJson(const StressRow& r) {
  json options = json::object();
  for (const auto& [k, v] : r.config.options) options[k] = v;
  return {{"condition", r.condition.name}, {"method", r.config.method}, {"options", options}};
}

StressOptions stressOptionsOf(const Plan& plan) {
  const json& j = plan.options;
  StressOptions o;
  o.conditions = j.at("conditions").get<std::vector<std::string>>();
  o.methods = j.at("methods").get<std::vector<std::string>>();
  o.layers = j.at("layers").get<std::vector<int>>();
  o.alphas.clear();
  for (const json& a : j.at("alphas")) o.alphas.push_back(float(exactNumberOf(a)));
  o.size = j.at("size").get<int>();
  return o;
}

// The rows of the atlas the plan asks for, checked against the list it recorded.
std::vector<StressRow> stressRowsOf(const Plan& plan, const StressOptions& o) {
  std::vector<StressRow> rows = stressRowsFor(o);
  json list = json::array();
  for (const StressRow& r : rows) list.push_back(stressRowJson(r));
  if (list != plan.options.at("rows"))
    throw std::invalid_argument(plan.dir + ": this oitref's atlas rows are not the plan's; plan again");
  return rows;
}

struct StressRowRun {
  int first = 0, count = 0;
};
StressRowRun stressRunOf(const Plan& plan, int index, size_t rows) {
  const json& j = plan.jobs.at(size_t(index));
  const StressRowRun r{j.at("first").get<int>(), j.at("count").get<int>()};
  if (r.first < 0 || r.count < 1 || size_t(r.first + r.count) > rows)
    throw std::invalid_argument(plan.dir + ": " + plan.jobName(index) + " names rows outside the atlas");
  return r;
}

json runStressJob(const Plan& plan, int index, const std::string&, Renderer& renderer, bool quiet) {
  const StressOptions o = stressOptionsOf(plan);
  std::vector<StressRow> rows = stressRowsOf(plan, o);
  const StressRowRun run = stressRunOf(plan, index, rows.size());
  const StressProgress progress = studyProgressPrinter(quiet);
  json out = json::array();
  for (int i = 0; i < run.count; ++i) {
    StressRow& row = rows[size_t(run.first + i)];
    progress(plan.jobName(index) + ": " + row.condition.name + ": " + row.config.label(), i + 1, run.count);
    renderStressRow(row, o, renderer);
    json cells = json::array();
    for (const StressCell& c : row.cells)
      cells.push_back({{"layers", c.layers}, {"alpha", exactNumber(c.alpha)}, {"error", exactNumber(c.error)},
                       {"non_finite_pixels", c.nonFinitePixels}, {"inf_in", c.infIn}, {"reveal_underflow", c.revealUnderflow},
                       {"moment_fallbacks", c.momentFallbacks}});
    out.push_back({{"row", stressRowJson(row)}, {"cells", cells}});
  }
  return {{"threads", renderer.threads()}, {"rows", out}};
}

int collectStress(const Plan& plan, const std::vector<json>& results, const std::string& out) {
  const StressOptions o = stressOptionsOf(plan);
  std::vector<StressRow> rows = stressRowsOf(plan, o);
  for (int i = 0; i < plan.jobCount(); ++i) {
    const json& r = results.at(size_t(i));
    const StressRowRun run = stressRunOf(plan, i, rows.size());
    const json& done = r.at("rows");
    if (int(done.size()) != run.count) throw std::runtime_error(plan.dir + ": " + plan.jobName(i) + " has the wrong number of rows");
    for (int k = 0; k < run.count; ++k) {
      StressRow& row = rows[size_t(run.first + k)];
      if (done[size_t(k)].at("row") != stressRowJson(row))
        throw std::runtime_error(plan.dir + ": " + plan.jobName(i) + " rendered another row than the plan's");
      for (const json& c : done[size_t(k)].at("cells")) {
        StressCell cell;
        cell.layers = c.at("layers").get<int>();
        cell.alpha = float(exactNumberOf(c.at("alpha")));
        cell.error = exactNumberOf(c.at("error"));
        cell.nonFinitePixels = c.at("non_finite_pixels").get<size_t>();
        cell.infIn = c.at("inf_in").get<std::vector<std::string>>();
        cell.revealUnderflow = c.at("reveal_underflow").get<bool>();
        cell.momentFallbacks = c.at("moment_fallbacks").get<uint64_t>();
        row.cells.push_back(cell);
      }
      if (row.cells.size() != o.layers.size() * o.alphas.size())
        throw std::runtime_error(plan.dir + ": " + plan.jobName(i) + " has the wrong number of cells");
    }
  }
  const JobsRan ran = jobsRan(results);
  writeStressAtlas(rows, o, ran.seconds, jobsProvenance(plan.jobCount(), ran.nodes, ran.threads == 0),
                   out.empty() ? plan.options.at("out").get<std::string>() : out);
  return 0;
}

}  // namespace

Plan planStress(const StressOptions& o, const std::string& out, int rowsPerJob, const std::string& dir) {
  const std::vector<StressRow> rows = stressRowsFor(o);
  Plan plan;
  plan.dir = dir, plan.kind = "stress", plan.planner = ProgramIdentity::ofThisProcess();
  json alphas = json::array(), list = json::array();
  for (float a : o.alphas) alphas.push_back(exactNumber(a));
  for (const StressRow& r : rows) list.push_back(stressRowJson(r));
  plan.options = {{"out", fs::absolute(out).lexically_normal().string()}, {"conditions", o.conditions}, {"methods", o.methods},
                  {"layers", o.layers}, {"alphas", alphas}, {"size", o.size}, {"rows", list}};
  for (const JobRun& run : evenRuns(int(rows.size()), rowsPerJob > 0 ? rowsPerJob : defaultStressRowsPerJob(o.size)))
    plan.jobs.push_back({{"first", run.first}, {"count", run.count}});
  writePlan(plan);
  return plan;
}

const PlanKind& stressPlanKind() {
  static const PlanKind kind{"stress", runStressJob, collectStress};
  return kind;
}

}  // namespace oitref::tools
