# Test and bench fixtures of the navigation packages (synthetic worlds and a scripted drive with a
# simulated laser: data without the simulator). Sources, in the devel space only: they are never
# installed. A package compiles them into a static library for its tests or benches with
#   mybot_nav_common_add_fixtures(<pkg>_fixtures [more sources...])
@[if DEVELSPACE]@
set(mybot_nav_common_FIXTURES_DIR "@(CMAKE_CURRENT_SOURCE_DIR)/test/fixtures")
set(mybot_nav_common_FIXTURE_SOURCES "${mybot_nav_common_FIXTURES_DIR}/synthetic_world.cpp")

function(mybot_nav_common_add_fixtures target)
  add_library(${target} STATIC ${mybot_nav_common_FIXTURE_SOURCES} ${ARGN})
  target_include_directories(${target} PUBLIC ${mybot_nav_common_FIXTURES_DIR})
  target_link_libraries(${target} ${mybot_nav_common_LIBRARIES})
endfunction()
@[end if]@
