/* firmware/sim/simavr_mcu_section.c - simavr's metadata for the Nano firmware's ELF.
 *
 * Tells simavr (and the virtual Nano of hil/) the part and its clock, so they run
 * articula-nano.elf as it is. Linked by firmware/avr.cmake only (with the section placed at
 * 0x910000 and kept by --undefined=_mmcu); the HEX for a real board leaves it out. Not in
 * src/, so PlatformIO, which has no simavr header, never compiles it. */
#include <simavr/avr/avr_mcu_section.h>

AVR_MCU(F_CPU, "atmega328p");
