// `oitref blend --cases`: parsing, exact values, output that round-trips, and error reporting.
#include <catch2/catch.hpp>

#include <sstream>

#include "oitref/core/blend.h"
#include "support.h"
#include "tools/blend_case.h"
#include "tools/number_parse.h"

using namespace oitref;
using namespace oitref::tools;

TEST_CASE("csv: numbers parse exactly (decimal, hex float, nan, inf)", "[csv]") {
  CHECK(*parseFloatExact("0x1.8p-3") == 0.1875f);
  CHECK(*parseFloatExact("0.1") == 0.1f);
  CHECK(*parseFloatExact(" 1e-45 ") == std::ldexp(1.0f, -149));  // correctly rounded to the denormal
  CHECK(std::isnan(*parseFloatExact("nan")));
  CHECK(*parseFloatExact("-inf") == -INFINITY);
  CHECK(*parseFloatExact("inf") == INFINITY);
  CHECK(*parseFloatExact("1e39") == INFINITY);
  CHECK_FALSE(parseFloatExact("1.0x"));
  CHECK_FALSE(parseFloatExact(""));
  CHECK_FALSE(parseFloatExact("zero"));
  test::BitStream rng(4);
  for (int i = 0; i < 100000; ++i) {
    const float v = test::fromBits(rng.next());
    if (std::isnan(v)) continue;
    REQUIRE(test::toBits(*parseFloatExact(hexFloat(v))) == test::toBits(v));
  }
}

TEST_CASE("csv: a batch round-trips: results parse back to the stored bits", "[csv]") {
  std::ostringstream in;
  in << blendCsvHeader(false) << "\n";
  test::BitStream rng(6);
  const std::vector<std::string> formats = {"rgba8", "rgb10a2", "rgba16f", "rgba32f", "r11g11b10f", "rg16f", "rgba:e5m2"};
  for (int i = 0; i < 500; ++i) {
    in << formats[size_t(i) % formats.size()] << "," << toString(BlendEquation(i % 5)) << ","
       << toString(BlendEquation((i / 5) % 5)) << "," << toString(BlendFactor(i % 15)) << ","
       << toString(BlendFactor((i / 3) % 15)) << "," << toString(BlendFactor((i / 7) % 15)) << ","
       << toString(BlendFactor((i / 11) % 15));
    for (int k = 0; k < 12; ++k) in << "," << hexFloat(rng.uniform(-0.5f, 3.0f));
    in << "\n";
  }
  std::istringstream input(in.str());
  std::ostringstream out, err;
  REQUIRE(runBlendCsv(input, out, err, exactProfile(), "test") == 0);
  CHECK(err.str().empty());
  std::istringstream lines(out.str());
  std::string line;
  std::getline(lines, line);
  CHECK(line == blendCsvHeader(true));
  int n = 0;
  while (std::getline(lines, line)) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    std::string s;
    while (std::getline(fields, s, ',')) f.push_back(s);
    REQUIRE(f.size() == 25);
    // Re-evaluate the input columns: same bits.
    std::string input19;
    for (int k = 0; k < 19; ++k) input19 += (k ? "," : "") + f[size_t(k)];
    const BlendCase c = parseBlendCsvLine(input19);
    const BlendOutcome o = evaluate(c, exactProfile());
    CHECK(f[19] == texelBitsToString(c.format, o.dstTexel.data()));
    CHECK(f[20] == texelBitsToString(c.format, o.resultTexel.data()));
    // The printed result values are the stored value exactly.
    for (int k = 0; k < 4; ++k) {
      const float printed = *parseFloatExact(f[size_t(21 + k)]);
      if (std::isnan(o.result[k])) CHECK(std::isnan(printed));
      else CHECK(test::toBits(printed) == test::toBits(o.result[k]));
    }
    // Storing the printed result again gives the same bits (a stored value is a fixed point).
    uint8_t again[16];
    encodeTexel(c.format, o.result, exactProfile(), again);
    CHECK(texelBitsToString(c.format, again) == f[20]);
    ++n;
  }
  CHECK(n == 500);
}

TEST_CASE("csv: bad lines are reported with line and column, the rest still run", "[csv]") {
  std::istringstream input(blendCsvHeader(false) + "\n" +
                           "rgba8,add,add,one,zero,one,zero,0,0,0,0,0,0,0,0,1,1,1,1\n"
                           "rgba9,add,add,one,zero,one,zero,0,0,0,0,0,0,0,0,1,1,1,1\n"
                           "rgba8,add,add,one,zero,one,zero,0,0,0,0,0,0,0,0,1,1,1\n"
                           "rgba8,add,add,one,zero,one,zero,0,0,0,0,0,0,0,0,1,1,1,1.5.2\n"
                           "rgba8,mul,add,one,zero,one,zero,0,0,0,0,0,0,0,0,1,1,1,1\n");
  std::ostringstream out, err;
  CHECK(runBlendCsv(input, out, err, exactProfile(), "cases.csv") == 4);
  const std::string e = err.str();
  CHECK_THAT(e, Catch::Contains("cases.csv: line 3, column 1 (format): unknown format 'rgba9'"));
  CHECK_THAT(e, Catch::Contains("cases.csv: line 4, column 19 (src_a): expected 19 fields, found 18"));
  CHECK_THAT(e, Catch::Contains("cases.csv: line 5, column 19 (src_a): '1.5.2' is not a number"));
  CHECK_THAT(e, Catch::Contains("cases.csv: line 6, column 2 (eq_rgb): unknown blend equation 'mul'"));
  CHECK_THAT(out.str(), Catch::Contains("ff ff ff ff"));
}

TEST_CASE("csv: a header's columns are read by name, in any order", "[csv]") {
  const std::string canonical = "rgba16f,add,add,src_alpha,one_minus_src_alpha,one,one_minus_src_alpha,0,0,0,0,1,0.5,0,1,0.2,0.4,0.6,0.5";
  // The same case with the source columns first and the format last.
  const std::string reorderedHeader =
      "src_r,src_g,src_b,src_a,eq_rgb,eq_alpha,src_rgb,dst_rgb,src_alpha,dst_alpha,const_r,const_g,const_b,const_a,dst_r,dst_g,"
      "dst_b,dst_a,format";
  const std::string reordered = "0.2,0.4,0.6,0.5,add,add,src_alpha,one_minus_src_alpha,one,one_minus_src_alpha,0,0,0,0,1,0.5,0,1,rgba16f";
  std::istringstream a(blendCsvHeader(false) + "\n" + canonical + "\n"), b(reorderedHeader + "\n" + reordered + "\n");
  std::ostringstream outA, outB, err;
  REQUIRE(runBlendCsv(a, outA, err, exactProfile(), "a.csv") == 0);
  REQUIRE(runBlendCsv(b, outB, err, exactProfile(), "b.csv") == 0);
  // The result columns (after the 19 echoed inputs) are the same.
  auto results = [](const std::string& out) {
    const std::string line = out.substr(out.find('\n') + 1);
    size_t at = 0;
    for (int i = 0; i < 19; ++i) at = line.find(',', at) + 1;
    return line.substr(at);
  };
  CHECK(results(outA.str()) == results(outB.str()));
  CHECK(err.str().empty());
  // A bad field is reported at its own column; a header without a column is refused.
  std::istringstream bad(reorderedHeader + "\n" + "0.2,0.4,0.6,x,add,add,src_alpha,one_minus_src_alpha,one,one_minus_src_alpha,0,0,0,0,1,0.5,0,1,rgba16f\n");
  std::ostringstream outC, errC;
  CHECK(runBlendCsv(bad, outC, errC, exactProfile(), "c.csv") == 1);
  CHECK_THAT(errC.str(), Catch::Contains("c.csv: line 2, column 4 (src_a): 'x' is not a number"));
  std::istringstream missing("format,eq_rgb,eq_alpha\nrgba8,add,add\n");
  std::ostringstream outD, errD;
  CHECK_THROWS_WITH(runBlendCsv(missing, outD, errD, exactProfile(), "d.csv"), Catch::Contains("d.csv: line 1: the header has no column 'src_rgb'"));
}
