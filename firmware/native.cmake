# firmware/native.cmake - the firmware's logic on the host, on a virtual clock, and its tests.
#
# The firmware on its virtual clock (sitl/sitl.cmake: src/ but the AVR HAL, with the SITL HAL
# and machine), the tests' harness
# (test/harness.cpp, which PlatformIO compiles with every test folder too), and one
# GoogleTest program per test folder
# (test/test_<unit>/test_<unit>.cpp), for each of four arms on the one firmware: the MK2 a
# blank EEPROM gets, under the prefix "firmware.", a test robot with half steps, a reversed
# motor, the identity coupling and a home pose away from step 0, under "firmware.halfstep.",
# that robot on 28BYJ-48s and ULN2003 boards under "firmware.uln2003.", and on STEP/DIR
# drivers in a CNC shield's sockets under "firmware.cnc.", and on hobby servos under
# "firmware.servo." (the shipped meArm's prediction: "firmware.wide.mearm."): a variant's
# configuration (made by `articula configure --header`) is what the harness puts in the SITL
# EEPROM of a fresh machine.
set(fw_test_dir ${ARTICULA_FIRMWARE_DIR}/test)
file(GLOB fw_test_folders LIST_DIRECTORIES true CONFIGURE_DEPENDS ${fw_test_dir}/test_*)

# robot: its file ("" for the built-in MK2); sitl: the firmware library the variant runs on
# ("" builds one of its own for three motors, as on the Nano; articula_firmware_sitl is the
# host's, eight motors, which the host library runs: a test that needs the host library, its
# loader or its prediction, runs on that one, since a program links one firmware); tests: the
# test folders to build ("": all but those that need the host library).
set(fw_host_tests test_robot test_prediction)
# Folders for one family of drivers only: the coils' on the 4-wire arms, the pulses' on the
# arms on STEP/DIR drivers (the robot file names "step-dir"), the servos' on servo arms.
set(fw_coil_tests test_coils)
set(fw_step_dir_tests test_step_dir)
set(fw_servo_tests test_servo)
function(articula_firmware_variant variant robot prefix sitl tests)
  set(not_for_this_arm ${fw_step_dir_tests} ${fw_servo_tests})
  if(robot)
    file(READ ${robot} robot_text)
    if(robot_text MATCHES "\"step-dir\"")
      set(not_for_this_arm ${fw_coil_tests} ${fw_servo_tests})
    elseif(robot_text MATCHES "\"servo\"")  # a servo's steps are pulses' ticks, as STEP/DIR's
      set(not_for_this_arm ${fw_coil_tests} ${fw_step_dir_tests})
    endif()
  endif()
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

  if(NOT sitl)
    set(sitl firmware_sitl_nano)
  endif()

  # The tests' harness: the variant's arm at boot, the checks that need GoogleTest.
  add_library(firmware_harness_${variant} OBJECT ${fw_test_dir}/harness.cpp)
  target_include_directories(firmware_harness_${variant} PUBLIC ${fw_test_dir})
  target_link_libraries(firmware_harness_${variant} PUBLIC ${sitl} GTest::gtest)
  target_compile_options(firmware_harness_${variant} PRIVATE ${ARTICULA_WARNINGS} ${ARTICULA_TEST_FLAGS})
  target_compile_definitions(firmware_harness_${variant} PRIVATE ${config_defs} ARTICULA_ROBOT_FILE="${robot_file}")
  if(robot)
    add_dependencies(firmware_harness_${variant} firmware_config_${variant})
  endif()

  foreach(folder ${fw_test_folders})
    get_filename_component(name ${folder} NAME)
    if(tests AND NOT name IN_LIST tests)
      continue()
    endif()
    if(NOT tests AND name IN_LIST fw_host_tests)
      continue()
    endif()
    if(name IN_LIST not_for_this_arm)
      continue()
    endif()
    # The folder's tests, compiled once for each build of the firmware (the variant's arm is its
    # harness's): every variant on that build links the same objects.
    set(objects firmware_tests_${sitl}_${name})
    if(NOT TARGET ${objects})
      add_library(${objects} OBJECT ${folder}/${name}.cpp)
      target_include_directories(${objects} PRIVATE ${fw_test_dir})
      target_link_libraries(${objects} PRIVATE ${sitl} GTest::gtest)
      if(name IN_LIST fw_host_tests)  # the host's loader, its prediction
        target_link_libraries(${objects} PRIVATE articula_host)
      endif()
      target_compile_options(${objects} PRIVATE ${ARTICULA_WARNINGS} ${ARTICULA_TEST_FLAGS})
      target_compile_definitions(${objects} PRIVATE ARTICULA_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
    endif()
    set(exe firmware_${variant}_${name})
    add_executable(${exe} $<TARGET_OBJECTS:${objects}>)
    target_link_libraries(${exe} PRIVATE firmware_harness_${variant} GTest::gtest_main)
    if(name IN_LIST fw_host_tests)
      target_link_libraries(${exe} PRIVATE articula_host)
    endif()
    gtest_discover_tests(${exe} TEST_PREFIX "${prefix}" DISCOVERY_TIMEOUT 60)
  endforeach()
endfunction()

# The firmware for the Nano's three motors on its virtual clock: one library for every variant
# on it (a variant's arm is in its harness, not in the firmware's build).
articula_firmware_sitl(firmware_sitl_nano 3)

articula_firmware_variant(main "" "firmware." "" "")
articula_firmware_variant(halfstep ${fw_test_dir}/robots/halfstep.json "firmware.halfstep." "" "")
# 28BYJ-48s on ULN2003 boards: the unipolar coil table, a gear train that is not whole.
articula_firmware_variant(uln2003 ${fw_test_dir}/robots/uln2003.json "firmware.uln2003." "" "")
# STEP/DIR drivers in a CNC shield's sockets: pulses and DIR, and ENABLE for the coils' idle rule.
articula_firmware_variant(cnc ${fw_test_dir}/robots/cnc.json "firmware.cnc." "" "")
# Hobby servos: a step is a tick of a servo's pulse.
articula_firmware_variant(servo ${fw_test_dir}/robots/servo.json "firmware.servo." "" "")
# The same arms on the host's build of the firmware (eight motors, host/CMakeLists.txt), which
# the prediction runs: the tests that need the host library. It gives the same answers as the
# Nano's build: hil/ holds the prediction against the Nano's own hex in simavr.
articula_firmware_variant(wide "" "firmware.wide." articula_firmware_sitl "${fw_host_tests}")
articula_firmware_variant(wide_halfstep ${fw_test_dir}/robots/halfstep.json "firmware.wide.halfstep." articula_firmware_sitl
                          "${fw_host_tests}")
articula_firmware_variant(wide_uln2003 ${fw_test_dir}/robots/uln2003.json "firmware.wide.uln2003." articula_firmware_sitl
                          "${fw_host_tests}")
articula_firmware_variant(wide_cnc ${fw_test_dir}/robots/cnc.json "firmware.wide.cnc." articula_firmware_sitl "${fw_host_tests}")
articula_firmware_variant(wide_servo ${fw_test_dir}/robots/servo.json "firmware.wide.servo." articula_firmware_sitl
                          "${fw_host_tests}")
articula_firmware_variant(wide_mearm ${PROJECT_SOURCE_DIR}/robots/mearm.json "firmware.wide.mearm." articula_firmware_sitl
                          "${fw_host_tests}")
