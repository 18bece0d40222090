#include "tools/stress_report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "oitref/oit/image_io.h"
#include "oitref/oit/metrics.h"
#include "tools/html.h"
#include "tools/number_parse.h"

namespace oitref::tools {
namespace {

using html::fmt;

std::string alphaText(float a) {
  if (a == 1.0f - 1e-6f) return "1−1e-6";
  return fmt("%g", double(a));
}

// Errors on a log scale: 1e-6 and below black, 1 and above white.
double errorScale(double e) { return e <= 1e-6 ? 0.0 : std::min(1.0, (std::log10(e) + 6.0) / 6.0); }

std::string failures(const StressCell& c) {
  std::string s;
  if (c.nonFinitePixels) s += std::to_string(c.nonFinitePixels) + " non-finite pixels; ";
  for (const std::string& a : c.infIn) s += "inf/NaN in " + a + "; ";
  if (c.revealUnderflow) s += "reveal underflowed to 0; ";
  if (c.momentFallbacks) s += std::to_string(c.momentFallbacks) + " moment fallbacks; ";
  return s;
}

std::string atlasTable(const StressRow& row, const StressOptions& o) {
  std::ostringstream t;
  t << "<figure class=atlas><figcaption>" << row.config.label() << "</figcaption><table><tr><th>n \\ α</th>";
  for (float a : o.alphas) t << "<th>" << alphaText(a) << "</th>";
  t << "</tr>\n";
  for (size_t i = 0; i < o.layers.size(); ++i) {
    t << "<tr><th>" << o.layers[i] << "</th>";
    for (size_t j = 0; j < o.alphas.size(); ++j) {
      const StressCell& c = row.cells[i * o.alphas.size() + j];
      std::string mark, cls;
      if (c.nonFinitePixels) mark = "N", cls = " class=nonfinite";
      else if (!c.infIn.empty()) mark = "∞", cls = " class=overflow";
      else if (c.revealUnderflow) mark = "0", cls = " class=underflow";
      else if (c.momentFallbacks) mark = "f", cls = " class=fallback";
      t << "<td" << cls << " style=\"background:" << (c.nonFinitePixels ? std::string("#0f0") : html::heatmapCss(errorScale(c.error)))
        << "\" title=\"n=" << c.layers << " α=" << alphaText(c.alpha) << ": error " << fmt("%.3g", c.error) << ". "
        << failures(c) << "\">" << mark << "</td>";
    }
    t << "</tr>\n";
  }
  t << "</table></figure>\n";
  return t.str();
}

constexpr const char* kAtlasStyle = R"(body{font:14px/1.4 system-ui,sans-serif;margin:2em auto;max-width:1500px;padding:0 1em;color:#222}
h2{border-bottom:2px solid #ddd;padding-top:.5em}.atlases{display:flex;flex-wrap:wrap;gap:14px}
figure.atlas{margin:0}figure.atlas figcaption{font-size:12px;font-weight:bold}
.atlas table{border-collapse:collapse}.atlas td{width:14px;height:11px;padding:0;font-size:9px;text-align:center;color:#0ff;font-weight:bold}
.atlas th{font-size:9px;font-weight:normal;padding:0 2px;text-align:right}.atlas tr:first-child th{writing-mode:vertical-rl;text-align:left}
td.nonfinite{color:#000}td.overflow{color:#0ff}td.underflow{color:#ff0}td.fallback{color:#9f9}
table.findings{border-collapse:collapse}table.findings td,table.findings th{border:1px solid #ccc;padding:1px 6px;font-size:13px}
.legend{display:flex;align-items:center;gap:8px}.legend .bar{width:240px;height:12px;border:1px solid #999})";

}  // namespace

std::vector<StressFinding> stressFindings(const StressRow& row) {
  std::map<std::string, StressFinding> first;
  std::vector<std::string> order;
  auto note = [&](const std::string& what, const StressCell& c) {
    auto it = first.find(what);
    if (it == first.end()) {
      first[what] = {what, c.layers, c.alpha, 1};
      order.push_back(what);
    } else {
      ++it->second.cells;
    }
  };
  for (const StressCell& c : row.cells) {
    if (c.nonFinitePixels) note("non-finite pixels", c);
    for (const std::string& a : c.infIn) note("inf/NaN in " + a, c);
    if (c.revealUnderflow) note("reveal underflow", c);
    if (c.momentFallbacks) note("moment fallback", c);
  }
  std::vector<StressFinding> out;
  for (const std::string& w : order) out.push_back(first[w]);
  return out;
}

std::string stressHtml(const std::vector<StressRow>& rows, const StressOptions& o, double seconds, const std::string& provenance) {
  std::ostringstream h;
  h << "<!doctype html>\n<html lang=en>\n<head>\n<meta charset=utf-8>\n<title>oitref stability atlas</title>\n<style>"
    << kAtlasStyle << "</style>\n</head>\n<body>\n<h1>oitref stability atlas</h1>\n<p>Each cell is one parametric scene: n "
       "full-screen layers (rows) of opacity α (columns), alternating two colours, submitted in a fixed shuffled order, "
       "rendered at " << o.size << "×" << o.size << " pixels with the method and format named above it, and compared with the "
       "exact composite computed in double from the layer list. Colour: the largest error over pixels and RGB, on a log "
       "scale. Marks: <b>N</b> non-finite pixels in the result (cell green), <b>∞</b> an attachment holds inf or NaN, "
       "<b>0</b> the revealage underflowed to 0 while the exact transmittance is above 0, <b>f</b> MBOIT's moment "
       "reconstruction fell back to the fragment's own layer. Hover a cell for its numbers; every number is in "
       "<a href=atlas.json>atlas.json</a> and <a href=atlas.csv>atlas.csv</a>. "
    << rows.size() << " rows, " << fmt("%.1f", seconds) << " s.</p>\n"
    << (provenance.empty() ? "" : "<p class=distributed><b>" + html::escape(provenance) + "</b></p>\n") << "<div class=legend><span>error ≤ 1e-6</span><div class=bar "
       "style=\"background:" << html::heatmapGradientCss() << "\"></div><span>≥ 1 (1e-6, 1e-5, …, 1 evenly)</span></div>\n";
  // Findings first: where each failure starts.
  h << "<h2 id=findings>Where each failure starts</h2>\n<table class=findings><tr><th>condition</th><th>method and format</th>"
       "<th>failure</th><th>first at n</th><th>with α</th><th>cells</th></tr>\n";
  for (const StressRow& r : rows)
    for (const StressFinding& f : stressFindings(r))
      h << "<tr><td>" << r.condition.name << "</td><td>" << r.config.label() << "</td><td>" << f.what << "</td><td>"
        << f.firstLayers << "</td><td>" << alphaText(f.alpha) << "</td><td>" << f.cells << "</td></tr>\n";
  h << "</table>\n";
  std::string condition;
  for (const StressRow& r : rows) {
    if (r.condition.name != condition) {
      if (!condition.empty()) h << "</div>\n";
      condition = r.condition.name;
      h << "<h2 id=\"" << condition << "\">" << condition << "</h2>\n<p>" << r.condition.description << "</p>\n<div class=atlases>\n";
    }
    h << atlasTable(r, o);
  }
  if (!condition.empty()) h << "</div>\n";
  h << "</body>\n</html>\n";
  return h.str();
}

std::string stressJson(const std::vector<StressRow>& rows, const StressOptions& o) {
  std::ostringstream j;
  j << "{\n  \"size\": " << o.size << ",\n  \"rows\": [";
  for (size_t r = 0; r < rows.size(); ++r) {
    const StressRow& row = rows[r];
    j << (r ? "," : "") << "\n    {\"condition\": " << jsonString(row.condition.name) << ", \"method\": "
      << jsonString(row.config.method) << ", \"options\": {";
    size_t k = 0;
    for (const auto& [key, value] : row.config.options) j << (k++ ? ", " : "") << jsonString(key) << ": " << jsonString(value);
    j << "},\n     \"findings\": [";
    const std::vector<StressFinding> findings = stressFindings(row);
    for (size_t f = 0; f < findings.size(); ++f)
      j << (f ? ", " : "") << "{\"what\": " << jsonString(findings[f].what) << ", \"first_layers\": " << findings[f].firstLayers
        << ", \"alpha\": " << jsonNumber(findings[f].alpha) << ", \"cells\": " << findings[f].cells << "}";
    j << "],\n     \"cells\": [";
    for (size_t c = 0; c < row.cells.size(); ++c) {
      const StressCell& cell = row.cells[c];
      j << (c ? "," : "") << "\n      {\"layers\": " << cell.layers << ", \"alpha\": " << jsonNumber(cell.alpha)
        << ", \"error\": " << jsonNumber(cell.error) << ", \"non_finite_pixels\": " << cell.nonFinitePixels << ", \"inf_in\": [";
      for (size_t a = 0; a < cell.infIn.size(); ++a) j << (a ? ", " : "") << jsonString(cell.infIn[a]);
      j << "], \"reveal_underflow\": " << (cell.revealUnderflow ? "true" : "false") << ", \"moment_fallbacks\": "
        << cell.momentFallbacks << "}";
    }
    j << "\n     ]}";
  }
  j << "\n  ]\n}\n";
  return j.str();
}

std::string stressCsv(const std::vector<StressRow>& rows) {
  std::ostringstream c;
  c << "condition,method,options,layers,alpha,error,non_finite_pixels,inf_in,reveal_underflow,moment_fallbacks\n";
  for (const StressRow& r : rows) {
    std::string options;
    for (const auto& [k, v] : r.config.options) options += (options.empty() ? "" : " ") + k + "=" + v;
    for (const StressCell& cell : r.cells) {
      std::string inf;
      for (const std::string& a : cell.infIn) inf += (inf.empty() ? "" : " ") + a;
      c << r.condition.name << "," << r.config.method << "," << options << "," << cell.layers << "," << jsonNumber(cell.alpha)
        << "," << jsonNumber(cell.error) << "," << cell.nonFinitePixels << "," << inf << ","
        << (cell.revealUnderflow ? 1 : 0) << "," << cell.momentFallbacks << "\n";
    }
  }
  return c.str();
}

void writeStressAtlas(const std::vector<StressRow>& rows, const StressOptions& o, double seconds,
                      const std::string& provenance, const std::string& dir) {
  const std::filesystem::path folder(dir);
  std::filesystem::create_directories(folder);
  writeTextFile((folder / "atlas.json").string(), stressJson(rows, o));
  writeTextFile((folder / "atlas.csv").string(), stressCsv(rows));
  writeTextFile((folder / "atlas.html").string(), stressHtml(rows, o, seconds, provenance));
  size_t failures = 0;
  for (const StressRow& r : rows) failures += stressFindings(r).size();
  std::printf("oitref stress: %zu rows × %zu cells, %zu failure kinds found, %.1f s\natlas: %s\n", rows.size(),
              o.layers.size() * o.alphas.size(), failures, seconds,
              std::filesystem::absolute(folder / "atlas.html").lexically_normal().c_str());
}

}  // namespace oitref::tools
