// `oitref study … --plan DIR`: the study as jobs of a plan folder (job_plan.h). A job is a run of
// one scene's configurations, in the study's order; each job renders the A-buffer itself for the
// truth its rows are measured against (untimed, where its run does not start with it) instead of
// waiting for a first job to write it: frames are the same bits in every process, an A-buffer
// frame costs about what one configuration's does, and the jobs need no order among them and
// share no files but their own.
#pragma once

#include <string>
#include <vector>

#include "tools/job_plan.h"
#include "tools/plan_kinds.h"
#include "tools/study.h"

namespace oitref::tools {

// What `oitref study` was asked, as a plan records it (the profile and memory limit as given:
// each job parses them again).
struct StudyPlanRequest {
  StudyOptions options;
  std::string profileText = "exact", memoryLimitText;
  int configurationsPerJob = 0;  // 0: as many as make about kJobPixelFrames of work (study_jobs.cpp)
};

// Writes the plan into `dir`; returns it.
Plan planStudy(const StudyPlanRequest& request, const std::string& dir);

// Its jobs run and are collected through studyPlanKind() (plan_kinds.h).

}  // namespace oitref::tools
