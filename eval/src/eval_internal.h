// Internals of `probebake eval` shared by its translation units.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "probebake/eval/eval.h"
#include "probebake/eval/reference.h"

namespace probebake::bake::detail {

struct ReferencePoints {
  std::vector<SamplePoint> points;
  ReferenceResult values;
  std::filesystem::path cache_file;
  bool from_cache = false;
  bool cache_written = false;
  int viewpoints = 0; // 0 when read from the cache
};

// Reads the cache beside the scene or computes (and then writes) it.
ReferencePoints cached_reference(const std::filesystem::path& scene_path, const scene::Scene& scene,
                                 const scene::RayScene& rays, const EvalSettings& settings);

// Per-point RGB RMS errors of `estimate` against `reference`, summarised.
struct ErrorStats {
  double rmse = 0.0, p95 = 0.0, max = 0.0, leak_rmse = 0.0;
  double relative_median = 0.0, relative_p95 = 0.0; // of |error| / max(|reference|, 1% of the mean)
  int leak_points = 0;
};
ErrorStats error_stats(const std::vector<glm::vec3>& estimate, const std::vector<glm::vec3>& reference,
                       double mean_reference);

double mean_irradiance(const std::vector<glm::vec3>& values); // over points and channels

// SVG helpers of the plots.
std::string escape_xml(const std::string& s);
double nice_step(double max); // a round step (1, 2 or 5 times a power of ten), about five intervals up to max

// The plots' frame (eval_plot.cpp: error against bake time; eval_plot_ladder.cpp: against probe count): a
// log x axis over whole decades and a linear error axis from 0, in a fixed SVG canvas.
inline constexpr double kPlotWidth = 760, kPlotHeight = 480, kPlotLeft = 70, kPlotRight = 20, kPlotTop = 40,
                        kPlotBottom = 60;
struct PlotAxes {
  double log_lo = -1, log_hi = 1, y_max = 1; // decades of x; the largest error shown
  double x(double value) const;              // values below 1e-6 are drawn at 1e-6
  double y(double error) const;              // errors above y_max are drawn at y_max
};
// The frame, grid lines and tick labels of both axes, and their titles.
std::string plot_axes_svg(const PlotAxes& axes, const char* x_title);
// The ladder's plot: relative RMSE against live probe count (log axis), a curve per placement method.
std::string ladder_svg_plot(const EvalResult& result);

} // namespace probebake::bake::detail
