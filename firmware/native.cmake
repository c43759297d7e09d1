# firmware/native.cmake - the firmware's logic on the host, on a virtual clock, and its tests.
#
# The firmware sources (all of src/ but the AVR HAL and main.cpp) with the SITL HAL and
# machine (sitl/) as one library compiled gnu++11 as on the Nano, the tests' harness
# (test/harness.cpp, which PlatformIO compiles with every test folder too), and one
# GoogleTest program per test folder
# (test/test_<unit>/test_<unit>.cpp), for each of two arms on the one firmware: the MK2 a
# blank EEPROM gets, under the prefix "firmware.", and a test robot with half steps, a
# reversed motor, the identity coupling and a home pose away from step 0, under
# "firmware.halfstep.": its configuration (made by `articula configure --header`) is what
# the harness puts in the SITL EEPROM of a fresh machine.
set(fw_src_dir ${ARTICULA_FIRMWARE_DIR}/src)
set(fw_test_dir ${ARTICULA_FIRMWARE_DIR}/test)
set(fw_sitl_dir ${ARTICULA_FIRMWARE_DIR}/sitl)
file(GLOB fw_sources CONFIGURE_DEPENDS ${fw_src_dir}/*.cpp)
list(FILTER fw_sources EXCLUDE REGEX "/(hal_avr|main)\\.cpp$")
file(GLOB fw_test_folders LIST_DIRECTORIES true CONFIGURE_DEPENDS ${fw_test_dir}/test_*)

# robot: its file ("" for the built-in MK2); motors: the build's motor count (robot::kJoints:
# 3 as on the Nano; more for the host, the same source); tests: the test folders to build ("":
# all).
function(articula_firmware_variant variant robot prefix motors tests)
  set(robot_file ${robot})
  set(config_defs "")
  if(robot)
    set(gen ${CMAKE_CURRENT_BINARY_DIR}/${variant})
    add_custom_command(OUTPUT ${gen}/test_config.h
      COMMAND ${CMAKE_COMMAND} -E make_directory ${gen}
      COMMAND $<TARGET_FILE:articula> configure ${robot} --header > ${gen}/test_config.h
      DEPENDS articula ${robot}
      COMMENT "The ${variant} test arm's configuration image"
      VERBATIM)
    add_custom_target(firmware_config_${variant} DEPENDS ${gen}/test_config.h)
    set(config_defs ARTICULA_TEST_CONFIG="${gen}/test_config.h")
  else()
    set(robot_file ${PROJECT_SOURCE_DIR}/robots/mk2plus.json)
  endif()

  # The firmware on its virtual clock (firmware/sitl/): src/'s controller compiled for the
  # host, unchanged, with the SITL HAL and the machine that runs its main loop and interrupts.
  # One library: the HAL and the firmware call each other.
  add_library(firmware_sitl_${variant} STATIC ${fw_sources} ${fw_sitl_dir}/hal_sitl.cpp ${fw_sitl_dir}/machine.cpp)
  target_include_directories(firmware_sitl_${variant} PUBLIC ${fw_src_dir} ${fw_sitl_dir})
  target_link_libraries(firmware_sitl_${variant} PUBLIC articula::core)
  target_compile_definitions(firmware_sitl_${variant} PUBLIC ARTICULA_FIRMWARE_MOTORS=${motors})
  target_compile_options(firmware_sitl_${variant} PRIVATE ${ARTICULA_WARNINGS})
  set_target_properties(firmware_sitl_${variant} PROPERTIES CXX_STANDARD 11 CXX_EXTENSIONS ON)

  # The tests' harness: the variant's arm at boot, the checks that need GoogleTest.
  add_library(firmware_harness_${variant} OBJECT ${fw_test_dir}/harness.cpp)
  target_include_directories(firmware_harness_${variant} PUBLIC ${fw_test_dir})
  target_link_libraries(firmware_harness_${variant} PUBLIC firmware_sitl_${variant} GTest::gtest)
  target_compile_options(firmware_harness_${variant} PRIVATE ${ARTICULA_WARNINGS} ${ARTICULA_TEST_FLAGS})
  target_compile_definitions(firmware_harness_${variant} PRIVATE ${config_defs})
  if(robot)
    add_dependencies(firmware_harness_${variant} firmware_config_${variant})
  endif()

  foreach(folder ${fw_test_folders})
    get_filename_component(name ${folder} NAME)
    if(tests AND NOT name IN_LIST tests)
      continue()
    endif()
    set(exe firmware_${variant}_${name})
    add_executable(${exe} ${folder}/${name}.cpp)
    target_link_libraries(${exe} PRIVATE firmware_harness_${variant} GTest::gtest_main)
    if(name STREQUAL "test_robot" OR name STREQUAL "test_prediction")  # the host's loader, its prediction
      target_link_libraries(${exe} PRIVATE articula_host)
    endif()
    target_compile_options(${exe} PRIVATE ${ARTICULA_WARNINGS} ${ARTICULA_TEST_FLAGS})
    target_compile_definitions(${exe} PRIVATE ARTICULA_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                                              ARTICULA_ROBOT_FILE="${robot_file}")
    gtest_discover_tests(${exe} TEST_PREFIX "${prefix}" DISCOVERY_TIMEOUT 60)
  endforeach()
endfunction()

articula_firmware_variant(main "" "firmware." 3 "")
articula_firmware_variant(halfstep ${fw_test_dir}/robots/halfstep.json "firmware.halfstep." 3 "")
# The same source built for eight motors, as the host's prediction will run it: the same
# answers for the MK2 as the Nano's build gives, to the tick (test_prediction).
articula_firmware_variant(wide "" "firmware.wide." 8 "test_prediction")
