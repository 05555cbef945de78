// SPDX-License-Identifier: MIT
/// @file plot.h
/// Scatter and line plots written as PNG, for the benchmark programs and the comparison apps:
/// axes (linear or log), ticks with numbers, axis titles, a legend, series as points or lines.
/// Self-contained (a 3x5 pixel font, drawn at 2x), so that a fresh machine needs no plotting
/// package; it draws what a reader needs to see a Pareto front or a convergence curve, no more.
#pragma once

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <cellrelief/core/image.h>
#include <cellrelief/io/image_io.h>

namespace cellrelief::app {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
  Color8 color{31, 119, 180, 255};
  bool lines = false;  ///< join the points in order (a curve), else draw markers
};

struct Plot {
  std::string title, xLabel, yLabel;
  bool logX = false, logY = false;
  int width = 900, height = 600;
  std::vector<PlotSeries> series;

  /// A color from a fixed palette, by series index.
  static Color8 palette(std::size_t i) {
    static constexpr std::array<std::array<std::uint8_t, 3>, 8> kColors = {{
        {31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14},
        {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {127, 127, 127}}};
    const auto& c = kColors[i % kColors.size()];
    return {c[0], c[1], c[2], 255};
  }

  void write(const std::filesystem::path& path) const;
};

namespace detail {

/// 3x5 glyphs, rows top to bottom, 3 bits each (bit 2 = left column). Lower case is drawn as
/// upper case; characters without a glyph are blank.
inline const std::uint16_t* glyph(char c) {
  struct Entry {
    char c;
    std::uint16_t rows[5];
  };
  static constexpr Entry kGlyphs[] = {
      {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
      {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
      {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
      {'+', {0, 2, 7, 2, 0}}, {'%', {5, 1, 2, 4, 5}}, {'/', {1, 1, 2, 4, 4}}, {'(', {1, 2, 2, 2, 1}},
      {')', {4, 2, 2, 2, 4}}, {',', {0, 0, 0, 2, 4}}, {':', {0, 2, 0, 2, 0}}, {'=', {0, 7, 0, 7, 0}},
      {'^', {2, 5, 0, 0, 0}}, {'_', {0, 0, 0, 0, 7}}, {'x', {0, 5, 2, 5, 0}},
      {'A', {2, 5, 7, 5, 5}}, {'B', {6, 5, 6, 5, 6}}, {'C', {3, 4, 4, 4, 3}}, {'D', {6, 5, 5, 5, 6}},
      {'E', {7, 4, 6, 4, 7}}, {'F', {7, 4, 6, 4, 4}}, {'G', {3, 4, 5, 5, 3}}, {'H', {5, 5, 7, 5, 5}},
      {'I', {7, 2, 2, 2, 7}}, {'J', {1, 1, 1, 5, 2}}, {'K', {5, 5, 6, 5, 5}}, {'L', {4, 4, 4, 4, 7}},
      {'M', {5, 7, 7, 5, 5}}, {'N', {6, 5, 5, 5, 5}}, {'O', {2, 5, 5, 5, 2}}, {'P', {6, 5, 6, 4, 4}},
      {'Q', {2, 5, 5, 6, 3}}, {'R', {6, 5, 6, 5, 5}}, {'S', {3, 4, 2, 1, 6}}, {'T', {7, 2, 2, 2, 2}},
      {'U', {5, 5, 5, 5, 7}}, {'V', {5, 5, 5, 5, 2}}, {'W', {5, 5, 7, 7, 5}}, {'X', {5, 5, 2, 5, 5}},
      {'Y', {5, 5, 2, 2, 2}}, {'Z', {7, 1, 2, 4, 7}}};
  const char u = c == 'x' ? c : char(std::toupper(static_cast<unsigned char>(c)));
  for (const Entry& e : kGlyphs)
    if (e.c == u) return e.rows;
  return nullptr;
}

class Canvas {
 public:
  Canvas(int w, int h) : mImage(w, h, 3, 255) {}
  void pixel(int x, int y, Color8 c) {
    if (x < 0 || y < 0 || x >= mImage.width() || y >= mImage.height()) return;
    for (int k = 0; k < 3; ++k) mImage.at(x, y, k) = c[k];
  }
  void rect(int x0, int y0, int x1, int y1, Color8 c) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) pixel(x, y, c);
  }
  void line(double x0, double y0, double x1, double y1, Color8 c, int thickness = 1) {
    const int steps = int(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
    for (int i = 0; i <= steps; ++i) {
      const double s = double(i) / steps;
      const int x = int(std::lround(x0 + s * (x1 - x0))), y = int(std::lround(y0 + s * (y1 - y0)));
      rect(x - thickness / 2, y - thickness / 2, x + (thickness - 1) / 2, y + (thickness - 1) / 2, c);
    }
  }
  /// Text at 2x scale: 8 pixels per character, 10 high. `vertical` draws it rotated upwards.
  void text(int x, int y, const std::string& s, Color8 c = {0, 0, 0, 255}, bool vertical = false) {
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::uint16_t* g = glyph(s[i]);
      if (!g) continue;
      for (int row = 0; row < 5; ++row)
        for (int col = 0; col < 3; ++col)
          if (g[row] & (4 >> col))
            for (int d = 0; d < 4; ++d) {
              const int gx = int(i) * 8 + col * 2 + (d & 1), gy = row * 2 + (d >> 1);
              if (vertical)
                pixel(x + gy, y - gx, c);
              else
                pixel(x + gx, y + gy, c);
            }
    }
  }
  static int textWidth(const std::string& s) { return int(s.size()) * 8; }
  const Image<std::uint8_t>& image() const { return mImage; }

 private:
  Image<std::uint8_t> mImage;
};

inline std::string tickLabel(double v) {
  char buffer[32];
  const double a = std::abs(v);
  if (v == 0)
    return "0";
  else if (a >= 1e4 || a < 1e-3)
    std::snprintf(buffer, sizeof buffer, "%.0e", v);
  else
    std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

/// Nice tick positions covering [lo, hi]: 1-2-5 steps (linear) or powers of ten (log).
inline std::vector<double> ticks(double lo, double hi, bool log) {
  std::vector<double> t;
  if (log) {
    for (double e = std::floor(std::log10(lo)); e <= std::ceil(std::log10(hi)); ++e) {
      const double v = std::pow(10.0, e);
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t.push_back(v);
    }
    if (t.size() < 2)
      for (double m : {2.0, 5.0})
        for (double e = std::floor(std::log10(lo)); e <= std::ceil(std::log10(hi)); ++e) {
          const double v = m * std::pow(10.0, e);
          if (v >= lo && v <= hi) t.push_back(v);
        }
    std::sort(t.begin(), t.end());
    return t;
  }
  const double raw = (hi - lo) / 6;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step)
    t.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
  return t;
}

}  // namespace detail

inline void Plot::write(const std::filesystem::path& path) const {
  detail::Canvas canvas(width, height);
  const int left = 90, right = width - 30, top = 50, bottom = height - 60;
  // Data range, padded; log axes keep positive values only.
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const PlotSeries& s : series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if ((logX && s.x[i] <= 0) || (logY && s.y[i] <= 0)) continue;
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
    }
  if (!(x0 <= x1)) x0 = logX ? 1 : 0, x1 = logX ? 10 : 1;
  if (!(y0 <= y1)) y0 = logY ? 1 : 0, y1 = logY ? 10 : 1;
  auto pad = [](double& lo, double& hi, bool log) {
    if (log) {
      lo /= 1.25, hi *= 1.25;
      if (hi / lo < 10) lo /= 2, hi *= 2;
    } else {
      const double span = hi > lo ? hi - lo : std::max(std::abs(hi), 1.0);
      lo -= 0.05 * span, hi += 0.05 * span;
    }
  };
  pad(x0, x1, logX);
  pad(y0, y1, logY);
  auto mapX = [&](double v) {
    const double s = logX ? std::log(v / x0) / std::log(x1 / x0) : (v - x0) / (x1 - x0);
    return left + s * (right - left);
  };
  auto mapY = [&](double v) {
    const double s = logY ? std::log(v / y0) / std::log(y1 / y0) : (v - y0) / (y1 - y0);
    return bottom - s * (bottom - top);
  };
  const Color8 grid{225, 225, 225, 255}, axis{0, 0, 0, 255};
  for (double t : detail::ticks(x0, x1, logX)) {
    const double px = mapX(t);
    canvas.line(px, top, px, bottom, grid);
    const std::string label = detail::tickLabel(t);
    canvas.text(int(px) - detail::Canvas::textWidth(label) / 2, bottom + 8, label);
  }
  for (double t : detail::ticks(y0, y1, logY)) {
    const double py = mapY(t);
    canvas.line(left, py, right, py, grid);
    const std::string label = detail::tickLabel(t);
    canvas.text(left - 8 - detail::Canvas::textWidth(label), int(py) - 5, label);
  }
  canvas.line(left, bottom, right, bottom, axis);
  canvas.line(left, top, left, bottom, axis);
  canvas.text((left + right - detail::Canvas::textWidth(title)) / 2, 15, title);
  canvas.text((left + right - detail::Canvas::textWidth(xLabel)) / 2, height - 25, xLabel);
  canvas.text(12, (top + bottom + detail::Canvas::textWidth(yLabel)) / 2, yLabel, axis, true);
  for (const PlotSeries& s : series) {
    double px = NAN, py = NAN;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (logX && s.x[i] <= 0) ||
          (logY && s.y[i] <= 0))
        continue;
      const double qx = mapX(s.x[i]), qy = mapY(s.y[i]);
      if (s.lines && std::isfinite(px)) canvas.line(px, py, qx, qy, s.color, 2);
      if (!s.lines) canvas.rect(int(qx) - 3, int(qy) - 3, int(qx) + 3, int(qy) + 3, s.color);
      px = qx, py = qy;
    }
  }
  // Legend, top right.
  int ly = top + 8;
  for (const PlotSeries& s : series) {
    const int lx = right - 20 - detail::Canvas::textWidth(s.name) - 24;
    canvas.rect(lx, ly + 1, lx + 14, ly + 8, s.color);
    canvas.text(lx + 22, ly, s.name);
    ly += 16;
  }
  io::writePng(canvas.image(), path);
}

}  // namespace cellrelief::app
