#pragma once
// Why a fitted quantity of the analysis is not reported. Every fractal dimension of
// `ballagg analyze` is the slope of a least-squares line over a window of scales; a slope
// fitted on too few points, or on a window the object does not fill, is a number without a
// meaning that a reader would still quote (a 2D aggregate whose centre of mass lies in a
// hole 22 R wide gives a mass-radius slope of 3). Such a fit is reported as NaN (null in
// JSON, nan in CSV) with the flaw's code beside it; the raw fit, where the files carry
// one, stays for inspection.
#include <cstdint>
#include <string>

namespace ballagg {

// A window needs at least this many points: two points always lie on a line and leave no
// residual from which to estimate the slope's error.
inline constexpr int kMinFitPoints = 3;
// A fractal dimension lies in (0, D]. A slope above D by more than this is the signature of
// a window that starts inside a hole or ends outside the object, not of the object; the
// margin admits the few per cent by which the lattice shells of a compact cluster exceed
// r^D at these short scales (a filled cubic ball gives 2.92 to 3.05 by the mass-radius fits).
inline constexpr double kDimensionExcess = 0.1;

enum class FitFlaw : std::uint8_t {
  none,                     // reported
  cluster_too_small,        // fewer spheres than the estimate needs (kFractalMinSize, kRichardsonMinSize)
  too_few_points,           // fewer than kMinFitPoints points in the fit's window
  hole_at_centre,           // mass-radius window: no centre within its inner radius of the centre of mass
  outside_dimension_range,  // the slope is not in (0, D + kDimensionExcess]
};

// The code written to the files: "ok" or the flaw's name.
constexpr const char* flaw_code(FitFlaw f) {
  switch (f) {
    case FitFlaw::none: return "ok";
    case FitFlaw::cluster_too_small: return "cluster_too_small";
    case FitFlaw::too_few_points: return "too_few_points";
    case FitFlaw::hole_at_centre: return "hole_at_centre";
    case FitFlaw::outside_dimension_range: return "outside_dimension_range";
  }
  return "ok";
}

// One sentence per flaw, for analysis.json's definitions and the docs.
std::string flaw_explanation(FitFlaw f);

// The flaw of a fitted dimension of a D-dimensional object, judged by its value alone.
template <int D>
constexpr FitFlaw dimension_range_flaw(double value) {
  return value > 0.0 && value <= D + kDimensionExcess ? FitFlaw::none : FitFlaw::outside_dimension_range;
}

}  // namespace ballagg
