# The cotton rover harvesting a row in MuJoCo: the simulated rover (thorvald_sim's physics and camera renderer),
# the harvest stack's plant on it, the headless harvest run, harvest_bench and its test. Included by the
# package's CMakeLists.txt after the perception and control libraries.
find_package(thorvald_sim REQUIRED)
find_package(thorvald_base REQUIRED)
find_package(mujoco REQUIRED)
find_package(rosgraph_msgs REQUIRED)
find_path(CLI11_INCLUDE_DIR CLI/CLI.hpp)
if(NOT CLI11_INCLUDE_DIR)
  message(FATAL_ERROR "cotton_harvester needs CLI11 (Debian: libcli11-dev)")
endif()

add_library(cotton_harvester_sim
  src/sim/rover_sim.cpp
  src/sim/sim_harvest_plant.cpp
  src/sim/harvest_run.cpp
  src/sim/miss_causes.cpp
  src/sim/rover_serial_bridge.cpp
  src/sim/rover_device_emulator.cpp
  src/sim/stack_run_report.cpp
  src/sim/harvest_scorer.cpp
)
target_include_directories(cotton_harvester_sim PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include ${thorvald_sim_INCLUDE_DIRS})
target_link_libraries(cotton_harvester_sim cotton_harvester_control cotton_harvester_perception ${thorvald_sim_LIBRARIES}
  mujoco::mujoco ${OpenCV_LIBRARIES})

add_executable(harvest_bench bench/harvest_bench.cpp)
target_include_directories(harvest_bench PRIVATE ${CLI11_INCLUDE_DIR})
target_link_libraries(harvest_bench cotton_harvester_sim)

# The headless harvest as a ROS node (launch/harvest_mujoco.launch): status and metrics topics, ends by itself.
add_executable(mujoco_harvest src/sim/mujoco_harvest_node.cpp)
target_include_directories(mujoco_harvest PRIVATE ${thorvald_base_INCLUDE_DIRS})
target_link_libraries(mujoco_harvest cotton_harvester_sim ${thorvald_base_LIBRARIES} ${catkin_LIBRARIES})
add_dependencies(mujoco_harvest ${catkin_EXPORTED_TARGETS})

# The rover and its row as the harvest stack's nodes see a rover: serial controllers on pseudo-terminals, the camera's
# topics, /clock; and the run's scorer (launch/harvest_mujoco_nodes.launch).
add_executable(mujoco_rover_sim src/sim/mujoco_rover_sim_node.cpp src/sim/rover_camera_messages.cpp)
target_include_directories(mujoco_rover_sim PRIVATE ${thorvald_base_INCLUDE_DIRS} ${rosgraph_msgs_INCLUDE_DIRS})
target_link_libraries(mujoco_rover_sim cotton_harvester_sim ${thorvald_base_LIBRARIES} ${catkin_LIBRARIES})
add_dependencies(mujoco_rover_sim ${PROJECT_NAME}_generate_messages_cpp ${catkin_EXPORTED_TARGETS})

# Waits for the metrics of several rovers in their namespaces (launch/harvest_two_rows.launch) and ends the launch.
add_executable(harvest_fleet_report src/sim/harvest_fleet_report_node.cpp)
target_include_directories(harvest_fleet_report PRIVATE ${thorvald_base_INCLUDE_DIRS})
target_link_libraries(harvest_fleet_report ${thorvald_base_LIBRARIES} ${catkin_LIBRARIES})

install(TARGETS cotton_harvester_sim harvest_bench mujoco_harvest mujoco_rover_sim harvest_fleet_report
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_mujoco_harvest test/sim/test_mujoco_harvest.cpp test/sim/test_rover_serial_bridge.cpp)
  target_link_libraries(test_mujoco_harvest cotton_harvester_sim)
  catkin_add_gtest(test_rover_sim_node_parts test/sim/test_rover_sim_node_parts.cpp)
  target_link_libraries(test_rover_sim_node_parts cotton_harvester_sim gtest_main)
  catkin_add_gtest(test_miss_causes test/sim/test_miss_causes.cpp)
  target_link_libraries(test_miss_causes cotton_harvester_sim)
  add_rostest(test/sim/harvest_mujoco.test DEPENDENCIES mujoco_harvest)
  add_rostest(test/sim/harvest_two_rows.test DEPENDENCIES mujoco_harvest)
  add_rostest(test/sim/harvest_mujoco_nodes.test
    DEPENDENCIES mujoco_rover_sim rover manipulator harvest_perception harvest_state_machine)
endif()
