#pragma once

#include <string>

#include "cotton_harvester/perception/network_boll_detector.h"
#include "cotton_harvester/testing/detection_scoring.h"

namespace cotton_harvester {
namespace perception {

/// perception_bench's figures of the trained boll network: whether its weights detect (the shipped frames of
/// test/perception/data/boll_net), and on held-out datasheet frames (boll_dataset_export --full) its precision and
/// recall next to the colour detector's, a boll counting as found when located within max_error_m in 3D.
struct NetworkFigures {
  int trained = 0;  ///< 1: the network finds >= half of the shipped frames' bolls at precision >= 0.5
  int trained_found = 0, trained_labels = 0, trained_false = 0;
  int heldout_frames = 0;                      ///< 0: no held-out folder given
  ScoreSummary network, colour;                ///< all held-out frames
  ScoreSummary network_centre, colour_centre;  ///< the same, LocatedBoll::centre within the limit of the centre
  ScoreSummary network_day[2], colour_day[2];  ///< [0] overcast, [1] sunny
  ScoreSummary fig8[3];                        ///< the network with linear, nearest and no interpolation of the input
  bool fig8_run = false;
};

/// Fills trained*: the network on the frames (PNG + YOLO labels) of `frames_dir`, IoU >= 0.4.
void checkTrained(const NetworkParams& params, const std::string& frames_dir, NetworkFigures* figures);

/// Scores the colour and network pipelines (default parameters but the detector) on every frame of `dir`; with
/// fig8 also the network with each input resize. top_fraction: the bolls' visible top in radii in front of their
/// centre, in the truth and the pipelines (PerceptionParams::boll_top_fraction). Returns an empty string or what went
/// wrong.
std::string scoreHeldout(const std::string& dir, const NetworkParams& params, bool fig8, double max_error_m,
                         double top_fraction, NetworkFigures* figures);

/// The tables of the figures.
void printNetworkFigures(const NetworkFigures& figures, double max_error_m);

}  // namespace perception
}  // namespace cotton_harvester
