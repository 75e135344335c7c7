// The run's random numbers: the project's counter-based generator
// (runtime/random.h), one per run, passed in. The engine names its streams
// by (RandomKind, sensor or robot, step) and counts by beam.
#pragma once

#include <cstdint>

#include "runtime/random.h"

namespace troupe::sim {

using troupe::Random;

/// Stream kinds, so two uses of the same owner never share numbers.
enum class RandomKind : uint64_t {
  OdomError = 1,
  RangerNoise = 2,
  RangerAngle = 3,
  RangerGauss = 6,
  Controller = 4,
  Color = 5,
  CameraNoise = 7,
};

}  // namespace troupe::sim
