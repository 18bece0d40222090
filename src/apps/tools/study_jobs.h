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

// Runs job `index` of a study plan into `staging` (its images, under <scene>/) and returns its
// result: its rows and the scene's figures.
nlohmann::json runStudyJob(const Plan& plan, int index, const std::string& staging, Renderer& renderer,
                           const StudyProgress& progress);

// Puts the jobs' results (results[i] of job i, all done) together into the study's result and
// copies their images into the plan's report folder (`outDir`).
StudyResult collectStudy(const Plan& plan, const std::vector<nlohmann::json>& results, const std::string& outDir);

// The report folder the plan names (the study's --out).
std::string studyReportFolder(const Plan& plan);

}  // namespace oitref::tools
