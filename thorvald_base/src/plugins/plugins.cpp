#include <pluginlib/class_list_macros.hpp>

#include "thorvald_base/standard_calculator.h"

PLUGINLIB_EXPORT_CLASS(thorvald_base::StandardCalculator, thorvald_base::BaseCalculator)
PLUGINLIB_EXPORT_CLASS(thorvald_base::DiffDriveCalculator, thorvald_base::BaseCalculator)
PLUGINLIB_EXPORT_CLASS(thorvald_base::OneWheelCalculator, thorvald_base::BaseCalculator)
