// Particle clusters: the modes of a particle belief, as the localize
// interface reports them.
#pragma once

#include <span>
#include <vector>

#include "drivers/common_desktop/particle_filter.h"

namespace troupe::desktop {

/// Groups particles whose histogram bins (bin_xy m, bin_a rad) touch,
/// including across the heading wrap-around, and returns each group's
/// weighted mean (circular for the heading), covariance and total weight,
/// heaviest first, at most `max_clusters`.
std::vector<PoseHypothesis> cluster_particles(std::span<const Particle> particles, double bin_xy,
                                              double bin_a, size_t max_clusters = 16);

}  // namespace troupe::desktop
