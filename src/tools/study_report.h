// What `oitref study` writes: index.html (a page a person would rather look at than read),
// results.json and results.csv (every number).
#pragma once

#include <string>
#include <vector>

#include "tools/study.h"

namespace oitref::tools {

std::string studyHtml(const StudyResult& result);
std::string studyJson(const StudyResult& result);
std::string studyCsv(const StudyResult& result);

// Indices of the rows on the speed–accuracy Pareto front: no other row is at least as fast and at
// least as accurate and better in one (errors below `floor` count as `floor`). The ground truth
// (row 0, the A-buffer, exact by definition) is a method like the others here.
std::vector<size_t> paretoFront(const std::vector<StudyRow>& rows, double floor);

// The Thesis's Table 3.2 per-pixel figure for the configurations it measured, or 0.
int thesisBytesPerPixel(const StudyVariant& variant);

}  // namespace oitref::tools
