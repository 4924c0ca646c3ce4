# AMCL localization and goal navigation (issue 8). Included from CMakeLists.txt after catkin_package().
# Components are looked up one by one so the package's catkin_* variables stay untouched.
find_package(actionlib REQUIRED)
find_package(actionlib_msgs REQUIRED)
find_package(move_base_msgs REQUIRED)
find_package(visualization_msgs REQUIRED)

set(MYBOT_NAV_ROS_INCLUDES ${actionlib_INCLUDE_DIRS} ${actionlib_msgs_INCLUDE_DIRS} ${move_base_msgs_INCLUDE_DIRS}
  ${visualization_msgs_INCLUDE_DIRS})

# Pure libraries: no ROS types.
add_library(mybot_localization_lib
  src/costmap_distance.cpp
  src/amcl_models.cpp
  src/amcl_filter.cpp
  src/amcl.cpp)
target_include_directories(mybot_localization_lib PUBLIC include ${catkin_INCLUDE_DIRS})
target_link_libraries(mybot_localization_lib mybot_navigation)

add_library(mybot_nav_lib
  src/costmap.cpp
  src/planner.cpp
  src/local_planner.cpp
  src/navigation.cpp)
target_include_directories(mybot_nav_lib PUBLIC include ${catkin_INCLUDE_DIRS})
target_link_libraries(mybot_nav_lib mybot_localization_lib)

# Thin nodes with amcl's and move_base's names.
add_executable(amcl_node src/amcl_node.cpp)
set_target_properties(amcl_node PROPERTIES OUTPUT_NAME amcl)
target_include_directories(amcl_node PRIVATE include ${catkin_INCLUDE_DIRS})
target_link_libraries(amcl_node mybot_localization_lib ${catkin_LIBRARIES})

add_executable(move_base_node src/navigation_node.cpp)
set_target_properties(move_base_node PROPERTIES OUTPUT_NAME move_base)
target_include_directories(move_base_node PRIVATE include ${catkin_INCLUDE_DIRS} ${MYBOT_NAV_ROS_INCLUDES})
target_link_libraries(move_base_node mybot_nav_lib ${catkin_LIBRARIES} ${actionlib_LIBRARIES})
add_dependencies(move_base_node ${catkin_EXPORTED_TARGETS})

install(TARGETS mybot_localization_lib mybot_nav_lib amcl_node move_base_node
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_amcl
    test/amcl/test_amcl_models.cpp
    test/amcl/test_amcl_filter.cpp
    test/gtest_main.cpp)
  target_link_libraries(test_amcl mybot_localization_lib)
  catkin_add_gtest(test_nav
    test/nav/test_costmap_planner.cpp
    test/nav/test_local_planner.cpp
    test/gtest_main.cpp)
  target_link_libraries(test_nav mybot_nav_lib)
  # Simulator in the loop (mybot_gazebo_lite at 5x real time), judged on ground truth.
  find_package(rostest REQUIRED)
  add_rostest(test/nav/nav_mybot.test)
  add_rostest(test/nav/nav_errors.test)
  add_rostest(test/nav/nav_reset.test)
  add_rostest(test/nav/amcl_global.test)
  add_rostest(test/nav/amcl_kidnap.test)
  # nav_factory.test runs in scripts/soak (20 goals): the navigation stack is outside lockstep, and
  # with 6 goals it failed 2 of 14 runs on 2026-11-26 ("failed to find a valid control" near the start).
  add_rostest(test/nav/nav_swerve.test)
  add_rostest(test/nav/nav_factory_swerve.test)
endif()

# Benchmark (bench/bench_nav at the workspace root runs it).
add_executable(bench_nav_lib bench/bench_nav.cpp)
target_link_libraries(bench_nav_lib mybot_nav_lib)
