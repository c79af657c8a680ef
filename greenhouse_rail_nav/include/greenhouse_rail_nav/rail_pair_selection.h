#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "greenhouse_rail_nav/rail_band.h"
#include "greenhouse_rail_nav/rail_detector_params.h"
#include "greenhouse_rail_nav/rail_pair.h"

namespace greenhouse_rail_nav {

/// The partner of lines[i] among the other lines: parallel to it within parallel_tolerance_rad, at its height within
/// height_tolerance_m, and a gauge (rail_gauge_m) away within gauge_tolerance_m; the nearest to the gauge (the later
/// one of a tie). std::nullopt when there is none.
std::optional<std::size_t> partnerAmongLines(const std::vector<RailLine>& lines, std::size_t i,
                                             const RailDetectorParams& p);

/// The partner of `rail` fitted to the band's points in a strip a gauge away on either side (its cluster may be
/// broken up or merged with leaves): a line through the strip's points, refitted on those within half the gauge
/// tolerance of it and trimmed, that has at least min_cluster_points points and min_line_length_m, fills
/// min_partner_coverage of its 5 cm bins and is parallel to `rail` and at its height (as partnerAmongLines). Of the
/// two sides, the one with more points; std::nullopt when neither has such a line.
std::optional<RailLine> partnerFromBand(const RailLine& rail, const RailBand& band, const RailDetectorParams& p);

/// Variances of base_link in the rail frame [m^2, m^2, rad^2] (x, y, yaw): the configured floors (sigma_*, and a
/// voxel for x) plus what the two rails' fit residuals say; y grows with the lever of the yaw error over
/// |base_in_rail.x|.
std::array<double, 3> railPairVariance(const RailPair& pair, const thorvald_base::Pose2D& base_in_rail,
                                       const RailDetectorParams& p);

/// The rail set the detector reports.
struct RailPairChoice {
  RailPair pair;                     ///< the two rails' axes and the rail frame in base_link
  double fit_score = 0.0;            ///< linearity of the line the pair was found from
  std::array<double, 3> variance{};  ///< railPairVariance
};

/// The rail detector's pair stage: for each line, best first, its partner among the lines or, when
/// search_band_for_partner, in the band's points (partnerAmongLines, partnerFromBand); both moved to their pipe axes
/// (pipeAxisLine; camera_xyz: the camera in base_link [m]) make the rail set, unless its centre line passes further
/// than max_lateral_offset_m from base_link (a neighbouring set). std::nullopt with `why` (when given) set when no
/// line yields a rail set.
std::optional<RailPairChoice> selectRailPair(const std::vector<RailLine>& lines, const RailBand& band,
                                             bool search_band_for_partner, const Eigen::Vector3d& camera_xyz,
                                             const RailDetectorParams& p, std::string* why);

}  // namespace greenhouse_rail_nav
