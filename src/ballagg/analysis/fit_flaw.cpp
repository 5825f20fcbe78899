#include "ballagg/analysis/fit_flaw.hpp"

#include <fmt/format.h>

#include "ballagg/analysis/mass_radius.hpp"

namespace ballagg {

std::string flaw_explanation(FitFlaw f) {
  switch (f) {
    case FitFlaw::none: return "the fit is reported";
    case FitFlaw::cluster_too_small: return "the cluster has fewer spheres than the estimate needs";
    case FitFlaw::too_few_points:
      return fmt::format("fewer than {} points in the fit's window: no slope error can be estimated", kMinFitPoints);
    case FitFlaw::hole_at_centre:
      return fmt::format("no sphere centre within the window's inner radius ({} R) of the centre of mass: the fit "
                         "measures the edge of a hole, not the aggregate",
                         kMassRadiusInner);
    case FitFlaw::outside_dimension_range:
      return fmt::format("the slope is outside (0, D + {}]: not a dimension of the object", kDimensionExcess);
  }
  return {};
}

}  // namespace ballagg
