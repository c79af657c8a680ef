#pragma once

// A recorded NMEA log cut into the receiver's epochs, for replay at the receiver's rate. ROS-free.

#include <istream>
#include <string>
#include <vector>

namespace thorvald_gnss {

/// The sentences of one epoch, each with its CR LF.
struct NmeaEpoch {
  std::string time;  ///< the UTC field ("hhmmss.ss") the epoch's sentences share
  std::string text;  ///< the sentences, concatenated
};

/// Reads an NMEA log: lines starting with '$' are sentences (a missing CR is added), empty lines and lines
/// starting with '#' are skipped, anything else is counted in `rejected`. A new epoch starts where the time field of
/// a GGA, RMC or GST sentence differs from the current epoch's. At most `max_lines` lines are read.
std::vector<NmeaEpoch> readNmeaEpochs(std::istream& in, size_t* rejected = nullptr, size_t max_lines = 1000000);

}  // namespace thorvald_gnss
