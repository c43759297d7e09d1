# cmake -P script run by CTest: configures and builds shared/avr_check with the AVR
# toolchain in a fresh tree, then prints each check ELF's size. Fails if any step fails.
file(REMOVE_RECURSE ${BINARY_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${BINARY_DIR} -G ${GENERATOR}
                        -DCMAKE_TOOLCHAIN_FILE=${SOURCE_DIR}/cmake/avr-gcc.cmake -DCMAKE_BUILD_TYPE=MinSizeRel
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the AVR build failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY_DIR} --target core_check RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the shared core does not compile for the ATmega328P")
endif()
file(GLOB elfs ${BINARY_DIR}/shared/avr_check/check_*.elf)
list(LENGTH elfs count)
if(count EQUAL 0)
  message(FATAL_ERROR "no check ELF was built")
endif()
execute_process(COMMAND avr-size ${elfs} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "avr-size could not read the check ELFs")
endif()
