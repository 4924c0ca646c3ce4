# C++ part of mybot_control (included from CMakeLists.txt).
include_directories(include ${catkin_INCLUDE_DIRS} ${EIGEN3_INCLUDE_DIRS})

# Pure library: no ROS types in its interface (kinematics, odometry, limiter, PID, mux).
add_library(mybot_control_lib
  src/lib/kinematics.cpp
  src/lib/odometry.cpp
  src/lib/four_wheel_steering.cpp
  src/lib/speed_limiter.cpp
  src/lib/pid.cpp
  src/lib/twist_mux.cpp
  src/lib/step_scheduler.cpp)

# ROS-side helpers of the nodes: validated parameters, PID/limit blocks, URDF geometry.
add_library(mybot_control_ros src/ros/ros_params.cpp src/ros/odometry_publisher.cpp)
target_link_libraries(mybot_control_ros mybot_control_lib ${catkin_LIBRARIES})
add_dependencies(mybot_control_ros ${PROJECT_NAME}_generate_messages_cpp)

foreach(node diffdrive_controller wheel_controller diffdrive_odom twist_mux)
  add_executable(${node} src/nodes/${node}_node.cpp)
  target_link_libraries(${node} mybot_control_ros mybot_control_lib ${catkin_LIBRARIES})
  add_dependencies(${node} ${PROJECT_NAME}_generate_messages_cpp)
  install(TARGETS ${node} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()
# The node objects without main(), for the nodelets and diffdrive_chain (all in one process).
add_library(mybot_diffdrive_nodes src/nodes/twist_mux_node.cpp src/nodes/diffdrive_controller_node.cpp
  src/nodes/wheel_controller_node.cpp src/nodes/diffdrive_odom_node.cpp)
target_compile_definitions(mybot_diffdrive_nodes PRIVATE MYBOT_CONTROL_NODE_LIBRARY)
target_link_libraries(mybot_diffdrive_nodes mybot_control_ros mybot_control_lib ${catkin_LIBRARIES})
add_dependencies(mybot_diffdrive_nodes ${PROJECT_NAME}_generate_messages_cpp)
add_library(mybot_diffdrive_nodelets src/nodes/diffdrive_nodelets.cpp)
target_link_libraries(mybot_diffdrive_nodelets mybot_diffdrive_nodes ${catkin_LIBRARIES})
add_executable(diffdrive_chain src/nodes/diffdrive_chain_node.cpp)
target_link_libraries(diffdrive_chain mybot_diffdrive_nodes ${catkin_LIBRARIES})
install(TARGETS diffdrive_chain RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(TARGETS mybot_control_lib mybot_control_ros mybot_diffdrive_nodes mybot_diffdrive_nodelets
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})
install(DIRECTORY include/mybot_control/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION}
  FILES_MATCHING PATTERN "*.hpp")

# Benchmark helper (bench/bench_control drives it).
add_executable(bench_control_lib test/bench/bench_control_lib.cpp)
target_link_libraries(bench_control_lib mybot_control_lib)

if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  catkin_add_gtest(test_control_lib
    test/gtest/test_kinematics.cpp
    test/gtest/test_odometry.cpp
    test/gtest/test_ackermann_odometry.cpp
    test/gtest/test_four_wheel_steering.cpp
    test/gtest/test_speed_limiter.cpp
    test/gtest/test_pid.cpp
    test/gtest/test_twist_mux.cpp
    test/gtest/test_step_scheduler.cpp
    test/gtest/main.cpp)
  target_link_libraries(test_control_lib mybot_control_lib)

  # Test fixture: integrates *_angular_vel_motor into stamped joint_states (and /clock).
  add_executable(loopback_wheels test/fixtures/loopback_wheels.cpp)
  target_link_libraries(loopback_wheels ${catkin_LIBRARIES})

  # rostests (test/rostest/*.py drive the nodes against the loopback or the simulator).
  set(MYBOT_CONTROL_ROSTESTS diffdrive_chain diffdrive_limits diffdrive_frames bad_config twist_mux)
  foreach(t ${MYBOT_CONTROL_ROSTESTS})
    add_rostest(test/rostest/${t}.test DEPENDENCIES loopback_wheels diffdrive_controller wheel_controller
      diffdrive_odom twist_mux diffdrive_chain mybot_diffdrive_nodelets)
  endforeach()
  # The same loopback suite with the three nodes loaded as nodelets into one manager.
  add_rostest(test/rostest/diffdrive_chain.test ARGS process:=nodelets DEPENDENCIES loopback_wheels
    mybot_diffdrive_nodelets)
  # In the simulator (mybot, joint-command mode) against ground truth.
  # square runs the four nodes in one process (diffdrive_chain), the others as separate nodes.
  foreach(args "mode:=square\;process:=chain" "mode:=reset\;process:=chain" "mode:=step" "mode:=weak\;pid_on:=true" "mode:=weak\;pid_on:=false")
    add_rostest(test/rostest/sim_chain.test ARGS ${args} DEPENDENCIES diffdrive_controller wheel_controller
      diffdrive_odom twist_mux diffdrive_chain mybot_diffdrive_nodelets)
  endforeach()
endif()
