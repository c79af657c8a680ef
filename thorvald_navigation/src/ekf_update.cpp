#include "thorvald_navigation/ekf_update.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "thorvald_base/pose2d.h"

namespace thorvald_navigation {

namespace {

std::string checkEntries(const std::vector<MeasuredEntry>& z, int n) {
  if (z.empty()) return "no state entry selected";
  for (const MeasuredEntry& e : z) {
    if (e.index < 0 || e.index >= n) return "state index " + std::to_string(e.index) + " out of range";
    if (!std::isfinite(e.value)) return "measurement " + std::to_string(e.index) + " is not finite";
    if (!(e.variance > 0.0) || !std::isfinite(e.variance))
      return "variance " + std::to_string(e.index) + " must be finite and > 0";
  }
  return {};
}

}  // namespace

template <int N>
UpdateResult kalmanUpdate(Eigen::Matrix<double, N, 1>& x, Eigen::Matrix<double, N, N>& p,
                          const std::vector<MeasuredEntry>& z, const std::vector<int>& angles, double gate_sigma) {
  UpdateResult result;
  const int n = static_cast<int>(x.size());
  result.error = checkEntries(z, n);
  if (!result.fused()) return result;
  const int m = static_cast<int>(z.size());
  auto is_angle = [&](int i) { return std::find(angles.begin(), angles.end(), i) != angles.end(); };
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m, n);
  Eigen::VectorXd innovation(m);
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(m, m);
  for (int row = 0; row < m; ++row) {
    const int i = z[row].index;
    h(row, i) = 1.0;
    const double d = z[row].value - x(i);
    innovation(row) = is_angle(i) ? thorvald_base::normalizeAngle(d) : d;
    r(row, row) = z[row].variance;
  }
  const Eigen::MatrixXd s = h * p * h.transpose() + r;
  const Eigen::LDLT<Eigen::MatrixXd> s_ldlt = s.ldlt();
  if (std::isfinite(gate_sigma)) {
    const double d2 = innovation.dot(s_ldlt.solve(innovation));
    result.mahalanobis = std::sqrt(std::max(0.0, d2));
    if (!(d2 < gate_sigma * gate_sigma)) {
      result.gated = true;
      result.error =
          "Mahalanobis distance " + std::to_string(result.mahalanobis) + " sigma >= gate " + std::to_string(gate_sigma);
      return result;
    }
  }
  const Eigen::MatrixXd k = p * h.transpose() * s_ldlt.solve(Eigen::MatrixXd::Identity(m, m));
  x += k * innovation;
  for (int i : angles) x(i) = thorvald_base::normalizeAngle(x(i));
  // Joseph form keeps the covariance symmetric positive semi-definite.
  const Eigen::Matrix<double, N, N> ikh = Eigen::Matrix<double, N, N>::Identity() - k * h;
  p = ikh * p * ikh.transpose() + k * r * k.transpose();
  p = 0.5 * (p + p.transpose());
  return result;
}

template UpdateResult kalmanUpdate<6>(Eigen::Matrix<double, 6, 1>&, Eigen::Matrix<double, 6, 6>&,
                                      const std::vector<MeasuredEntry>&, const std::vector<int>&, double);
template UpdateResult kalmanUpdate<15>(Eigen::Matrix<double, 15, 1>&, Eigen::Matrix<double, 15, 15>&,
                                       const std::vector<MeasuredEntry>&, const std::vector<int>&, double);

}  // namespace thorvald_navigation
