# Control part of cotton_harvester: harvest state machine, manipulator and rover controllers, the
# simulated controllers on pseudo-terminals. Included by the package's CMakeLists.txt after
# catkin_package() and message generation.
find_package(nav_msgs REQUIRED)
find_package(diagnostic_msgs REQUIRED)
find_package(Threads REQUIRED)

set(CONTROL_ROS_INCLUDES ${CMAKE_CURRENT_SOURCE_DIR}/include ${catkin_INCLUDE_DIRS} ${nav_msgs_INCLUDE_DIRS}
    ${diagnostic_msgs_INCLUDE_DIRS})

# ---- ROS-free library: plain structs in and out, serial ports and pseudo-terminals through POSIX (util) --------
add_library(cotton_harvester_control
  src/control/swashplate_mapping.cpp
  src/control/position_pid.cpp
  src/control/deadband_position_controller.cpp
  src/control/articulation_controller.cpp
  src/control/manipulator_calibration.cpp
  src/control/manipulator_protocol.cpp
  src/control/navigation_protocol.cpp
  src/control/serial_port.cpp
  src/control/hydrostatic_drive_model.cpp
  src/control/stepper_axis_model.cpp
  src/control/simulated_controllers.cpp
  src/control/rover_controller.cpp
  src/control/harvest_decision.cpp
  src/control/boll_tracker.cpp
  src/control/harvest_metrics.cpp
  src/control/pick_capture.cpp
  src/control/leaf_clearance.cpp
  src/control/canopy_search.cpp
  src/control/harvest_actions.cpp
  src/control/harvest_machine.cpp
  src/control/step_response.cpp
  src/control/virtual_row.cpp
  src/control/waypoint_path.cpp
  src/control/pure_pursuit.cpp
  src/control/row_turn_planner.cpp
)
# thorvald_state_machine's ROS-free library alone: thorvald_state_machine_LIBRARIES also carries its ROS adapter and
# roscpp.
set(thorvald_state_machine_core ${thorvald_state_machine_LIBRARIES})
list(FILTER thorvald_state_machine_core INCLUDE REGEX "(^|/)(lib)?thorvald_state_machine(\\.so.*|\\.a)?$")
target_include_directories(cotton_harvester_control PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
  ${thorvald_state_machine_INCLUDE_DIRS})
target_link_libraries(cotton_harvester_control ${thorvald_state_machine_core} util Threads::Threads)

# ---- ROS adapter: the harvest machine's plant on topics; the nodes' parameter loaders are headers in src/ros/ ----
add_library(cotton_harvester_ros src/ros/topic_harvest_plant.cpp)
target_include_directories(cotton_harvester_ros PUBLIC ${CONTROL_ROS_INCLUDES})
target_link_libraries(cotton_harvester_ros cotton_harvester_control ${catkin_LIBRARIES})
add_dependencies(cotton_harvester_ros ${${PROJECT_NAME}_EXPORTED_TARGETS} ${catkin_EXPORTED_TARGETS})

# ---- Benchmark ----------------------------------------------------------------------------------------------
add_executable(rover_step_bench bench/rover_step_bench.cpp)
target_link_libraries(rover_step_bench cotton_harvester_control ${OpenCV_LIBRARIES})

install(TARGETS cotton_harvester_control cotton_harvester_ros rover_step_bench
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

# ---- Tests --------------------------------------------------------------------------------------------------
if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  catkin_add_gtest(test_control_unit
    test/control/test_main.cpp
    test/control/test_swashplate_mapping.cpp
    test/control/test_position_pid.cpp
    test/control/test_deadband_position_controller.cpp
    test/control/test_manipulator.cpp
    test/control/test_protocols.cpp
    test/control/test_rover_controller.cpp
    test/control/test_serial_path.cpp
    test/control/test_harvest_decision.cpp
    test/control/test_harvest_actions.cpp
    test/control/test_harvest_machine.cpp
    test/control/test_harvest_metrics.cpp
    test/control/test_pick_capture.cpp
    test/control/test_leaf_clearance.cpp
    test/control/test_canopy_search.cpp
  )
  target_link_libraries(test_control_unit cotton_harvester_control)
endif()

# ---- Nodes --------------------------------------------------------------------------------------------------
add_executable(simulated_controller src/nodes/simulated_controller_node.cpp)
add_executable(manipulator src/nodes/manipulator_node.cpp)
add_executable(rover src/nodes/rover_node.cpp)
add_executable(harvest_state_machine src/nodes/harvest_state_machine_node.cpp)
foreach(node simulated_controller manipulator rover harvest_state_machine)
  target_link_libraries(${node} cotton_harvester_ros cotton_harvester_control ${catkin_LIBRARIES})
  add_dependencies(${node} ${${PROJECT_NAME}_EXPORTED_TARGETS} ${catkin_EXPORTED_TARGETS})
endforeach()
install(TARGETS simulated_controller manipulator rover harvest_state_machine
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

# ---- Node tests (rostest; the python test scripts use rospy) ------------------------------------------------
if(CATKIN_ENABLE_TESTING)
  add_rostest(test/control/control_serial.test DEPENDENCIES simulated_controller rover manipulator)
  add_rostest(test/control/harvest_sim.test
    DEPENDENCIES simulated_controller rover manipulator harvest_state_machine)
  add_rostest_gtest(test_topic_harvest_plant test/control/topic_harvest_plant.test
    test/control/test_topic_harvest_plant.cpp)
  target_link_libraries(test_topic_harvest_plant cotton_harvester_ros cotton_harvester_control ${catkin_LIBRARIES})
  add_dependencies(test_topic_harvest_plant ${${PROJECT_NAME}_EXPORTED_TARGETS} ${catkin_EXPORTED_TARGETS})
endif()

# ---- Row following: pure pursuit and the headland turn on the rover's models (gtest) --------------------------
if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_row_following test/control/test_main.cpp test/control/test_row_following.cpp
    test/control/test_row_turn_planner.cpp)
  target_link_libraries(test_row_following cotton_harvester_control)
endif()
