#include "physics/air_density.h"

#include "physics/constants.h"

namespace nph::physics {

double dryAirDensity(double p, double t, double r_v) { return p / (kGasConstantDryAir * t * (1.0 + r_v / kEpsilon)); }

double moistAirDensity(double p, double t, double q_v, double q_c) {
  const double density_temperature = t * (1.0 + (1.0 / kEpsilon - 1.0) * q_v - q_c);
  return p / (kGasConstantDryAir * density_temperature);
}

}  // namespace nph::physics
