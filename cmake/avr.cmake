# Helpers for AVR images: an ELF plus its size report.
function(wmra_avr_image name)
  add_executable(${name} ${ARGN})
  set_target_properties(${name} PROPERTIES SUFFIX ".elf")
  target_link_libraries(${name} PRIVATE wmra_kinematics)
  add_custom_command(TARGET ${name} POST_BUILD
    COMMAND ${AVR_SIZE} --format=avr --mcu=${AVR_MCU} $<TARGET_FILE:${name}>
    VERBATIM)
endfunction()
