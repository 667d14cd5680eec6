// Power-law fit and break-even count; see economics.h.
#include "economics.h"

#include <cmath>

namespace study {

double PowerFit::secondsFor(double error) const { return std::exp((std::log(error) - a) / b); }

std::optional<PowerFit> fitPowerLaw(const std::vector<CurvePoint>& pts) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const CurvePoint& p : pts) {
    if (!(p.seconds > 0 && p.error > 0 && std::isfinite(p.seconds) && std::isfinite(p.error))) continue;
    double x = std::log(p.seconds), y = std::log(p.error);
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  double den = n * sxx - sx * sx;
  if (n < 2 || !(std::abs(den) > 1e-12)) return std::nullopt;
  PowerFit f;
  f.b = (n * sxy - sx * sy) / den;
  f.a = (sy - f.b * sx) / n;
  // A tracer whose error does not fall with time cannot be read at another error.
  if (!(f.b < 0)) return std::nullopt;
  return f;
}

Economics economics(const PowerFit& tracer, double error, double solveSeconds, double renderSeconds, int views) {
  Economics e;
  e.tracerSecondsPerImage = tracer.secondsFor(error);
  double gain = e.tracerSecondsPerImage - renderSeconds;  // saved per view once the solve is paid
  if (gain > 0) e.breakEvenViews = std::max(1.0, std::ceil(solveSeconds / gain));
  e.ratioAtViews = (solveSeconds + views * renderSeconds) / (views * e.tracerSecondsPerImage);
  return e;
}

}  // namespace study
