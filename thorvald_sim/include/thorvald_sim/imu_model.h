#pragma once

// The `datasheet` error model of a MEMS IMU (UM7 on the greenhouse robot, PhidgetSpatial Precision 3/3/3 1044 on
// the cotton rover): white noise, a bias instability (first-order Gauss-Markov), a bias random walk and a
// scale-factor error, per axis. ROS-free and deterministic given the random engine.

#include <Eigen/Core>
#include <random>

namespace thorvald_sim {

/// The errors of one triad (gyroscope [rad/s] or accelerometer [m/s^2]); figures and sources in the README.
struct ImuTriadModel {
  double white_sigma = 0.0;         ///< std dev of each sample [unit]
  double bias_instability = 0.0;    ///< steady std dev of the Gauss-Markov bias [unit]
  double bias_correlation_s = 1e3;  ///< its correlation time [s]
  double bias_random_walk = 0.0;    ///< bias random walk [unit / sqrt(s)]
  double scale_factor_sigma = 0.0;  ///< std dev of the per-axis scale-factor error, drawn once [fraction]
};

struct ImuModel {
  ImuTriadModel gyro, accel;
};

/// The UM7 of the greenhouse robot (every figure uncertain: README).
ImuModel um7ImuModel();
/// The PhidgetSpatial Precision 3/3/3 (1044) of the cotton rover, from its product page's figures (README).
ImuModel phidget1044ImuModel();

/// The drifting state of one IMU's errors: the scale factors and the Gauss-Markov biases drawn at construction (the
/// bias at switch-on, from its steady distribution), then carried from one reading to the next. Not thread-safe
/// (one per sensor).
class ImuErrors {
 public:
  ImuErrors(const ImuModel& model, std::mt19937& rng);

  /// The readings at time `t_s` [s] (non-decreasing) with the errors applied in place: scale, bias, white noise.
  void apply(double t_s, Eigen::Vector3d* gyro_radps, Eigen::Vector3d* accel_mps2, std::mt19937& rng);

  /// The biases now (Gauss-Markov plus random walk) [rad/s], [m/s^2].
  Eigen::Vector3d gyroBias() const { return gyro_.bias(); }
  Eigen::Vector3d accelBias() const { return accel_.bias(); }

 private:
  class Triad {
   public:
    Triad(const ImuTriadModel& m, std::mt19937& rng);
    /// Moves the bias on by dt [s], then returns the reading of `truth`.
    Eigen::Vector3d read(const Eigen::Vector3d& truth, double dt, std::mt19937& rng);
    Eigen::Vector3d bias() const { return markov_ + walk_; }

   private:
    ImuTriadModel m_;
    Eigen::Vector3d scale_, markov_, walk_;
  };

  Triad gyro_, accel_;
  double last_t_ = 0.0;
  bool started_ = false;
};

}  // namespace thorvald_sim
