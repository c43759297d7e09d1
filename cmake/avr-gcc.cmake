# CMake toolchain file for Debian's avr-gcc (package gcc-avr 5.4) and the ATmega328P of
# the Arduino Nano. Use: cmake -DCMAKE_TOOLCHAIN_FILE=cmake/avr-gcc.cmake ...
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR avr)

set(AVR_MCU atmega328p CACHE STRING "AVR part")
set(AVR_F_CPU 16000000UL CACHE STRING "CPU clock in Hz")

find_program(AVR_GCC avr-gcc REQUIRED)
find_program(AVR_GXX avr-g++ REQUIRED)
find_program(AVR_GCC_AR avr-gcc-ar REQUIRED)
find_program(AVR_GCC_RANLIB avr-gcc-ranlib REQUIRED)
find_program(AVR_OBJCOPY avr-objcopy REQUIRED)
find_program(AVR_SIZE avr-size REQUIRED)

set(CMAKE_C_COMPILER ${AVR_GCC})
set(CMAKE_CXX_COMPILER ${AVR_GXX})
set(CMAKE_ASM_COMPILER ${AVR_GCC})
# LTO objects need the plugin-aware archiver (Arduino's platform.txt does the same).
set(CMAKE_AR ${AVR_GCC_AR} CACHE FILEPATH "" FORCE)
set(CMAKE_RANLIB ${AVR_GCC_RANLIB} CACHE FILEPATH "" FORCE)

# Compiler checks would try to link a host-style program; a static library is enough.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)


set(CMAKE_C_FLAGS_INIT "-mmcu=${AVR_MCU} -DF_CPU=${AVR_F_CPU}")
# avr-g++ 5.4 defaults to C++98; the core is written for gnu++11.
set(CMAKE_CXX_FLAGS_INIT "-mmcu=${AVR_MCU} -DF_CPU=${AVR_F_CPU} -std=gnu++11")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-mmcu=${AVR_MCU}")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
