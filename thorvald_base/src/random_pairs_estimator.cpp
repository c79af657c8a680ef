#include <cmath>

#include "thorvald_base/velocity_estimator.h"

namespace thorvald_base {
namespace {
constexpr double kParallelSin = 1e-3;  // normals closer to parallel than this do not intersect usefully
constexpr double kFarCentre_m = 1e4;   // a centre of rotation this far away is straight driving
}  // namespace

RandomPairsEstimator::RandomPairsEstimator(unsigned seed, int pairs) : state_(seed ? seed : 1u), pairs_(pairs) {}

unsigned RandomPairsEstimator::next() {
  // xorshift32: small, seeded, the same sequence on every machine.
  state_ ^= state_ << 13;
  state_ ^= state_ >> 17;
  state_ ^= state_ << 5;
  return state_;
}

VelocityEstimate RandomPairsEstimator::estimate(const std::vector<WheelObservation>& wheels) {
  VelocityEstimate out;
  const size_t n = wheels.size();
  if (n == 0) return out;
  // Centre of rotation: mean intersection of the wheels' normal lines over random pairs.
  double cx = 0.0, cy = 0.0;
  int hits = 0;
  if (n >= 2) {
    for (int k = 0; k < pairs_; ++k) {
      const size_t i = next() % n;
      size_t j = next() % (n - 1);
      if (j >= i) ++j;
      const auto& p = wheels[i];
      const auto& q = wheels[j];
      // Normal line of wheel p: p + t * (-sin, cos). Solve p + t*np = q + u*nq.
      const double npx = -std::sin(p.heading_rad), npy = std::cos(p.heading_rad);
      const double nqx = -std::sin(q.heading_rad), nqy = std::cos(q.heading_rad);
      const double det = npx * (-nqy) - npy * (-nqx);
      if (std::fabs(det) < kParallelSin) continue;
      const double dx = q.x - p.x, dy = q.y - p.y;
      const double t = (dx * (-nqy) - dy * (-nqx)) / det;
      cx += p.x + t * npx;
      cy += p.y + t * npy;
      ++hits;
    }
  }
  double sum_sd = 0.0, sum_dd = 0.0;
  if (hits > 0) {
    cx /= hits;
    cy /= hits;
  }
  if (hits > 0 && std::hypot(cx, cy) < kFarCentre_m) {
    // Rotation about (cx, cy): each wheel's speed is w times its lever arm along its heading.
    for (const auto& w : wheels) {
      if (!w.has_speed) continue;
      const double d = (w.x - cx) * std::sin(w.heading_rad) - (w.y - cy) * std::cos(w.heading_rad);
      sum_sd += w.speed_mps * d;
      sum_dd += d * d;
    }
  }
  if (sum_dd > 1e-9) {
    const double wz = sum_sd / sum_dd;
    out.twist = {wz * cy, -wz * cx, wz};
  } else {
    // Straight driving (or every wheel at the centre): the mean wheel velocity.
    double vx = 0.0, vy = 0.0;
    int m = 0;
    for (const auto& w : wheels) {
      if (!w.has_speed) continue;
      vx += w.speed_mps * std::cos(w.heading_rad);
      vy += w.speed_mps * std::sin(w.heading_rad);
      ++m;
    }
    if (m == 0) return out;
    out.twist = {vx / m, vy / m, 0.0};
  }
  out.covariance = Eigen::Matrix3d::Identity() * 1e-3;
  out.valid = out.twist.finite();
  return out;
}

std::unique_ptr<VelocityEstimator> makeVelocityEstimator(const std::string& name, unsigned seed) {
  if (name == "least_squares") return std::make_unique<LeastSquaresEstimator>();
  if (name == "random_pairs") return std::make_unique<RandomPairsEstimator>(seed);
  return nullptr;
}

}  // namespace thorvald_base
