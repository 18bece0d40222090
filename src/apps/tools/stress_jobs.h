// `oitref stress … --plan DIR`: the stability atlas as jobs of a plan folder (job_plan.h), each a
// run of consecutive atlas rows (a condition × a method configuration, all its cells). The cells
// depend on nothing but their own scene, so the jobs need no ground truth from each other.
#pragma once

#include <algorithm>
#include <string>

#include "tools/job_plan.h"
#include "tools/plan_kinds.h"
#include "tools/stress.h"

namespace oitref::tools {

// Writes the plan into `dir` (rowsPerJob 0: defaultStressRowsPerJob); the atlas goes to `out`.
Plan planStress(const StressOptions& options, const std::string& out, int rowsPerJob, const std::string& dir);
// Rows a job gets by default: about two minutes of a core. The full atlas at --size 4 (256 rows
// of 130 cells, up to 4096 layers) took 124 s of one core here, about 0.5 s a row, and a row's
// time grows with its cells' pixels: at size 4, 240 rows a job; at 16, 15; from 62 on, one.
inline int defaultStressRowsPerJob(int size) { return std::max(1, 3840 / std::max(1, size * size)); }

}  // namespace oitref::tools
