// `oitref suite … --plan DIR` and `oitref reference … --plan DIR`: one job per scene (a scene's
// every method, the A-buffer first as the truth of its errors), in plan folders (job_plan.h).
#pragma once

#include <string>
#include <vector>

#include "tools/job_plan.h"
#include "tools/plan_kinds.h"

namespace oitref::tools {

struct SuiteRequest {
  std::vector<std::string> scenes;
  int width = 0, height = 0;  // 0: each scene's own
  std::string out;            // the images' folder; "" for none
  std::string profileText = "exact", memoryLimitText;
};
Plan planSuite(const SuiteRequest& request, const std::string& dir);

// The golden set of the scenes in `scenesDir`, checked against (or, with `write`, written into)
// the reference folder `referenceDir`.
Plan planReference(const std::string& scenesDir, const std::string& referenceDir, bool write, const std::string& dir);

}  // namespace oitref::tools
