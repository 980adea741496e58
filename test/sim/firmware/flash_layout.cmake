# cmake -DAVR_NM=... -DELF=... -P flash_layout.cmake
# The image within the chip's lower 128 KB, so that every code address fits a 16-bit word
# pointer (avr-gcc's indirect calls and switch tables use eicall/eijmp with EIND 0: no far calls,
# no EIND trampolines), and PROGMEM within the lower 64 KB, where pgm_read_* (LPM through a 16-bit
# Z) reaches. avr-libc's linker script places PROGMEM right after the vectors and the trampolines
# and before the start-up code (__ctors_start).
execute_process(COMMAND ${AVR_NM} ${ELF} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "avr-nm ${ELF} failed")
endif()
function(address_of name out)
  string(REGEX MATCH "([0-9a-f]+) [A-Za-z] ${name}\n" m "${symbols}")
  if(NOT m)
    message(FATAL_ERROR "${name} not in ${ELF}")
  endif()
  math(EXPR value "0x${CMAKE_MATCH_1}" OUTPUT_FORMAT DECIMAL)
  set(${out} ${value} PARENT_SCOPE)
endfunction()
address_of(__trampolines_start trampolines_start)
address_of(__trampolines_end trampolines_end)
address_of(__ctors_start progmem_end)
address_of(_etext text_end)
address_of(__data_load_start data_load)
execute_process(COMMAND ${CMAKE_COMMAND} -E echo "trampolines ${trampolines_start}..${trampolines_end}, PROGMEM ends at ${progmem_end} B, code at ${text_end} B, flash with .data's image ${data_load} B")
if(NOT trampolines_start EQUAL trampolines_end)
  message(FATAL_ERROR "EIND trampolines in the image: code beyond 128 KB is called through a pointer")
endif()
if(progmem_end GREATER 65536)
  message(FATAL_ERROR "PROGMEM ends at ${progmem_end} B, beyond the lower 64 KB that pgm_read_* reaches")
endif()
if(text_end GREATER 131072)
  message(FATAL_ERROR "code ends at ${text_end} B, beyond the lower 128 KB")
endif()
