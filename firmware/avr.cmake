# The Nano firmware, built with the AVR toolchain (cmake/avr-gcc.cmake); included by
# firmware/CMakeLists.txt. Makes, for each build (below):
#   <build>.elf  every firmware/src/*.cpp, and avr-libc: no Arduino core (the HAL sets every
#                register it uses, main.cpp is the entry point); runs unchanged in simavr;
#                one firmware for every arm its drivers can move (the robot configuration is
#                in EEPROM);
#   <build>.hex  what goes to the board (without the simavr and EEPROM sections), after a
#                size check that prints flash and RAM use and fails the build above the
#                budgets below.
set(ARTICULA_FLASH_BUDGET 30720 CACHE STRING "firmware flash budget in bytes: all a Nano with the old bootloader takes")
set(ARTICULA_RAM_BUDGET 1600 CACHE STRING "firmware static RAM (.data + .bss) budget in bytes (the Nano has 2,048)")

# ---- the firmware: one source, a build for each family of drivers ----
# articula_avr_firmware(NAME DEFINITIONS...): every source in src/ (the AVR HAL and main.cpp,
# and the portable logic) as NAME.elf, and NAME.hex after the size check.
#   articula-nano  the Nano's (or Uno's) own pins: L298N or ULN2003 boards (board.h's slots)
#   articula-cnc   a Nano on a CNC Shield V4 or an Uno on a CNC Shield V3: STEP/DIR drivers in
#                  its sockets (ARTICULA_CNC_SHIELD: board.h's shield pins); the same pins on
#                  both, so one hex, within the Nano's old-bootloader budget
#   articula-servo hobby-servo arms (meArm, EEZYbotARM MK2): a servo on any header pin the
#                  configuration names, Timer1's pulses (ARTICULA_SERVO_ARM)
file(GLOB firmware_sources CONFIGURE_DEPENDS ${ARTICULA_FIRMWARE_DIR}/src/*.cpp)
# The flags, from firmware/flags.txt (PlatformIO takes them from there too): each "name: flags"
# line as firmware_<name>_flags.
file(STRINGS ${ARTICULA_FIRMWARE_DIR}/flags.txt flag_lines REGEX "^[a-z]+:")
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${ARTICULA_FIRMWARE_DIR}/flags.txt)
foreach(line IN LISTS flag_lines)
  string(REGEX MATCH "^([a-z]+): *(.*)$" unused "${line}")
  separate_arguments(firmware_${CMAKE_MATCH_1}_flags UNIX_COMMAND "${CMAKE_MATCH_2}")
endforeach()
foreach(name language warnings size link)
  if(NOT firmware_${name}_flags)
    message(FATAL_ERROR "firmware/flags.txt: no line \"${name}: ...\"")
  endif()
endforeach()
set(firmware_flags ${firmware_size_flags})

# The simavr metadata (MCU name and clock) in a .mmcu section, so simavr and the virtual Nano
# run this very ELF without being told what it is. simavr 1.6 needs the section at 0x910000
# (elsewhere it loads .data from the wrong place); the HEX leaves it out. The section comes
# from simavr's own header (Debian package libsimavr-dev), compiled from a C file outside
# src/, so PlatformIO (which has no simavr) never sees it; it is compiled without LTO, which
# would drop the tags that nothing refers to.
set(simavr_header /usr/include/simavr/avr/avr_mcu_section.h)
if(EXISTS ${simavr_header})
  # Only this one header, not /usr/include (the host's libc must not shadow avr-libc).
  configure_file(${simavr_header} ${CMAKE_CURRENT_BINARY_DIR}/simavr_include/simavr/avr/avr_mcu_section.h COPYONLY)
  add_library(simavr_mcu_section OBJECT ${ARTICULA_FIRMWARE_DIR}/sim/simavr_mcu_section.c)
  target_include_directories(simavr_mcu_section PRIVATE ${CMAKE_CURRENT_BINARY_DIR}/simavr_include)
  target_compile_options(simavr_mcu_section PRIVATE ${firmware_warnings_flags} -fno-lto)
else()
  message(STATUS "no ${simavr_header} (libsimavr-dev): the ELF has no simavr metadata; "
                 "run it with simavr -m atmega328p -f 16000000")
endif()

function(articula_avr_firmware name)
  add_executable(${name} ${firmware_sources})
  set_target_properties(${name} PROPERTIES SUFFIX ".elf")
  target_include_directories(${name} PRIVATE ${ARTICULA_FIRMWARE_DIR}/src ${ARTICULA_SHARED_DIR})
  target_compile_definitions(${name} PRIVATE ${ARGN})
  target_compile_options(${name} PRIVATE ${firmware_warnings_flags} $<$<COMPILE_LANGUAGE:CXX>:${firmware_language_flags}>
                                         ${firmware_flags})
  target_link_options(${name} PRIVATE ${firmware_flags} ${firmware_link_flags})
  target_link_libraries(${name} PRIVATE m)
  if(TARGET simavr_mcu_section)
    target_sources(${name} PRIVATE $<TARGET_OBJECTS:simavr_mcu_section>)
    target_link_options(${name} PRIVATE -Wl,--undefined=_mmcu,--section-start=.mmcu=0x910000)
  endif()
  # The HEX, after the size check (runs at every build, so every build shows the figures).
  set(elf ${CMAKE_CURRENT_BINARY_DIR}/${name}.elf)
  set(hex ${CMAKE_CURRENT_BINARY_DIR}/${name}.hex)
  add_custom_target(${name}-hex ALL
    COMMAND ${CMAKE_COMMAND} -DELF=${elf} -DAVR_SIZE=${AVR_SIZE} -DFLASH_BUDGET=${ARTICULA_FLASH_BUDGET}
            -DRAM_BUDGET=${ARTICULA_RAM_BUDGET} -P ${ARTICULA_FIRMWARE_DIR}/tools/avr_size_check.cmake
    COMMAND ${AVR_OBJCOPY} -O ihex -R .eeprom -R .mmcu ${elf} ${hex}
    BYPRODUCTS ${hex}
    DEPENDS ${name}
    COMMENT "${name}.hex"
    VERBATIM)
endfunction()

articula_avr_firmware(articula-nano)
articula_avr_firmware(articula-cnc ARTICULA_CNC_SHIELD)
articula_avr_firmware(articula-servo ARTICULA_SERVO_ARM)
