#include "tools/study_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "oitref/oit/image_io.h"
#include "oitref/oit/metrics.h"
#include "tools/html.h"
#include "tools/plan_kinds.h"
#include "tools/number_parse.h"

namespace oitref::tools {
namespace {

using html::escape;
using html::fmt;

// The heatmaps' colour scale as a CSS gradient, from the same function that paints them.
std::string legendHtml(double scale) {
  return "<div class=legend><span>|Δ| 0</span><div class=bar style=\"background:" + html::heatmapGradientCss() +
         "\"></div><span>" + fmt("%.3g", scale) + " and above</span><span class=nonfinite>■ non-finite</span></div>\n";
}

// 20 distinguishable colours (the first ten are the common "category10" set).
const char* kMethodColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
                                "#7f7f7f", "#bcbd22", "#17becf", "#393b79", "#e7ba52", "#637939", "#843c39",
                                "#7b4173", "#3182bd", "#31a354", "#fd8d3c", "#000000", "#9c9ede"};

std::string colourOf(const std::string& method, std::map<std::string, int>& index) {
  const auto it = index.emplace(method, int(index.size())).first;
  return kMethodColours[size_t(it->second) % std::size(kMethodColours)];
}

// Errors below this are rounding of the ground truths against each other (the ray cast, the
// A-buffer in double): the scatter draws them on one "exact" band under its axis.
constexpr double kExact = 1e-6;

// Speed–accuracy scatter, time and RMSE on log scales, the Pareto front drawn as a staircase.
std::string scatterSvg(const StudyScene& s, std::map<std::string, int>& colours) {
  constexpr double W = 760, H = 440, left = 70, right = 170, top = 16, bottom = 48;
  if (s.rows.size() < 2) return "";
  double msLo = 1e300, msHi = 0, eLo = 1e300, eHi = 0;
  bool anyExact = false;
  for (size_t i = 0; i < s.rows.size(); ++i) {
    const StudyRow& r = s.rows[i];
    msLo = std::min(msLo, r.ms), msHi = std::max(msHi, r.ms);
    if (r.rmse < kExact) anyExact = true;
    else eLo = std::min(eLo, r.rmse), eHi = std::max(eHi, r.rmse);
  }
  if (eHi == 0) eLo = eHi = 1e-3;
  const double x0 = std::floor(std::log10(std::max(msLo, 1e-3))), x1 = std::max(x0 + 1, std::ceil(std::log10(msHi)));
  const double y1 = std::max(std::floor(std::log10(eLo)) + 1, std::ceil(std::log10(eHi)));
  const double y0 = std::floor(std::log10(eLo)) - (anyExact ? 0.7 : 0.0);  // room for the exact band
  auto px = [&](double ms) { return left + (std::log10(std::max(ms, 1e-3)) - x0) / (x1 - x0) * (W - left - right); };
  auto py = [&](double e) {
    const double l = e < kExact ? y0 : std::log10(e);
    return H - bottom - (l - y0) / (y1 - y0) * (H - top - bottom);
  };
  std::ostringstream svg;
  svg << "<svg class=scatter xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << W << " " << H << "\" width=\"" << W
      << "\" height=\"" << H << "\" role=img aria-label=\"time against error for " << escape(s.name) << "\">\n";
  for (double k = x0; k <= x1; ++k) {
    const double x = px(std::pow(10, k));
    svg << "<line class=grid x1=" << x << " y1=" << top << " x2=" << x << " y2=" << H - bottom << " />"
        << "<text x=" << x << " y=" << H - bottom + 16 << " text-anchor=middle>" << fmt("%g", std::pow(10, k)) << "</text>\n";
  }
  for (double k = std::ceil(y0); k <= y1; ++k) {
    const double y = py(std::pow(10, k));
    svg << "<line class=grid x1=" << left << " y1=" << y << " x2=" << W - right << " y2=" << y << " />"
        << "<text x=" << left - 6 << " y=" << y + 4 << " text-anchor=end>" << fmt("%g", std::pow(10, k)) << "</text>\n";
  }
  if (anyExact)
    svg << "<line class=exact x1=" << left << " y1=" << py(0) << " x2=" << W - right << " y2=" << py(0) << " />"
        << "<text x=" << left - 6 << " y=" << py(0) + 4 << " text-anchor=end>exact</text>\n";
  svg << "<text x=" << (left + W - right) / 2 << " y=" << H - 8 << " text-anchor=middle>frame time, ms (log)</text>"
      << "<text transform=\"translate(16," << (top + H - bottom) / 2
      << ") rotate(-90)\" text-anchor=middle>RMSE against the A-buffer (log)</text>\n";
  const std::vector<size_t> front = paretoFront(s.rows, kExact);
  // Labels of the front go where they overlap no earlier label: first just above the point,
  // then alternately lower and higher in steps of a line.
  std::vector<std::array<double, 3>> placed;  // x, baseline y, width
  auto labelY = [&](double x, double y, double width) {
    for (int k = 0; k < 12; ++k) {
      const double candidate = y + (k % 2 ? 1 : -1) * 12.0 * ((k + 1) / 2);
      const bool clash = std::any_of(placed.begin(), placed.end(), [&](const std::array<double, 3>& p) {
        return x < p[0] + p[2] && p[0] < x + width && std::fabs(candidate - p[1]) < 12;
      });
      if (!clash) {
        placed.push_back({x, candidate, width});
        return candidate;
      }
    }
    return y;
  };
  std::string steps;
  for (size_t k = 0; k < front.size(); ++k) {
    const StudyRow& r = s.rows[front[k]];
    if (k) steps += " " + fmt("%.1f", px(r.ms)) + "," + fmt("%.1f", py(s.rows[front[k - 1]].rmse));
    steps += " " + fmt("%.1f", px(r.ms)) + "," + fmt("%.1f", py(r.rmse));
  }
  svg << "<polyline class=front points=\"" << steps << "\" />\n";
  for (size_t i = 0; i < s.rows.size(); ++i) {
    const StudyRow& r = s.rows[i];
    const bool onFront = std::find(front.begin(), front.end(), i) != front.end();
    svg << "<circle cx=" << fmt("%.1f", px(r.ms)) << " cy=" << fmt("%.1f", py(r.rmse)) << " r=" << (onFront ? 6 : 4)
        << " fill=\"" << colourOf(r.variant.method, colours) << "\"" << (onFront ? " class=onfront" : "")
        << (r.nonFinitePixels ? " stroke=\"#f00\" stroke-width=2" : "") << "><title>" << escape(r.variant.method) << " "
        << escape(r.variant.label()) << ": " << fmt("%.3g", r.ms) << " ms, RMSE " << fmt("%.3g", r.rmse)
        << (r.nonFinitePixels ? ", " + std::to_string(r.nonFinitePixels) + " non-finite pixels" : "") << "</title></circle>\n";
    if (onFront) {
      const std::string text = r.variant.method + (r.variant.options.empty() ? "" : " " + r.variant.label());
      const double x = px(r.ms) + 8, y = labelY(x, py(r.rmse) - 6, 6.0 * double(text.size()));
      svg << "<text class=label x=" << fmt("%.1f", x) << " y=" << fmt("%.1f", y) << ">" << escape(text) << "</text>\n";
    }
  }
  // Method key.
  double ky = top + 8;
  std::vector<std::string> seen;
  for (size_t i = 0; i < s.rows.size(); ++i) {
    const std::string& m = s.rows[i].variant.method;
    if (std::find(seen.begin(), seen.end(), m) != seen.end()) continue;
    seen.push_back(m);
    svg << "<circle cx=" << W - right + 20 << " cy=" << ky << " r=4 fill=\"" << colourOf(m, colours) << "\" /><text x="
        << W - right + 30 << " y=" << ky + 4 << ">" << escape(m) << "</text>\n";
    ky += 17;
  }
  svg << "<line class=front x1=" << W - right + 12 << " y1=" << ky << " x2=" << W - right + 28 << " y2=" << ky
      << " /><text x=" << W - right + 30 << " y=" << ky + 4 << ">Pareto front</text>\n";
  svg << "</svg>\n";
  return svg.str();
}

std::string rowCells(const StudyRow& r) {
  std::ostringstream o;
  o << "<td>" << escape(r.variant.method) << "</td><td>" << escape(r.variant.label()) << "</td><td class=n>"
    << fmt("%.2f", r.ms) << "</td><td class=n>" << (r.fragmentsPerSecond > 0 ? fmt("%.3g", r.fragmentsPerSecond) : "–") << "</td><td class=n>"
    << r.bytesPerPixel << "</td><td class=n>" << r.passes << "</td><td class=n>" << fmt("%.3e", r.rmse)
    << "</td><td class=n>" << (std::isinf(r.psnr) ? std::string("∞") : fmt("%.2f", r.psnr)) << "</td><td class=n>"
    << fmt("%.4f", r.flip) << "</td><td class=n>" << fmt("%.3e", r.maxError) << "</td><td class=n"
    << (r.nonFinitePixels ? " style=\"color:#c00;font-weight:bold\"" : "") << ">" << r.nonFinitePixels << "</td><td>"
    << escape(r.note) << "</td>";
  return o.str();
}

std::string sceneSection(const StudyScene& s, double heatmapScale, std::map<std::string, int>& colours) {
  std::ostringstream o;
  o << "<section id=\"scene-" << escape(s.name) << "\">\n<h2>" << escape(s.name) << "</h2>\n<p>" << s.width << "×"
    << s.height << ", " << s.fragments << " transparent fragments, depth complexity up to " << s.depthComplexityMax
    << ". Ground truth: the A-buffer (exact per-pixel sort, OVER back to front). The ray cast, an independent ground "
       "truth, differs from it by RMSE "
    << fmt("%.2e", s.raycastRmse) << " (max " << fmt("%.2e", s.raycastMax) << ", " << fmt("%.2f", 100 * s.raycastShareWithin)
    << " % of pixels within 1/255).</p>\n";
  o << "<h3>Speed and accuracy</h3>\n" << scatterSvg(s, colours);
  o << "<h3>Images</h3>\n" << legendHtml(heatmapScale) << "<div class=grid>\n";
  for (const StudyRow& r : s.rows) {
    o << "<figure><img src=\"" << escape(r.image) << "\" alt=\"" << escape(r.variant.method + " " + r.variant.label())
      << "\"><img src=\"" << escape(r.heatmap) << "\" alt=\"error of " << escape(r.variant.method) << "\"><figcaption><b>"
      << escape(r.variant.method) << "</b> " << (r.variant.options.empty() ? "" : escape(r.variant.label())) << "<br>"
      << (&r == &s.rows.front() ? std::string("ground truth") : "RMSE " + fmt("%.2e", r.rmse) + ", ꟻLIP " + fmt("%.3f", r.flip))
      << "</figcaption></figure>\n";
  }
  o << "</div>\n<h3>Table</h3>\n<table>\n<tr><th>method</th><th>variant</th><th>ms</th><th>fragments/s</th><th>bytes/pixel</th>"
       "<th>passes</th><th>RMSE</th><th>PSNR dB</th><th>ꟻLIP</th><th>max error</th><th>non-finite pixels</th><th>notes</th></tr>\n";
  for (const StudyRow& r : s.rows) o << "<tr>" << rowCells(r) << "</tr>\n";
  o << "</table>\n</section>\n";
  return o.str();
}

// "2 threads", or for jobs with different thread counts, that they differ.
std::string threadsText(const StudyResult& result) {
  return result.threads > 0 ? std::to_string(result.threads) + " threads" : std::string("threads differing between jobs");
}

// Timing like the thesis's Table 3.1: variants down, scenes across.
std::string timingTable(const StudyResult& result) {
  std::ostringstream o;
  o << "<h2 id=timing>Timing</h2>\n<p>Median frame time in ms (like Table 3.1 of Rožek's thesis), " << threadsText(result)
    << ", median of " << result.runs << " runs after one warm-up (a warm-up of 100 ms or more counts as the first run).</p>\n<table>\n<tr><th>method</th><th>variant</th>";
  for (const StudyScene& s : result.scenes) o << "<th>" << escape(s.name) << "</th>";
  o << "</tr>\n";
  if (result.scenes.empty()) return o.str() + "</table>\n";
  for (size_t i = 0; i < result.scenes[0].rows.size(); ++i) {
    const StudyVariant& v = result.scenes[0].rows[i].variant;
    o << "<tr><td>" << escape(v.method) << "</td><td>" << escape(v.label()) << "</td>";
    for (const StudyScene& s : result.scenes) o << "<td class=n>" << fmt("%.2f", s.rows[i].ms) << "</td>";
    o << "</tr>\n";
  }
  return o.str() + "</table>\n";
}

// Memory like the thesis's Table 3.2, from the attachments each method declares.
std::string memoryTable(const StudyResult& result) {
  std::ostringstream o;
  o << "<h2 id=memory>Memory</h2>\n<p>Bytes per pixel of the attachments each method declares (the presented RGBA8 "
       "target and the depth buffer included, as the thesis includes the default framebuffer), and what that is at "
       "1920×1080 (like Table 3.2 of Rožek's thesis, whose figures are beside ours for the configuration with the "
       "formats it measured: the thesis presets, with weight=one and 16-bit targets for its WBOIT 16F). The thesis gives "
       "every pass a framebuffer with its own depth buffer where oitref's passes share the opaque one; the last "
       "column says what that adds. The A-buffer's fragment storage depends on the scene and is not included.</p>\n<table>\n"
       "<tr><th>method</th><th>variant</th><th>bytes/pixel</th><th>MB at 1920×1080</th><th>Table 3.2 row</th>"
       "<th>thesis bytes/pixel</th><th>what the thesis counts besides</th></tr>\n";
  if (result.scenes.empty()) return o.str() + "</table>\n";
  for (const StudyRow& r : result.scenes[0].rows) {
    const ThesisMemoryRow* thesis = thesisMemoryRow(r.variant);
    o << "<tr><td>" << escape(r.variant.method) << "</td><td>" << escape(r.variant.label()) << "</td><td class=n>"
      << r.bytesPerPixel << "</td><td class=n>" << fmt("%.3f", r.bytesPerPixel * 1920.0 * 1080.0 / 1e6) << "</td><td>"
      << (thesis ? thesis->name : "") << "</td><td class=n>" << (thesis ? std::to_string(thesis->bytesPerPixel) : "")
      << "</td><td>" << (thesis ? thesis->counting : "") << "</td></tr>\n";
  }
  return o.str() + "</table>\n";
}

constexpr const char* kStudyStyle = R"(body{font:15px/1.45 system-ui,sans-serif;margin:2em auto;max-width:1300px;padding:0 1em;color:#222}
h1{margin-bottom:.2em}h2{border-bottom:2px solid #ddd;padding-top:.6em}nav a{margin-right:1em}
table{border-collapse:collapse;margin:.5em 0 1.5em}td,th{border:1px solid #ccc;padding:2px 8px}th{background:#f3f3f3}
td.n{text-align:right;font-variant-numeric:tabular-nums}tr:hover td{background:#fafae8}
.grid{display:flex;flex-wrap:wrap;gap:10px}figure{margin:0;width:164px;font-size:12px}
figure img{width:160px;display:block;image-rendering:pixelated;border:1px solid #999;margin-bottom:2px}
.legend{display:flex;align-items:center;gap:8px;font-size:13px;margin:.3em 0 .8em}.legend .bar{width:240px;height:12px;border:1px solid #999}
.legend .nonfinite{color:#0f0;text-shadow:0 0 1px #000}
svg.scatter{font-size:12px;background:#fff;border:1px solid #ddd}svg .grid{stroke:#e4e4e4}
svg .front{fill:none;stroke:#c00;stroke-width:1.5;stroke-dasharray:4 3}svg .onfront{stroke:#000;stroke-width:1.5}
svg .label{font-size:11px}svg .exact{stroke:#999;stroke-dasharray:1 3})";

// Once the page has loaded, says how many images decoded, marks any that did not (and reports
// them on the console, where scripts/check_report.sh looks).
constexpr const char* kImageCheck = R"(<p id=imagestatus></p>
<script>
window.addEventListener('load', () => {
  const images = [...document.images], broken = images.filter(i => !i.complete || i.naturalWidth === 0);
  for (const i of broken) { i.style.outline = '3px solid red'; console.error('image failed to load: ' + i.getAttribute('src')); }
  const status = document.getElementById('imagestatus');
  status.dataset.images = images.length; status.dataset.broken = broken.length;
  status.textContent = broken.length ? broken.length + ' of ' + images.length + ' images failed to load' : '';
});
</script>
)";

}  // namespace

std::vector<size_t> paretoFront(const std::vector<StudyRow>& rows, double floor) {
  std::vector<size_t> front;
  for (size_t i = 0; i < rows.size(); ++i) {
    const double ti = rows[i].ms, ei = std::max(rows[i].rmse, floor);
    bool dominated = false;
    for (size_t j = 0; j < rows.size() && !dominated; ++j) {
      const double tj = rows[j].ms, ej = std::max(rows[j].rmse, floor);
      dominated = j != i && tj <= ti && ej <= ei && (tj < ti || ej < ei);
    }
    if (!dominated) front.push_back(i);
  }
  std::sort(front.begin(), front.end(), [&](size_t a, size_t b) { return rows[a].ms < rows[b].ms; });
  return front;
}

const ThesisMemoryRow* thesisMemoryRow(const StudyVariant& v) {
  // Algorithms 1–6 give each pass a framebuffer of its own: the transparent passes test against a
  // copy of the opaque depth (D2, and D_M for MBOIT's moment pass), and weighted sum's composite
  // target C3 has a depth buffer D3. oitref's passes share the opaque depth, and its
  // weighted-sum composite needs none. Three rows (weighted average and both WBOITs) are 8 B above
  // what their Require lines list: exactly an RGBA8 colour and a 32-bit depth buffer, a window's
  // default framebuffer, into which their composites draw (the thesis says its figures include the
  // default framebuffer). Peel's and weighted sum's lists end in such a framebuffer, F3, and their
  // figures are their lists; MBOIT 32F's figure is Algorithm 6's list alone, without those 8 B.
  static const std::map<std::string, std::string> kThesis16F = {
      {"preset", "thesis"}, {"weight", "one"}, {"accum", "rgba16f"}, {"reveal", "r16f"}};
  static const std::pair<StudyVariant, ThesisMemoryRow> rows[] = {
      {{"peel", {}}, {"Depth peeling", 24, "the same six attachments: C1/D1, C2/D2, C3/D3"}},
      {{"wsum", {}}, {"Weighted sum", 28, "+8: D2 (a copy of D1) and D3 of F3"}},
      {{"wavg", {}}, {"Weighted avg. 16F", 30, "+4: D2; +8: the default framebuffer (RGBA8, 32-bit depth) the composite draws into, which Algorithm 3 does not list"}},
      {{"wboit", kThesis16F}, {"WBOIT 16F", 30, "+4: D2; +8: the default framebuffer (RGBA8, 32-bit depth) the composite draws into, which Algorithm 4 does not list"}},
      {{"wboit", {{"preset", "thesis"}}}, {"WBOIT 32F", 40, "+4: D2; +8: the default framebuffer (RGBA8, 32-bit depth) the composite draws into, which Algorithm 4 does not list"}},
      {{"mboit", {{"preset", "thesis"}}}, {"MBOIT 32F", 56, "+8: D2 and D_M (Algorithm 6's list; the default framebuffer counted for WBOIT is not counted here)"}}};
  for (const auto& [variant, row] : rows)
    if (variant.method == v.method && variant.options == v.options) return &row;
  return nullptr;
}

namespace {

// A study run as jobs of a plan: its times come from separate processes, maybe other nodes and
// hours; the page says so where the figures are read (results.json gives each row's job and node).
std::string distributedNote(const StudyResult& result) {
  if (result.jobs == 0) return "";
  return "<p class=distributed><b>" + escape(jobsProvenance(result.jobs, result.nodes, result.threads == 0)) + "</b></p>\n";
}

}  // namespace

std::string studyHtml(const StudyResult& result) {
  std::map<std::string, int> colours;
  std::ostringstream o;
  o << "<!doctype html>\n<html lang=en>\n<head>\n<meta charset=utf-8>\n<title>oitref study</title>\n<style>" << kStudyStyle
    << "</style>\n</head>\n<body>\n<h1>oitref study</h1>\n<p>" << result.scenes.size() << " scenes, "
    << (result.scenes.empty() ? 0 : result.scenes[0].rows.size()) << " configurations each, " << threadsText(result)
    << ", each time the median of " << result.runs << " runs after one warm-up (a warm-up of 100 ms or more counts as the first run; every run bit-identical), "
    << "profile " << escape(result.profile) << "; " << fmt("%.1f", result.totalSeconds)
    << " s in all. Errors are against the A-buffer: RMSE, PSNR and max over RGB of the RGBA32F result, ꟻLIP (LDR, "
       "Andersson et al. 2020, 67 pixels per degree) of the same result as a display shows it (clamped to [0, 1], "
       "read as sRGB). Every number is also in "
       "<a href=results.json>results.json</a> and <a href=results.csv>results.csv</a>.</p>\n"
    << distributedNote(result) << "<nav>";
  for (const StudyScene& s : result.scenes) o << "<a href=\"#scene-" << escape(s.name) << "\">" << escape(s.name) << "</a>";
  o << "<a href=#timing>timing</a><a href=#memory>memory</a></nav>\n";
  for (const StudyScene& s : result.scenes) o << sceneSection(s, result.heatmapScale, colours);
  o << timingTable(result) << memoryTable(result) << kImageCheck << "</body>\n</html>\n";
  return o.str();
}

std::string studyJson(const StudyResult& result) {
  std::ostringstream o;
  o << "{\n  \"threads\": " << result.threads << ", \"runs\": " << result.runs << ", \"profile\": "
    << jsonString(result.profile) << ", \"heatmap_scale\": " << jsonNumber(result.heatmapScale)
    << ", \"total_seconds\": " << jsonNumber(result.totalSeconds);
  if (result.jobs > 0) {
    o << ", \"jobs\": " << result.jobs << ", \"nodes\": [";
    for (size_t i = 0; i < result.nodes.size(); ++i) o << (i ? ", " : "") << jsonString(result.nodes[i]);
    o << "]";
  }
  o << ",\n  \"scenes\": [";
  for (size_t si = 0; si < result.scenes.size(); ++si) {
    const StudyScene& s = result.scenes[si];
    o << (si ? "," : "") << "\n    {\"name\": " << jsonString(s.name) << ", \"width\": " << s.width << ", \"height\": "
      << s.height << ", \"fragments\": " << s.fragments << ", \"depth_complexity_max\": " << s.depthComplexityMax
      << ", \"raycast_rmse\": " << jsonNumber(s.raycastRmse) << ", \"raycast_max\": " << jsonNumber(s.raycastMax)
      << ", \"raycast_share_within_1_255\": " << jsonNumber(s.raycastShareWithin) << ",\n     \"rows\": [";
    for (size_t i = 0; i < s.rows.size(); ++i) {
      const StudyRow& r = s.rows[i];
      o << (i ? "," : "") << "\n      {\"method\": " << jsonString(r.variant.method) << ", \"options\": {";
      size_t k = 0;
      for (const auto& [key, value] : r.variant.options)
        o << (k++ ? ", " : "") << jsonString(key) << ": " << jsonString(value);
      o << "}, \"ms\": " << jsonNumber(r.ms) << ", \"run_ms\": [";
      for (size_t j = 0; j < r.runMs.size(); ++j) o << (j ? ", " : "") << jsonNumber(r.runMs[j]);
      o << "], \"fragments_shaded\": " << r.fragmentsShaded << ", \"fragments_per_second\": "
        << jsonNumber(r.fragmentsPerSecond) << ", \"bytes_per_pixel\": " << r.bytesPerPixel << ", \"passes\": " << r.passes
        << ", \"rmse\": " << jsonNumber(r.rmse) << ", \"psnr\": " << jsonNumber(r.psnr) << ", \"flip\": "
        << jsonNumber(r.flip) << ", \"max_error\": " << jsonNumber(r.maxError) << ", \"non_finite_pixels\": "
        << r.nonFinitePixels << ", \"note\": " << jsonString(r.note) << ", \"image\": " << jsonString(r.image)
        << ", \"heatmap\": " << jsonString(r.heatmap);
      if (r.job >= 0) o << ", \"job\": " << r.job << ", \"node\": " << jsonString(r.node);
      o << "}";
    }
    o << "\n    ]}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

void writeStudyReport(const StudyResult& result, const std::string& dir) {
  const std::filesystem::path folder(dir);
  std::filesystem::create_directories(folder);
  writeTextFile((folder / "results.json").string(), studyJson(result));
  writeTextFile((folder / "results.csv").string(), studyCsv(result));
  writeTextFile((folder / "index.html").string(), studyHtml(result));
}

std::string studyCsv(const StudyResult& result) {
  std::ostringstream o;
  o << "scene,method,variant,ms,fragments_shaded,fragments_per_second,bytes_per_pixel,passes,rmse,psnr,flip,max_error,"
       "non_finite_pixels,threads,runs" << (result.jobs > 0 ? ",job,node" : "") << "\n";
  for (const StudyScene& s : result.scenes)
    for (const StudyRow& r : s.rows)
      o << s.name << "," << r.variant.method << "," << r.variant.label() << "," << jsonNumber(r.ms) << ","
        << r.fragmentsShaded << "," << jsonNumber(r.fragmentsPerSecond) << "," << r.bytesPerPixel << "," << r.passes << ","
        << jsonNumber(r.rmse) << "," << jsonNumber(r.psnr) << "," << jsonNumber(r.flip) << "," << jsonNumber(r.maxError)
        << "," << r.nonFinitePixels << "," << result.threads << "," << result.runs
        << (r.job >= 0 ? "," + std::to_string(r.job) + "," + r.node : std::string()) << "\n";
  return o.str();
}

}  // namespace oitref::tools
