// Position step responses of the rover against the simulated hydrostatic drive (deadband, actuator slew, flow
// lag), through the serial frames: the deadband-aware controller (profile, inverse deadband map, feedforward,
// anti-windup) and the paper's PID (Kp 0.7, Ki 0.04, Kd 5.0 on encoder pulses, eq. 8), on steps of 0.3, 1 and 2 m
// forward and back, on the nominal drive and on a drive whose deadband, slew, lag and pump gains differ from
// what the controller assumes. Writes a PNG of the nominal step responses and ends with
//   RESULT {"overshoot_m": <worst over the new controller's nominal steps>, "settling_s": <worst>, ...}
//   rosrun cotton_harvester rover_step_bench [--png FILE] [--duration S] [--band M]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cotton_harvester/control/step_response.h"

using namespace cotton_harvester::control;

namespace {

struct Run {
  std::string controller;
  double step_m;
  StepResponse response;
};

/// Plots position against time, one panel per controller, every step as a line, its target dashed.
void writePng(const std::string& path, const std::vector<Run>& runs, double duration_s) {
  const int panel_w = 760, panel_h = 420, margin = 60;
  cv::Mat image(panel_h + 2 * margin, 2 * panel_w + 3 * margin, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar colours[] = {{200, 80, 30},  {40, 150, 40},  {30, 30, 200},
                                {160, 60, 160}, {20, 140, 200}, {100, 100, 100}};
  const char* names[] = {"deadband", "paper_pid"};
  for (int p = 0; p < 2; ++p) {
    const cv::Point origin(margin + p * (panel_w + margin), margin);
    const auto to_px = [&](double t, double x) {
      return cv::Point(origin.x + static_cast<int>(t / duration_s * panel_w),
                       origin.y + static_cast<int>((2.4 - x) / 4.8 * panel_h));
    };
    cv::rectangle(image, cv::Rect(origin, cv::Size(panel_w, panel_h)), cv::Scalar(0, 0, 0), 1);
    cv::line(image, to_px(0, 0), to_px(duration_s, 0), cv::Scalar(180, 180, 180), 1);
    for (int s = 0; s <= static_cast<int>(duration_s); s += 10) {
      cv::line(image, to_px(s, -2.4), to_px(s, -2.3), cv::Scalar(0, 0, 0), 1);
      cv::putText(image, std::to_string(s), to_px(s, -2.4) + cv::Point(-8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                  cv::Scalar(0, 0, 0), 1);
    }
    for (double x : {-2.0, -1.0, 1.0, 2.0})
      cv::putText(image, cv::format("%+.0f m", x), to_px(0, x) + cv::Point(-55, 5), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                  cv::Scalar(0, 0, 0), 1);
    cv::putText(image, std::string(names[p]) + ": position [m] against time [s]", origin + cv::Point(10, -15),
                cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1);
    int c = 0;
    for (const Run& run : runs) {
      if (run.controller != names[p]) continue;
      const cv::Scalar colour = colours[c++ % 6];
      for (double t = 0.0; t < duration_s; t += 0.8)
        cv::line(image, to_px(t, run.step_m), to_px(std::min(duration_s, t + 0.4), run.step_m), colour, 1);
      std::vector<cv::Point> line;
      for (size_t i = 0; i < run.response.samples.size(); i += 10)
        line.push_back(to_px(run.response.samples[i].t_s, run.response.samples[i].position_m));
      cv::polylines(image, line, false, colour, 2, cv::LINE_AA);
    }
  }
  cv::imwrite(path, image);
}

}  // namespace

int main(int argc, char** argv) {
  std::string png = "rover_step_response.png";
  double duration_s = 60.0, band_m = 0.05;
  CLI::App app{"rover_step_bench: position step responses of the rover controllers on the simulated drive"};
  app.add_option("--png", png, "where to write the step-response plot ('' for none)");
  app.add_option("--duration", duration_s, "simulated seconds per step")->check(CLI::Range(5.0, 600.0));
  app.add_option("--band", band_m, "settling band [m]")->check(CLI::Range(0.001, 1.0));
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;

  const SimulatedNavigationParams nominal;
  // A drive that is not the one the controller was set up for: wider deadband, slower actuator, longer lag,
  // weaker pump.
  SimulatedNavigationParams other = nominal;
  other.drive.deadband_low_pwm = 78.0;
  other.drive.deadband_high_pwm = 100.0;
  other.drive.actuator_rate_pwm_per_s = 9.0;
  other.drive.flow_time_constant_s = 0.6;
  other.drive.max_forward_speed_mps = 0.42;
  other.drive.max_reverse_speed_mps = 0.42;

  std::printf("rover position step responses, simulated hydrostatic drive, settling band +-%.2f m, %.0f s per step\n",
              band_m, duration_s);
  std::printf("%-10s %-8s %-8s %-12s %-12s %-14s %-10s\n", "control", "drive", "step_m", "overshoot_m", "settling_s",
              "final_err_m", "peak_pwm");
  std::fflush(stdout);
  std::vector<Run> nominal_runs;
  double worst_overshoot = 0.0, worst_settling = 0.0, paper_overshoot_1m = 0.0, paper_settling_1m = -1.0;
  double other_worst_overshoot = 0.0, other_worst_settling = 0.0;
  bool all_settled = true, other_all_settled = true;
  for (const PositionControl control : {PositionControl::kDeadbandAware, PositionControl::kPaperPid}) {
    for (int drive = 0; drive < 2; ++drive) {
      for (double step : {0.3, 1.0, 2.0, -0.3, -1.0, -2.0}) {
        RoverControllerParams params;
        params.position_control = control;
        const StepResponse response = simulateStep(params, drive == 0 ? nominal : other, step, duration_s, band_m);
        double peak_pwm = 90.0;
        for (const auto& s : response.samples)
          if (std::abs(s.pwm - 90.0) > std::abs(peak_pwm - 90.0)) peak_pwm = s.pwm;
        std::printf("%-10s %-8s %-8.2f %-12.3f %-12.2f %-14.4f %-10.1f\n", toString(control).c_str(),
                    drive == 0 ? "nominal" : "other", step, response.overshoot_m, response.settling_s,
                    response.final_error_m, peak_pwm);
        std::fflush(stdout);
        if (drive == 0) nominal_runs.push_back({toString(control), step, response});
        if (control == PositionControl::kDeadbandAware) {
          if (drive == 0) {
            worst_overshoot = std::max(worst_overshoot, response.overshoot_m);
            worst_settling = std::max(worst_settling, response.settling_s);
            all_settled = all_settled && response.settling_s >= 0.0;
          } else {
            other_worst_overshoot = std::max(other_worst_overshoot, response.overshoot_m);
            other_worst_settling = std::max(other_worst_settling, response.settling_s);
            other_all_settled = other_all_settled && response.settling_s >= 0.0;
          }
        } else if (drive == 0 && step == 1.0) {
          paper_overshoot_1m = response.overshoot_m;
          paper_settling_1m = response.settling_s;
        }
      }
    }
  }
  if (!png.empty()) {
    writePng(png, nominal_runs, duration_s);
    std::printf("wrote %s\n", png.c_str());
  }
  std::printf("(settling_s -1: never stayed within the band; paper: about 0.18 m of overshoot on the real rover)\n");
  std::printf(
      "RESULT {\"overshoot_m\": %.3f, \"settling_s\": %.2f, \"all_settled\": %s, \"other_drive_overshoot_m\": %.3f, "
      "\"other_drive_settling_s\": %.2f, \"other_drive_all_settled\": %s, \"paper_pid_overshoot_1m\": %.3f, "
      "\"paper_pid_settling_1m_s\": %.2f}\n",
      worst_overshoot, all_settled ? worst_settling : -1.0, all_settled ? "true" : "false", other_worst_overshoot,
      other_all_settled ? other_worst_settling : -1.0, other_all_settled ? "true" : "false", paper_overshoot_1m,
      paper_settling_1m);
  return 0;
}
