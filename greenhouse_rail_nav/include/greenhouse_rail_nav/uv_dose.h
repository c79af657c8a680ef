#pragma once

#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace greenhouse_rail_nav {

/// The lamps as the dose sees them: a stretch of row lit evenly while they are on.
struct UvDoseParams {
  double lamp_power_w = 60.0;          ///< UV-C power the lamps put on the row (both sides together) [W]
  double lamp_length_m = 0.75;         ///< length of row under the lamps at once [m]
  double lamp_offset_m = -0.325;       ///< the lit stretch's centre along base_link's x (behind the axle < 0) [m]
  double target_dose_j_per_m = 100.0;  ///< the set dose: a metre of row with at least this much is covered [J/m]
  double bin_m = 0.05;                 ///< resolution along the row [m]
  /// Empty when usable, else the bad parameter and what it must be.
  std::string validate() const;
};

/// The UV dose along one rail set's row [J per metre of row]: the lamps' power spread evenly over the lit stretch, for
/// the time each piece of row spends under it with the lamps on. A robot driving at a constant speed v with the lamps
/// on gives every metre lamp_power / v (the stretch passes over it in lamp_length / v). Positions are of base_link
/// along the rails from where it came onto them [m]; the row runs from 0 to `row_length_m`.
class RowDose {
 public:
  RowDose(const UvDoseParams& params, double row_length_m);
  /// base_link moved from `from_m` to `to_m` along the rails in `dt_s` seconds [m, s] with the lamps `on` (the
  /// motion taken as uniform; a stop is from == to).
  void add(double from_m, double to_m, double dt_s, bool on);
  /// Dose per bin [J/m], bin i covering [i, i + 1) * bin_m of the row.
  const std::vector<double>& dose() const { return dose_; }
  double rowLength() const { return row_length_m_; }
  const UvDoseParams& params() const { return params_; }
  /// Share of the row's length with at least the target dose, in [0, 1].
  double coverage() const;
  double minDose() const;
  double meanDose() const;
  /// The stretches of row below the target dose, [from, to] [m], merged.
  std::vector<std::pair<double, double>> uncovered() const;

 private:
  /// Spreads `energy_j` over the lit stretch centred at `centre_m`.
  void deposit(double centre_m, double energy_j);

  UvDoseParams params_;
  double row_length_m_;
  std::vector<double> dose_;
};

/// Splits a mission's motion into rail sets and records it for the dose: a set begins where the robot comes onto the
/// rails; an entry within `same_set_m` of an earlier one is that set again (a treatment resumed or redone), any other a
/// new set, numbered in the order met. Along the rails the position is the odometry's displacement from the entry
/// point projected on the heading at the entry [m]; off the rails nothing is recorded.
class UvDoseRecorder {
 public:
  /// `row_length_m` > 0: every set's row is that long; 0: as far as base_link went along it.
  UvDoseRecorder(const UvDoseParams& params, double row_length_m, double same_set_m = 0.5);
  /// One odometry sample at `t_s` [s]: base_link's position [m] and heading [rad] in the odometry frame, whether it is
  /// on the rails, and whether the lamps are on (taken as held until the next sample).
  void update(double t_s, double x, double y, double yaw, bool on_rails, bool lamps_on);
  std::size_t sets() const { return sets_.size(); }
  /// The set the robot is on now (-1: on the floor).
  int currentSet() const { return on_rails_ ? current_ : -1; }
  /// The dose along set `i`'s row from all its passes.
  RowDose dose(std::size_t i) const;

 private:
  struct Motion {
    double from_m, to_m, dt_s;
    bool on;
  };
  struct SetTrack {
    double entry_x, entry_y, entry_yaw, farthest_m = 0.0;
    std::vector<Motion> motions;
  };
  UvDoseParams params_;
  double row_length_m_, same_set_m_;
  std::vector<SetTrack> sets_;
  int current_ = -1;
  bool on_rails_ = false, have_last_ = false, last_lamps_ = false;
  double last_t_ = 0.0, last_s_ = 0.0;
};

/// A strip image of the row's dose, one column per bin (at least `width_px` wide, bins stretched), `height_px` high:
/// below the target red to yellow by dose / target, at or over it green; a white line every metre along the bottom.
cv::Mat doseStrip(const RowDose& row, int width_px = 800, int height_px = 40);

/// One rail set's dose in the report.
struct SetDoseReport {
  int set_index = 0;
  std::string png_file;  ///< the strip written for it (empty: none)
  const RowDose* row = nullptr;
};
/// The report as YAML text: per set its index, row length, target, min and mean dose, coverage [%] and the uncovered
/// stretches, with the lamp parameters.
std::string doseReportYaml(const std::vector<SetDoseReport>& sets);

}  // namespace greenhouse_rail_nav
