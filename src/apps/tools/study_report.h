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
// index.html, results.json and results.csv into `dir` (created if need be).
void writeStudyReport(const StudyResult& result, const std::string& dir);

// Indices of the rows on the speed–accuracy Pareto front: no other row is at least as fast and at
// least as accurate and better in one (errors below `floor` count as `floor`). The ground truth
// (row 0, the A-buffer, exact by definition) is a method like the others here.
std::vector<size_t> paretoFront(const std::vector<StudyRow>& rows, double floor);

// A row of the thesis's Table 3.2 (memory per pixel) and the study configuration that has its
// attachments, with what the thesis counts that oitref does not allocate.
struct ThesisMemoryRow {
  const char* name;  // as Table 3.2 names it
  int bytesPerPixel;
  const char* counting;  // the difference to oitref's count, explained
};
// The Table 3.2 row measured in the configuration `variant`, or null.
const ThesisMemoryRow* thesisMemoryRow(const StudyVariant& variant);

}  // namespace oitref::tools
