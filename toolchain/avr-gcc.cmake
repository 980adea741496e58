# CMake toolchain for the ATmega2560 (Arduino Mega) with Debian's gcc-avr 5.4 and avr-libc.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR avr)

find_program(AVR_GCC avr-gcc REQUIRED)
find_program(AVR_GXX avr-g++ REQUIRED)
find_program(AVR_OBJCOPY avr-objcopy REQUIRED)
find_program(AVR_SIZE avr-size REQUIRED)

set(CMAKE_C_COMPILER ${AVR_GCC})
set(CMAKE_CXX_COMPILER ${AVR_GXX})
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(AVR_MCU atmega2560 CACHE STRING "AVR part (-mmcu)")
set(AVR_F_CPU 16000000UL CACHE STRING "CPU clock in Hz")

# avr-g++ 5.4 knows C++14 at most and ships no C++ standard library. -mstrict-X keeps the X
# pointer to the addressing modes the hardware has (no displacement), which spares the
# adiw/sbiw pairs around struct accesses: 2-3% fewer cycles in the kinematics.
set(CMAKE_CXX_FLAGS_INIT "-mmcu=${AVR_MCU} -DF_CPU=${AVR_F_CPU} -mstrict-X -std=gnu++14 -fno-exceptions -fno-rtti -fno-threadsafe-statics")
set(CMAKE_C_FLAGS_INIT "-mmcu=${AVR_MCU} -DF_CPU=${AVR_F_CPU} -mstrict-X")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-mmcu=${AVR_MCU} -Wl,--gc-sections")
# No -O here: CMake appends its "-O3 -DNDEBUG" to these, and the last -O wins. So every image is
# built at -O3 (the kinematics and control cycle budgets were measured so) unless its CMakeLists
# sets a source's level (firmware/CMakeLists.txt: cold code at -Os, for flash).
set(CMAKE_CXX_FLAGS_RELEASE_INIT "-g -ffunction-sections -fdata-sections")  # -g: line info for profiles, not flashed
set(CMAKE_C_FLAGS_RELEASE_INIT "-ffunction-sections -fdata-sections")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
