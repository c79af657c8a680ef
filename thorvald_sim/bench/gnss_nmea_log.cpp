// gnss_nmea_log: the RTK-GNSS receiver model (gnss_model.h) on a straight drive, written as the NMEA log the receiver
// would send (GGA, RMC, GST at its rate). The log replays into gpsd through thorvald_gnss's nmea_tcp_feeder:
//   rosrun thorvald_sim gnss_nmea_log --duration 60 --outage 20 24 > drive.nmea
//   rosrun thorvald_gnss nmea_tcp_feeder _file:=drive.nmea & gpsd -N -n tcp://127.0.0.1:10110
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "thorvald_common/command_line.h"
#include "thorvald_sim/gnss_model.h"
#include "thorvald_sim/nmea_sentences.h"

int main(int argc, char** argv) {
  thorvald_sim::GnssModelParams params;
  double duration_s = 30.0;
  double speed_mps = 1.0;
  double heading_deg = 90.0;
  std::vector<double> outages;
  std::vector<double> datum{params.datum_latitude_deg, params.datum_longitude_deg, params.datum_altitude_m};
  CLI::App app{"NMEA log of the RTK-GNSS receiver model on a straight drive from the datum (stdout)", "gnss_nmea_log"};
  app.add_option("--duration", duration_s, "model time [s]")->check(CLI::Range(0.0, 86400.0));
  app.add_option("--speed", speed_mps, "ground speed [m/s]")->check(CLI::Range(0.0, 50.0));
  app.add_option("--heading", heading_deg, "course, clockwise from north [deg]")->check(CLI::Range(0.0, 360.0));
  app.add_option("--seed", params.seed, "random seed");
  app.add_option("--rate", params.rate_hz, "solution rate [Hz]")->check(CLI::Range(0.1, 100.0));
  app.add_option("--outage", outages, "start and end of an outage [s], repeatable: --outage 20 24")
      ->expected(2)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_option("--datum", datum, "latitude [deg], longitude [deg], ellipsoidal height [m]")->expected(3);
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  for (size_t i = 0; i + 1 < outages.size(); i += 2) params.outages.push_back({outages[i], outages[i + 1]});
  params.datum_latitude_deg = datum[0];
  params.datum_longitude_deg = datum[1];
  params.datum_altitude_m = datum[2];
  try {
    thorvald_sim::GnssModel model(params);
    const double heading_rad = heading_deg * 3.14159265358979323846 / 180.0;
    const Eigen::Vector3d velocity(speed_mps * std::sin(heading_rad), speed_mps * std::cos(heading_rad), 0.0);
    const long epochs = static_cast<long>(duration_s * params.rate_hz);
    for (long k = 0; k <= epochs; ++k) {
      const double t = static_cast<double>(k) / params.rate_hz;
      const auto solution = model.update(t, velocity * t);
      if (!solution) continue;
      for (const std::string& sentence : thorvald_sim::epochSentences(*solution)) std::fputs(sentence.c_str(), stdout);
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "gnss_nmea_log: " << e.what() << std::endl;
    return thorvald_common::kUsageErrorExitCode;
  }
  return 0;
}
