// The walkthrough economics: when does one finite-element solve plus N cheap renders beat N path-
// traced images of the same error? The path tracer's error falls as a power of its time (about
// t^-1/2), so its curve measured at a few sample counts is fitted on log-log axes and read at the
// error a solve reached.
#pragma once
#include <optional>
#include <vector>

namespace study {

struct CurvePoint {
  double seconds = 0, error = 0;  // time for one image, its relative RMSE against the reference
};

/// Least squares on log error = a + b log seconds. Needs two points with different times and
/// positive errors; nullopt otherwise.
struct PowerFit {
  double a = 0, b = 0;
  double secondsFor(double error) const;  // time the fitted tracer needs to reach `error`
};
std::optional<PowerFit> fitPowerLaw(const std::vector<CurvePoint>& pts);

struct Economics {
  double tracerSecondsPerImage = 0;  // at the solve's error
  std::optional<double> breakEvenViews;  // smallest N for which solve + N renders <= N traced images; none if never
  double ratioAtViews = 0;               // (solve + N render) / (N traced images) at the N asked for
};
Economics economics(const PowerFit& tracer, double error, double solveSeconds, double renderSeconds, int views);

}  // namespace study
