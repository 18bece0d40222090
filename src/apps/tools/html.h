// Small pieces shared by the HTML reports (study_report.cpp, stress_report.cpp).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include "oitref/oit/metrics.h"

namespace oitref::tools::html {

// printf-style formatting of one number.
inline std::string fmt(const char* pattern, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, v);
  return buffer;
}

// Text for HTML content and attribute values.
inline std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

// The heatmaps' colour at t ∈ [0, 1] as CSS, from the function that paints the PNG heatmaps.
inline std::string heatmapCss(double t) {
  float rgb[3];
  heatmapColour(t, rgb);
  return "rgb(" + std::to_string(int(std::lround(rgb[0] * 255))) + "," + std::to_string(int(std::lround(rgb[1] * 255))) +
         "," + std::to_string(int(std::lround(rgb[2] * 255))) + ")";
}

// The whole colour scale as a CSS linear gradient, left to right.
inline std::string heatmapGradientCss() {
  std::string stops;
  for (int i = 0; i <= 10; ++i) stops += "," + heatmapCss(i / 10.0) + " " + std::to_string(i * 10) + "%";
  return "linear-gradient(to right" + stops + ")";
}

}  // namespace oitref::tools::html
