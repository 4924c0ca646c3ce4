# rospy tools of mybot_control (included from CMakeLists.txt): scripts/, the
# mybot_control Python module (catkin_python_setup in CMakeLists.txt), their tests.
file(GLOB MYBOT_CONTROL_PY_SCRIPTS ${PROJECT_SOURCE_DIR}/scripts/*)
if(MYBOT_CONTROL_PY_SCRIPTS)
  catkin_install_python(PROGRAMS ${MYBOT_CONTROL_PY_SCRIPTS}
    DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
endif()

if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  # catkin 0.8 has no pytest macro; this registers the suite with `catkin test`.
  catkin_run_tests_target("pytest" "control_tools" "pytest-control_tools.xml"
    COMMAND "/usr/bin/python3 -m pytest -q -p no:cacheprovider ${PROJECT_SOURCE_DIR}/test/python --junitxml=${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/pytest-control_tools.xml"
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  file(GLOB MYBOT_CONTROL_TOOL_TESTS RELATIVE ${PROJECT_SOURCE_DIR} ${PROJECT_SOURCE_DIR}/test/tools/*.test)
  foreach(t ${MYBOT_CONTROL_TOOL_TESTS})
    add_rostest(${t})
  endforeach()
  add_rostest(test/rostest/twin.test)
endif()
