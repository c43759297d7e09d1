# The Nano's bootloader, for the page's virtual Nano to be flashed through (studio/web/src/
# nano.mjs, stk500.mjs): Optiboot, built here from the source Debian's arduino-core-avr
# ships beside its prebuilt hex. Included by firmware/CMakeLists.txt in the AVR build. Makes
#   optiboot_atmega328.hex   115,200 baud, 3 LED flashes, at 0x7E00 (the Nano's "new bootloader")
#
# Not Debian's prebuilt optiboot/optiboot_atmega328.hex: built with Debian's avr-gcc 5.4 it is
# 532 bytes for a 512-byte slot. Its code runs on past 0x7FFF (the chip's program counter
# wraps to the application's vectors) and the version word at 0x7FFE overwrites one of its
# instructions, so it drops into the application as it starts. The Makefile's options plus
# -fno-move-loop-invariants (and the -mrelax this GCC has instead of -mshort-calls) make 500.
set(ARDUINO_AVR_DIR /usr/share/arduino/hardware/arduino/avr CACHE PATH
    "Arduino AVR core 1.8.x (Debian package arduino-core-avr): Optiboot's source")
set(optiboot_dir ${ARDUINO_AVR_DIR}/bootloaders/optiboot)
set(optiboot_elf ${CMAKE_CURRENT_BINARY_DIR}/optiboot_atmega328.elf)
set(optiboot_hex ${CMAKE_CURRENT_BINARY_DIR}/optiboot_atmega328.hex)
if(NOT EXISTS ${optiboot_dir}/optiboot.c)
  message(FATAL_ERROR "no Optiboot source in ${optiboot_dir}: install the Debian package arduino-core-avr")
endif()
add_custom_command(
  OUTPUT ${optiboot_hex}
  COMMAND ${AVR_GCC} -mmcu=atmega328p -DF_CPU=16000000L -DBAUD_RATE=115200 -DLED_START_FLASHES=3
          -Os -fno-inline-small-functions -fno-split-wide-types -mrelax -fno-caller-saves
          -fno-tree-scev-cprop -fno-jump-tables -fno-move-loop-invariants -w
          -I${optiboot_dir} -nostartfiles -nostdlib
          -Wl,--section-start=.text=0x7e00 -Wl,--section-start=.version=0x7ffe -Wl,--relax
          -o ${optiboot_elf} ${optiboot_dir}/optiboot.c
  # its code must end before the version word at 0x7FFE
  COMMAND ${CMAKE_COMMAND} -DELF=${optiboot_elf} -DAVR_SIZE=${AVR_SIZE} -DTEXT_LIMIT=510
          -P ${ARTICULA_FIRMWARE_DIR}/tools/bootloader_size_check.cmake
  COMMAND ${AVR_OBJCOPY} -O ihex -j .text -j .version ${optiboot_elf} ${optiboot_hex}
  DEPENDS ${optiboot_dir}/optiboot.c ${ARTICULA_FIRMWARE_DIR}/tools/bootloader_size_check.cmake
  COMMENT "optiboot_atmega328.hex (from Debian's Optiboot source)"
  VERBATIM)
add_custom_target(optiboot ALL DEPENDS ${optiboot_hex})
