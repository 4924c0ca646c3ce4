# Swerve drive part of mybot_control (included at the end of CMakeLists.txt).
# Pure library: kinematics, odometry, module servo loops (no ROS types).
add_library(mybot_swerve_lib
  src/lib/swerve_kinematics.cpp
  src/lib/swerve_odometry.cpp
  src/lib/swerve_module.cpp
  src/lib/swerve_limiter.cpp)
target_link_libraries(mybot_swerve_lib mybot_control_lib)

# ROS-side helpers of the swerve nodes (geometry from parameters / URDF).
add_library(mybot_swerve_ros src/ros/swerve_ros.cpp)
target_link_libraries(mybot_swerve_ros mybot_swerve_lib mybot_control_ros ${catkin_LIBRARIES})

foreach(node swerve_controller swerve_module swerve_odom)
  add_executable(${node} src/nodes/${node}_node.cpp)
  target_link_libraries(${node} mybot_swerve_ros mybot_swerve_lib mybot_control_ros mybot_control_lib ${catkin_LIBRARIES})
  add_dependencies(${node} ${PROJECT_NAME}_generate_messages_cpp)
  install(TARGETS ${node} RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endforeach()
# The node objects without main(), for the nodelets and swerve_chain (all three in one process).
add_library(mybot_swerve_nodes src/nodes/swerve_controller_node.cpp src/nodes/swerve_module_node.cpp src/nodes/swerve_odom_node.cpp)
target_compile_definitions(mybot_swerve_nodes PRIVATE MYBOT_CONTROL_NODE_LIBRARY)
target_link_libraries(mybot_swerve_nodes mybot_swerve_ros mybot_swerve_lib mybot_control_ros mybot_control_lib ${catkin_LIBRARIES})
add_dependencies(mybot_swerve_nodes ${PROJECT_NAME}_generate_messages_cpp)
add_library(mybot_swerve_nodelets src/nodes/swerve_nodelets.cpp)
target_link_libraries(mybot_swerve_nodelets mybot_swerve_nodes ${catkin_LIBRARIES})
add_executable(swerve_chain src/nodes/swerve_chain_node.cpp)
target_link_libraries(swerve_chain mybot_swerve_nodes ${catkin_LIBRARIES})
install(TARGETS swerve_chain RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(TARGETS mybot_swerve_lib mybot_swerve_ros mybot_swerve_nodes mybot_swerve_nodelets
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # One test file per type, as wpimath does.
  catkin_add_gtest(test_swerve_lib test/swerve/test_swerve_kinematics.cpp test/swerve/test_swerve_odometry.cpp
    test/swerve/test_swerve_module.cpp test/swerve/test_swerve_limiter.cpp)
  target_link_libraries(test_swerve_lib mybot_swerve_lib gtest_main)

  find_package(rostest REQUIRED)
  set(MYBOT_SWERVE_ROSTESTS swerve_bad_config swerve_sim_motion swerve_sim_modules swerve_sim_pose
      swerve_sim_pose_nodes swerve_sim_pose_nodelets swerve_sim_odometry)
  foreach(t ${MYBOT_SWERVE_ROSTESTS})
    add_rostest(test/swerve/${t}.test DEPENDENCIES swerve_controller swerve_module swerve_odom swerve_chain mybot_swerve_nodelets)
  endforeach()
endif()
