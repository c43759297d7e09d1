# firmware/sitl/sitl.cmake - the firmware on a virtual clock as a library, for the firmware's
# native tests (firmware/native.cmake) and for the host's prediction (host/CMakeLists.txt: the
# host library, the CLI, Python and the web engine all run it).
#
# articula_firmware_sitl(TARGET MOTORS): src/'s controller (every .cpp but the AVR HAL and
# main.cpp), compiled for the host unchanged, gnu++11 as on the Nano, with the SITL HAL and the
# machine that runs its main loop and interrupts (sitl/). One library: the HAL and the firmware
# call each other. MOTORS is the build's motor count (robot::kJoints): 3 as on the Nano, 8 for
# the host (the same source). It drives every stepper kind (ARTICULA_FIRMWARE_DRIVES: the
# L298N's and ULN2003's coils and STEP/DIR drivers), the configuration's $131 choosing, where
# each AVR build drives one family (robot.h).
#
# A program links one such library, never two (they define the same symbols); it holds any
# number of machines of it (machine.h: sitl::Machine, each with the firmware's state).
#
# articula_firmware_sitl(TARGET MOTORS SRC_DIR): the same from another copy of src/ (a test
# that changes a firmware source and sees the prediction follow: host/tests/CMakeLists.txt).
function(articula_firmware_sitl target motors)
  set(sitl ${CMAKE_CURRENT_FUNCTION_LIST_DIR})
  set(src ${sitl}/../src)
  if(ARGC GREATER 2)
    set(src ${ARGV2})
  endif()
  file(GLOB sources CONFIGURE_DEPENDS ${src}/*.cpp)
  list(FILTER sources EXCLUDE REGEX "/(hal_avr|main)\\.cpp$")
  add_library(${target} STATIC ${sources} ${sitl}/hal_sitl.cpp ${sitl}/machine.cpp)
  # (virtual-nano/coil_decoder.h: the SITL reads the coils as the virtual Nanos do)
  target_include_directories(${target} PUBLIC ${src} ${sitl} ${sitl}/../../virtual-nano)
  target_link_libraries(${target} PUBLIC articula::core)
  target_compile_definitions(${target} PUBLIC ARTICULA_FIRMWARE_MOTORS=${motors} ARTICULA_FIRMWARE_DRIVES=0x0F)
  target_compile_options(${target} PRIVATE ${ARTICULA_WARNINGS})
  set_target_properties(${target} PROPERTIES CXX_STANDARD 11 CXX_EXTENSIONS ON UNITY_BUILD OFF)
endfunction()
