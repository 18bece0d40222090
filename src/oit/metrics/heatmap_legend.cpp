#include "metrics/heatmap_legend.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "oitref/oit/metrics.h"

namespace oitref {
namespace {

// 3×5 glyphs, one row per entry, the high bit of three the left column.
struct Glyph {
  char c;
  unsigned char rows[5];
};
constexpr Glyph kFont[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
    {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
    {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
    {'+', {0, 2, 7, 2, 0}}, {'e', {0, 7, 7, 4, 7}}, {' ', {0, 0, 0, 0, 0}}};
constexpr int kScale = 2, kAdvance = 4 * kScale;

const Glyph* glyphOf(char c) {
  for (const Glyph& g : kFont)
    if (g.c == c) return &g;
  return nullptr;
}

int textWidth(const std::string& text) { return int(text.size()) * kAdvance; }

// Draws text with its top-left corner at (left, top), top row 0.
void drawText(Image& image, const std::string& text, int left, int top, const Profile& profile) {
  for (size_t k = 0; k < text.size(); ++k) {
    const Glyph* g = glyphOf(text[k]);
    if (!g) continue;
    for (int row = 0; row < 5 * kScale; ++row)
      for (int col = 0; col < 3 * kScale; ++col) {
        if (!(g->rows[row / kScale] >> (2 - col / kScale) & 1)) continue;
        const int x = left + int(k) * kAdvance + col, yTop = top + row;
        if (x < image.width() && yTop < image.height()) image.store(x, image.height() - 1 - yTop, {1, 1, 1, 1}, profile);
      }
  }
}

}  // namespace

Image withLegend(const Image& map, double scaleMax) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", scaleMax);
  const std::string maxLabel = text;
  constexpr int gap = 4, barHeight = 10, labelGap = 3, margin = 4;
  const int width = std::max(map.width(), textWidth("0") + textWidth(maxLabel) + 3 * kAdvance);
  const int legendHeight = gap + barHeight + labelGap + 5 * kScale + margin;
  const Profile profile = exactProfile();
  Image out(map.format(), width, map.height() + legendHeight);
  out.clear({0, 0, 0, 1}, profile);
  // The map keeps its rows; the legend goes below it (lower window y).
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) out.store(x, y + legendHeight, map.fetch(x, y), profile);
  const int barTop = map.height() + gap;  // counted from the top row
  for (int row = 0; row < barHeight; ++row)
    for (int x = 0; x < width; ++x) {
      glm::vec4 c(0, 0, 0, 1);
      heatmapColour(width > 1 ? double(x) / (width - 1) : 0.0, &c[0]);
      out.store(x, out.height() - 1 - (barTop + row), c, profile);
    }
  const int labelTop = barTop + barHeight + labelGap;
  drawText(out, "0", 0, labelTop, profile);
  drawText(out, maxLabel, width - textWidth(maxLabel) + kScale, labelTop, profile);
  return out;
}

void heatmapColour(double t, float rgb[3]) {
  // Stops of the colour scale at t = 0, 0.2, 0.4, 0.6, 0.8, 1: black, blue, magenta, orange,
  // yellow, white — increasing in lightness, so the order survives a greyscale print.
  static const float stops[6][3] = {{0, 0, 0}, {0.1f, 0.1f, 0.8f}, {0.7f, 0.1f, 0.7f},
                                    {1, 0.5f, 0.1f}, {1, 0.9f, 0.2f}, {1, 1, 1}};
  t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
  const int i = std::min(4, int(t * 5));
  const float f = float(t * 5 - i);
  for (int k = 0; k < 3; ++k) rgb[k] = stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f;
}

Image flipHeatmapWithLegend(const FlipResult& r) {
  Image map(makeFormat(FormatId::RGBA8), r.width, r.height);
  const Profile profile = exactProfile();
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      glm::vec4 c(0, 0, 0, 1);
      heatmapColour(r.at(r.error, x, y), &c[0]);
      map.store(x, y, c, profile);
    }
  return withLegend(map, 1.0);
}

}  // namespace oitref
