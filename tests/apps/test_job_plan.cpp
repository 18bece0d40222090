// Plan folders (tools/job_plan.h): the jobs' shares of a work list, the --array lists of missing
// jobs, and the numbers of a result file, each against what it must be by definition.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "tools/job_plan.h"

using namespace oitref::tools;

TEST_CASE("plans: evenRuns covers the list once, in as few runs as allowed, lengths within one", "[jobs]") {
  for (int total = 0; total <= 60; ++total)
    for (int atMost = 1; atMost <= 70; ++atMost) {
      const std::vector<JobRun> runs = evenRuns(total, atMost);
      const int expectedRuns = total == 0 ? 0 : (total + atMost - 1) / atMost;
      REQUIRE(int(runs.size()) == expectedRuns);
      int next = 0, shortest = total, longest = 0;
      for (const JobRun& r : runs) {
        REQUIRE(r.first == next);
        REQUIRE(r.count >= 1);
        REQUIRE(r.count <= atMost);
        shortest = std::min(shortest, r.count), longest = std::max(longest, r.count);
        next += r.count;
      }
      REQUIRE(next == total);
      if (!runs.empty()) REQUIRE(longest - shortest <= 1);
    }
}

TEST_CASE("plans: indexRanges writes a Slurm --array list that reads back to the indices", "[jobs]") {
  std::mt19937 random(5);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<int> indices;
    for (int i = 0; i < 40; ++i)
      if (random() % 3 == 0) indices.push_back(i);
    const std::string text = indexRanges(indices);
    // Parsed as Slurm reads --array: comma-separated items, each N or N-M.
    std::vector<int> back;
    size_t at = 0;
    while (at < text.size()) {
      size_t end = text.find(',', at);
      if (end == std::string::npos) end = text.size();
      const std::string item = text.substr(at, end - at);
      const size_t dash = item.find('-');
      const int first = std::stoi(item.substr(0, dash)), last = dash == std::string::npos ? first : std::stoi(item.substr(dash + 1));
      REQUIRE(first <= last);
      for (int i = first; i <= last; ++i) back.push_back(i);
      at = end + 1;
    }
    REQUIRE(back == indices);
  }
  REQUIRE(indexRanges({}).empty());
  REQUIRE(indexRanges({0, 1, 2, 3, 7, 9, 10}) == "0-3,7,9-10");
}

TEST_CASE("plans: a result file's numbers read back to the same bits, inf and NaN included", "[jobs]") {
  std::mt19937_64 random(11);
  std::vector<double> values = {0.0, -0.0, 1.0, 0.1, 1e-310, std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity()};
  for (int i = 0; i < 2000; ++i) {
    const uint64_t bits = random();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isnan(v)) values.push_back(v);
  }
  for (double v : values) {
    // Through the text a result file holds.
    const double back = exactNumberOf(nlohmann::json::parse(nlohmann::json{{"v", exactNumber(v)}}.dump()).at("v"));
    uint64_t a, b;
    std::memcpy(&a, &v, sizeof a), std::memcpy(&b, &back, sizeof b);
    REQUIRE(a == b);
  }
  REQUIRE(std::isnan(exactNumberOf(nlohmann::json::parse(nlohmann::json(exactNumber(std::nan(""))).dump()))));
  REQUIRE_THROWS_WITH(exactNumberOf(nlohmann::json("fast")), Catch::Contains("'fast' is not a number"));
}
