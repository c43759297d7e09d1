# firmware/native.cmake - the firmware's logic on the host, tested against a fake HAL.
#
# For each robot variant: robot_config.h generated from its robot file, the firmware
# sources (all of src/ but the AVR HAL and main.cpp) as a library compiled gnu++11 as on the
# Nano, the fake HAL and harness (test/*.cpp, which PlatformIO compiles with every test
# folder too), and one GoogleTest program per test folder (test/test_<unit>/test_<unit>.cpp).
# Two variants: the robot the firmware is built for (ARTICULA_ROBOT, the MK2: full steps,
# parallelogram) under the prefix "firmware.", and a test robot with half steps, a reversed
# motor, the identity coupling and a home pose away from step 0 under "firmware.halfstep.".
find_program(ARTICULA_PYTHON3 python3 REQUIRED)

set(fw_src_dir ${ARTICULA_FIRMWARE_DIR}/src)
set(fw_test_dir ${ARTICULA_FIRMWARE_DIR}/test)
file(GLOB fw_sources CONFIGURE_DEPENDS ${fw_src_dir}/*.cpp)
list(FILTER fw_sources EXCLUDE REGEX "/(hal_avr|main)\\.cpp$")
file(GLOB fw_test_folders LIST_DIRECTORIES true CONFIGURE_DEPENDS ${fw_test_dir}/test_*)

function(articula_firmware_variant variant robot prefix)
  set(gen ${CMAKE_CURRENT_BINARY_DIR}/${variant})
  add_custom_command(OUTPUT ${gen}/robot_config.h
    COMMAND ${ARTICULA_PYTHON3} ${ARTICULA_FIRMWARE_DIR}/tools/robot_config.py ${robot} ${gen}/robot_config.h
    DEPENDS ${ARTICULA_FIRMWARE_DIR}/tools/robot_config.py ${robot}
    COMMENT "Generating robot_config.h (${variant}) from ${robot}"
    VERBATIM)

  add_library(firmware_${variant} STATIC ${fw_sources} ${gen}/robot_config.h)
  target_include_directories(firmware_${variant} PUBLIC ${fw_src_dir} ${gen})
  target_link_libraries(firmware_${variant} PUBLIC articula::core)
  target_compile_options(firmware_${variant} PRIVATE ${ARTICULA_WARNINGS})
  set_target_properties(firmware_${variant} PROPERTIES CXX_STANDARD 11 CXX_EXTENSIONS ON)

  # The fake HAL resolves the library's hal:: calls: linked as objects, ahead of it.
  add_library(firmware_sim_${variant} OBJECT ${fw_test_dir}/fake_hal.cpp ${fw_test_dir}/harness.cpp)
  target_include_directories(firmware_sim_${variant} PUBLIC ${fw_test_dir})
  target_link_libraries(firmware_sim_${variant} PUBLIC firmware_${variant} GTest::gtest)
  target_compile_options(firmware_sim_${variant} PRIVATE ${ARTICULA_WARNINGS})

  foreach(folder ${fw_test_folders})
    get_filename_component(name ${folder} NAME)
    set(exe firmware_${variant}_${name})
    add_executable(${exe} ${folder}/${name}.cpp)
    target_link_libraries(${exe} PRIVATE firmware_sim_${variant} GTest::gtest_main)
    target_compile_options(${exe} PRIVATE ${ARTICULA_WARNINGS})
    target_compile_definitions(${exe} PRIVATE ARTICULA_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                                              ARTICULA_ROBOT_FILE="${robot}")
    gtest_discover_tests(${exe} TEST_PREFIX "${prefix}" DISCOVERY_TIMEOUT 60)
  endforeach()
endfunction()

articula_firmware_variant(main ${ARTICULA_ROBOT} "firmware.")
articula_firmware_variant(halfstep ${fw_test_dir}/robots/halfstep.json "firmware.halfstep.")
