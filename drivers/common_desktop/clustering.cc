#include "drivers/common_desktop/clustering.h"

#include <algorithm>
#include <unordered_map>

#include "drivers/common_desktop/pose_bins.h"

namespace troupe::desktop {

std::vector<PoseHypothesis> cluster_particles(std::span<const Particle> particles, double bin_xy,
                                              double bin_a, size_t max_clusters) {
  PoseBins bins(bin_xy, bin_a);
  // Bin of each particle, and the occupied bins.
  std::unordered_map<uint64_t, int> cluster_of;  // bin key -> cluster id (-1: not yet labelled)
  std::vector<PoseBins::Index> index(particles.size());
  for (size_t i = 0; i < particles.size(); ++i) {
    index[i] = bins.index(particles[i].pose);
    cluster_of.emplace(bins.key(index[i]), -1);
  }
  // Label connected bins (26-neighbourhood) by flood fill.
  int clusters = 0;
  std::vector<PoseBins::Index> stack;
  for (size_t i = 0; i < particles.size(); ++i) {
    if (cluster_of[bins.key(index[i])] >= 0) continue;
    int id = clusters++;
    cluster_of[bins.key(index[i])] = id;
    stack.assign(1, index[i]);
    while (!stack.empty()) {
      PoseBins::Index b = stack.back();
      stack.pop_back();
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int da = -1; da <= 1; ++da) {
            PoseBins::Index n{b.ix + dx, b.iy + dy, b.ia + da};
            auto it = cluster_of.find(bins.key(n));
            if (it != cluster_of.end() && it->second < 0) {
              it->second = id;
              stack.push_back(
                  {n.ix, n.iy, ((n.ia % bins.heading_bins()) + bins.heading_bins()) % bins.heading_bins()});
            }
          }
        }
      }
    }
  }
  // First moments, with the heading as a weighted unit vector.
  struct Sum {
    double w = 0, x = 0, y = 0, c = 0, s = 0;
  };
  std::vector<Sum> sums(static_cast<size_t>(clusters));
  std::vector<int> label(particles.size());
  for (size_t i = 0; i < particles.size(); ++i) {
    label[i] = cluster_of[bins.key(index[i])];
    const Particle& p = particles[i];
    Sum& s = sums[size_t(label[i])];
    s.w += p.weight;
    s.x += p.weight * p.pose.x;
    s.y += p.weight * p.pose.y;
    s.c += p.weight * std::cos(p.pose.a);
    s.s += p.weight * std::sin(p.pose.a);
  }
  double total = 0;
  for (const Sum& s : sums) total += s.w;
  std::vector<PoseHypothesis> out(static_cast<size_t>(clusters));
  for (size_t k = 0; k < out.size(); ++k) {
    const Sum& s = sums[k];
    double w = s.w > 0 ? s.w : 1;
    out[k].mean = {s.x / w, s.y / w, std::atan2(s.s, s.c)};
    out[k].weight = total > 0 ? s.w / total : 0;
    out[k].cov.setZero();
  }
  // Second moments about each mean, heading deviations wrapped.
  for (size_t i = 0; i < particles.size(); ++i) {
    PoseHypothesis& h = out[size_t(label[i])];
    const Particle& p = particles[i];
    Eigen::Vector3d d(p.pose.x - h.mean.x, p.pose.y - h.mean.y, wrap_angle(p.pose.a - h.mean.a));
    h.cov += p.weight * d * d.transpose();
  }
  for (size_t k = 0; k < out.size(); ++k) {
    if (sums[k].w > 0) out[k].cov /= sums[k].w;
  }
  std::sort(out.begin(), out.end(),
            [](const PoseHypothesis& a, const PoseHypothesis& b) { return a.weight > b.weight; });
  if (out.size() > max_clusters) out.resize(max_clusters);
  return out;
}

void ParticleFilter::cluster() {
  hypotheses_ = cluster_particles(particles_, params_.bin_xy, params_.bin_a);
}

}  // namespace troupe::desktop
