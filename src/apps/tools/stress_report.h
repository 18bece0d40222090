// What `oitref stress` writes: atlas.html (per condition, a heatmap of error over layers × α for
// each method and format, numeric failures marked), atlas.json and atlas.csv.
#pragma once

#include <string>
#include <vector>

#include "tools/stress.h"

namespace oitref::tools {

// The failures of one row, by the smallest layer count at which each first appears.
struct StressFinding {
  std::string what;  // "inf in accum", "non-finite pixels", "reveal underflow", "moment fallback"
  int firstLayers = 0;
  float alpha = 0;   // the first α of the sweep that shows it at firstLayers
  int cells = 0;     // how many cells of the row show it
};
std::vector<StressFinding> stressFindings(const StressRow& row);

// provenance: plan_kinds.h's jobsProvenance for an atlas run as jobs, else "".
std::string stressHtml(const std::vector<StressRow>& rows, const StressOptions& options, double seconds,
                       const std::string& provenance = "");
std::string stressJson(const std::vector<StressRow>& rows, const StressOptions& options);
std::string stressCsv(const std::vector<StressRow>& rows);
// atlas.html, atlas.json and atlas.csv into `dir` (created if need be), and the command's summary
// on stdout.
void writeStressAtlas(const std::vector<StressRow>& rows, const StressOptions& options, double seconds,
                      const std::string& provenance, const std::string& dir);

}  // namespace oitref::tools
