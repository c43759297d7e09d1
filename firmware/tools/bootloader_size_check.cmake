# cmake -DELF=... -DAVR_SIZE=avr-size -DTEXT_LIMIT=bytes -P bootloader_size_check.cmake
# Fails when the bootloader's code is longer than its slot.
execute_process(COMMAND ${AVR_SIZE} -A ${ELF} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "avr-size failed on ${ELF}")
endif()
string(REGEX MATCH "\n\\.text +([0-9]+)" _ "${out}")
set(text ${CMAKE_MATCH_1})
if(text GREATER TEXT_LIMIT)
  message(FATAL_ERROR "${ELF}: its code is ${text} bytes, more than the ${TEXT_LIMIT} of its slot")
endif()
message(STATUS "bootloader: ${text} of ${TEXT_LIMIT} bytes")
