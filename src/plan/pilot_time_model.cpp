#include "plan/pilot_time_model.h"

#include <cstddef>

namespace vktg {

PilotTimeModel fitPilotTimes(const std::vector<double>& seconds, const std::vector<double>& spp) {
  const double count = double(spp.size());
  double meanSpp = 0, meanSeconds = 0;
  for (std::size_t r = 0; r < spp.size(); ++r) meanSpp += spp[r] / count, meanSeconds += seconds[r] / count;
  double covariance = 0, spread = 0;
  for (std::size_t r = 0; r < spp.size(); ++r) {
    covariance += (spp[r] - meanSpp) * (seconds[r] - meanSeconds);
    spread += (spp[r] - meanSpp) * (spp[r] - meanSpp);
  }
  PilotTimeModel model;
  model.perSpp = spread > 0 ? covariance / spread : 0.0;
  model.fixed = meanSeconds - model.perSpp * meanSpp;
  if (model.perSpp < 0) {  // timing noise of a launch-bound render: all of it is fixed cost
    model.perSpp = 0;
    model.fixed = meanSeconds;
  } else if (model.fixed < 0) {  // noise the other way: a line through the origin
    double weighted = 0, squares = 0;
    for (std::size_t r = 0; r < spp.size(); ++r) weighted += spp[r] * seconds[r], squares += spp[r] * spp[r];
    model.fixed = 0;
    model.perSpp = squares > 0 ? weighted / squares : 0.0;
  }
  return model;
}

}  // namespace vktg
