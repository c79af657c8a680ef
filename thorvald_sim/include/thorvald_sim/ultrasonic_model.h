#pragma once

// The `datasheet` echo model of an ultrasonic range finder: the nearest echo in the beam cone, lost on surfaces met
// too obliquely (the sound reflects away; a farther surface in the cone may answer instead), and optional
// cross-talk between two sensors firing together. ROS-free.

#include <random>
#include <vector>

namespace thorvald_sim {

struct UltrasonicModel {
  double max_incidence_rad = 0.35;      ///< no echo from a surface met more obliquely than this [rad]
  double cross_talk_probability = 0.0;  ///< chance per reading that a neighbour's echo is heard (crossTalk)
};

/// One ray of the cone: its true range (negative for nothing) and the angle between it and the surface normal.
struct EchoRay {
  double range_m = -1.0;
  double incidence_rad = 0.0;
};

/// The nearest range among the rays whose surface echoes back (incidence within the limit); +inf for none.
double nearestEcho(const std::vector<EchoRay>& rays, const UltrasonicModel& model);

/// Cross-talk: a sensor that hears a neighbour's ping after it travelled `other_path_m` (neighbour -> surface ->
/// this sensor) reads half that path as a range. With `probability`, the reading is the nearer of its own range and
/// that; otherwise its own.
double crossTalk(double own_m, double other_path_m, double probability, std::mt19937& rng);

}  // namespace thorvald_sim
