#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace thorvald_navigation {

/// One entry of a measurement: the state index it observes, its value and variance.
struct MeasuredEntry {
  int index = 0;
  double value = 0.0;
  double variance = 1.0;  ///< [unit^2], finite and > 0
};

/// What a Kalman update did: fused, or rejected with the reason (and the gate's distance when the gate refused it).
struct UpdateResult {
  std::string error;                                              ///< empty when fused
  double mahalanobis = std::numeric_limits<double>::quiet_NaN();  ///< [sigma] of the innovation, when computed
  bool gated = false;                                             ///< rejected by the Mahalanobis gate
  bool fused() const { return error.empty(); }
};

/// The Kalman update both of the workspace's filters share (PlanarEkf, FusionEkf): a direct observation of the
/// selected state entries, innovations of the entries in `angles` taken modulo 2 pi, Joseph-form covariance.
/// `gate_sigma` is a Mahalanobis gate in standard deviations as robot_localization's *_rejection_threshold: the
/// measurement is refused when d^2 >= gate_sigma^2 (infinity: no gate). Non-finite values, variances <= 0 and
/// out-of-range indices are refused with the reason; a refused measurement leaves `x` and `p` untouched.
/// Instantiated for the 6-entry planar state and the 15-entry state (fixed sizes, so both filters keep their
/// own arithmetic).
template <int N>
UpdateResult kalmanUpdate(Eigen::Matrix<double, N, 1>& x, Eigen::Matrix<double, N, N>& p,
                          const std::vector<MeasuredEntry>& z, const std::vector<int>& angles,
                          double gate_sigma = std::numeric_limits<double>::infinity());

}  // namespace thorvald_navigation
