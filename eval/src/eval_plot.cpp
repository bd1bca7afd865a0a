// `probebake eval --plot`: relative RMSE against bake time (log axis) as a self-contained SVG, the Pareto
// front of the probe configurations (nothing both faster and more accurate) drawn as a staircase.
#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "eval_internal.h"
#include "probebake/eval/eval.h"

namespace probebake::bake {

std::string detail::escape_xml(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

double detail::nice_step(double max) {
  const double raw = max / 5.0, power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * power >= raw) return m * power;
  return 10.0 * power;
}

double detail::PlotAxes::x(double value) const {
  const double l = std::log10(std::max(value, 1e-6));
  return kPlotLeft + (l - log_lo) / (log_hi - log_lo) * (kPlotWidth - kPlotLeft - kPlotRight);
}

double detail::PlotAxes::y(double error) const {
  return kPlotHeight - kPlotBottom - std::min(error, y_max) / y_max * (kPlotHeight - kPlotTop - kPlotBottom);
}

std::string detail::plot_axes_svg(const PlotAxes& a, const char* x_title) {
  std::string s;
  const double x0 = kPlotLeft, x1 = kPlotWidth - kPlotRight, y0 = kPlotHeight - kPlotBottom, y1 = kPlotTop;
  s +=
      fmt::format("<rect x='{}' y='{}' width='{}' height='{}' fill='none' stroke='#444'/>\n", x0, y1, x1 - x0, y0 - y1);
  for (int d = int(a.log_lo); d <= int(a.log_hi); ++d)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, d);
      if (std::log10(v) > a.log_hi + 1e-9) continue;
      const double x = a.x(v);
      s += fmt::format("<line x1='{:.1f}' y1='{}' x2='{:.1f}' y2='{}' stroke='#ddd'/>\n", x, y0, x, y1);
      s += fmt::format("<text x='{:.1f}' y='{}' font-size='11' text-anchor='middle'>{:g}</text>\n", x, y0 + 16, v);
    }
  const double step = nice_step(a.y_max);
  for (double v = 0; v <= a.y_max + step * 1e-6; v += step) {
    s += fmt::format("<line x1='{}' y1='{:.1f}' x2='{}' y2='{:.1f}' stroke='#ddd'/>\n", x0, a.y(v), x1, a.y(v));
    s += fmt::format("<text x='{}' y='{:.1f}' font-size='11' text-anchor='end'>{:g}</text>\n", x0 - 6, a.y(v) + 4, v);
  }
  s += fmt::format("<text x='{}' y='{}' font-size='13' text-anchor='middle'>{}</text>\n", (x0 + x1) / 2,
                   kPlotHeight - 18, x_title);
  s += fmt::format("<text x='16' y='{}' font-size='13' text-anchor='middle' transform='rotate(-90 16 {})'>"
                   "relative RMSE of irradiance</text>\n",
                   (y0 + y1) / 2, (y0 + y1) / 2);
  return s;
}

namespace {

using detail::escape_xml;
using detail::nice_step;

using detail::plot_axes_svg;
using Axes = detail::PlotAxes;
constexpr double kWidth = detail::kPlotWidth, kHeight = detail::kPlotHeight, kRight = detail::kPlotRight,
                 kTop = detail::kPlotTop;

Axes make_axes(const std::vector<EvalRow>& rows) {
  Axes a;
  double lo = 1e300, hi = 0, err = 0;
  for (const EvalRow& r : rows) {
    lo = std::min(lo, std::max(r.bake_seconds, 1e-6));
    hi = std::max(hi, std::max(r.bake_seconds, 1e-6));
    err = std::max(err, r.relative_rmse);
  }
  if (rows.empty()) return a;
  a.log_lo = std::floor(std::log10(lo));
  a.log_hi = std::max(std::ceil(std::log10(hi)), a.log_lo + 1);
  const double step = nice_step(err > 0 ? err * 1.05 : 1.0);
  a.y_max = std::ceil(err * 1.05 / step) * step;
  if (!(a.y_max > 0)) a.y_max = 1;
  return a;
}

// Indices of the "svo" rows on the Pareto front, by increasing bake time.
std::vector<std::size_t> pareto_front(const std::vector<EvalRow>& rows) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].sampler == "svo") order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return rows[a].bake_seconds != rows[b].bake_seconds ? rows[a].bake_seconds < rows[b].bake_seconds
                                                        : rows[a].relative_rmse < rows[b].relative_rmse;
  });
  std::vector<std::size_t> front;
  double best = INFINITY;
  for (std::size_t i : order)
    if (rows[i].relative_rmse < best) {
      best = rows[i].relative_rmse;
      front.push_back(i);
    }
  return front;
}

std::string front_svg(const Axes& a, const std::vector<EvalRow>& rows, const std::vector<std::size_t>& front) {
  if (front.empty()) return {};
  std::string path =
      fmt::format("M {:.1f} {:.1f}", a.x(rows[front[0]].bake_seconds), a.y(rows[front[0]].relative_rmse));
  for (std::size_t k = 1; k < front.size(); ++k) // staircase: the front is flat until the next better point
    path += fmt::format(" H {:.1f} V {:.1f}", a.x(rows[front[k]].bake_seconds), a.y(rows[front[k]].relative_rmse));
  return fmt::format("<path d='{}' fill='none' stroke='#d62728' stroke-width='1.5' stroke-dasharray='5 3'/>\n", path);
}

std::string points_svg(const Axes& a, const std::vector<EvalRow>& rows, const std::vector<std::size_t>& front) {
  std::string s;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const EvalRow& r = rows[i];
    const double x = a.x(r.bake_seconds), y = a.y(r.relative_rmse);
    const bool on_front = std::find(front.begin(), front.end(), i) != front.end();
    const std::string label = escape_xml(r.sampler == "svo" ? r.label : r.label + " (" + r.sampler + ")");
    if (r.sampler != "svo")
      s += fmt::format(
          "<rect x='{:.1f}' y='{:.1f}' width='9' height='9' fill='none' stroke='#2ca02c' stroke-width='2'/>\n", x - 4.5,
          y - 4.5);
    else
      s += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='{}' fill='{}'/>\n", x, y, on_front ? 5 : 4,
                       on_front ? "#d62728" : "#1f77b4");
    s += fmt::format("<text x='{:.1f}' y='{:.1f}' font-size='10' fill='#333'>{}</text>\n", x + 7, y - 5, label);
  }
  return s;
}

std::string legend_svg() {
  const double x = kWidth - kRight - 190, y = kTop + 12;
  return fmt::format(
      "<circle cx='{0}' cy='{1}' r='5' fill='#d62728'/><text x='{2}' y='{3}' font-size='11'>Pareto front</text>\n"
      "<circle cx='{0}' cy='{4}' r='4' fill='#1f77b4'/><text x='{2}' y='{5}' font-size='11'>dominated</text>\n"
      "<rect x='{6}' y='{7}' width='9' height='9' fill='none' stroke='#2ca02c' stroke-width='2'/>"
      "<text x='{2}' y='{8}' font-size='11'>all-probes baseline</text>\n",
      x, y, x + 10, y + 4, y + 16, y + 20, x - 4.5, y + 27.5, y + 36);
}

} // namespace

std::string eval_svg_plot(const EvalResult& result) {
  if (std::any_of(result.rows.begin(), result.rows.end(), [](const EvalRow& r) { return r.asked_probes > 0; }))
    return detail::ladder_svg_plot(result);
  const Axes axes = make_axes(result.rows);
  const std::vector<std::size_t> front = pareto_front(result.rows);
  std::string svg =
      fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{0}' height='{1}' viewBox='0 0 {0} {1}' "
                  "font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n",
                  kWidth, kHeight);
  svg += fmt::format("<text x='{}' y='22' font-size='14' text-anchor='middle'>{}: error against bake time ({} points, "
                     "{} paths/point)</text>\n",
                     kWidth / 2, escape_xml(result.scene.filename().string()), result.points, result.paths);
  svg += plot_axes_svg(axes, "bake time (s, log scale)") + front_svg(axes, result.rows, front) +
         points_svg(axes, result.rows, front) + legend_svg();
  return svg + "</svg>\n";
}

} // namespace probebake::bake
