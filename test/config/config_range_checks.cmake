# cmake -DAVR_GXX=... -DSOURCE_DIR=... -DWORK_DIR=... -P config_range_checks.cmake
# Each case: header | the text as it is | the text out of range | the static_assert message's start
# (no semicolons: a CMake list separator). A header is named as the firmware includes it,
# "config/x.h" (in firmware/) or "wmra_mega/board.h" (in boards/); its copy goes to
# WORK_DIR/<case>/, searched before firmware/ and boards/ (-I order).
set(cases
  "config/control_config.h|kStickCalibrationSpread_counts = 12|kStickCalibrationSpread_counts = 20|kStickCalibrationSpread_counts:"
  "config/control_config.h|kMaxRxBytesPerTick = 32|kMaxRxBytesPerTick = 11|kMaxRxBytesPerTick:"
  "config/control_config.h|kMaxRxStepsPerTick = 48|kMaxRxStepsPerTick = 30|kMaxRxStepsPerTick in"
  "config/control_config.h|kDriftMaxCorrection_mm_s = 20|kDriftMaxCorrection_mm_s = 51|kDriftMaxCorrection_mm_s at most"
  "config/gravity_config.h|{97, 30, 672}|{97, 30, -672}|kLinkCentre:"
  "config/joints_config.h|kHomingFast_crad_s[3] = {10, 30, 25}|kHomingFast_crad_s[3] = {25, 30, 25}|kHomingFast_crad_s: J1's"
  "config/joints_config.h|kHomingFast_crad_s[3] = {10, 30, 25}|kHomingFast_crad_s[3] = {12, 30, 25}|kHomingFast_crad_s[0]: J1's homing approach must stop"
  "config/joints_config.h|kHomingFast_crad_s[3] = {10, 30, 25}|kHomingFast_crad_s[3] = {10, 30, 40}|kHomingFast_crad_s[2]: J6's fast approach"
  "config/joints_config.h|kJ6Sweep_deg[4] = {-30, 90, -178, 178}|kJ6Sweep_deg[4] = {-30, 90, -179, 179}|kJ6Sweep_deg:"
  "config/stop_config.h|kStopTorqueShare_permille = 700|kStopTorqueShare_permille = 950|kStopTorqueShare_permille in"
  "config/stop_config.h|kStepperLoadInertia_gm2[3] = {3200, 115, 2}|kStepperLoadInertia_gm2[3] = {3200, 115, 0}|kStepperHoldingTorque_mNm in"
  "config/joints_config.h|kDcKp[3] = {{5527, 100000}|kDcKp[3] = {{5527, 1000}|kDcKp, kDcKi_per_s, kDcKd_s: each gain fits"
  "config/joints_config.h|kArrivedTolerance_mdeg = 1000|kArrivedTolerance_mdeg = 300|kArrivedTolerance_mdeg:"
  "config/joints_config.h|kStepsPerJointTurn[3] = {200ul * 32 * 2, 200ul * 32 * 10,|kStepsPerJointTurn[3] = {200ul * 32 * 2, 200ul * 32 * 50,|kStepsPerJointTurn:"
  "config/modes_config.h|Mode::r1, Mode::r2, Mode::gripper}|Mode::r1, Mode::xy, Mode::gripper}|kModeCycle: each"
  "config/motion_config.h|kJointSpeedLimit_crad_s[6] = {80,|kJointSpeedLimit_crad_s[6] = {0,|kJointSpeedLimit_crad_s in"
  "wmra_mega/board.h|kTimingProbe = {Port::L, 0, 49}|kTimingProbe = {Port::B, 7, 49}|board pins: each pin")

set(flags -mmcu=atmega2560 -DF_CPU=16000000UL -std=gnu++14 -fno-exceptions -fno-rtti -fsyntax-only)
set(includes -I${SOURCE_DIR}/firmware -I${SOURCE_DIR}/boards -I${SOURCE_DIR}/lib)
set(source ${SOURCE_DIR}/firmware/app/arm_control.cpp)

execute_process(COMMAND ${AVR_GXX} ${flags} ${includes} ${source} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the configuration as it is does not compile:\n${err}")
endif()

file(REMOVE_RECURSE ${WORK_DIR})
set(failed 0)
set(n 0)
foreach(c IN LISTS cases)
  string(REPLACE "|" ";" parts "${c}")
  list(GET parts 0 header)
  list(GET parts 1 as_is)
  list(GET parts 2 out_of_range)
  list(GET parts 3 expected)
  math(EXPR n "${n} + 1")
  if(header MATCHES "^config/")
    set(original ${SOURCE_DIR}/firmware/${header})
  else()
    set(original ${SOURCE_DIR}/boards/${header})
  endif()
  file(READ ${original} text)
  string(FIND "${text}" "${as_is}" at)
  if(at EQUAL -1)
    message(SEND_ERROR "case ${n}: '${as_is}' is not in ${header} (the value changed? update the case)")
    set(failed 1)
    continue()
  endif()
  string(REPLACE "${as_is}" "${out_of_range}" text "${text}")
  file(WRITE ${WORK_DIR}/${n}/${header} "${text}")
  execute_process(COMMAND ${AVR_GXX} ${flags} -I${WORK_DIR}/${n} ${includes} ${source} RESULT_VARIABLE rc ERROR_VARIABLE err)
  string(FIND "${err}" "static assertion failed: ${expected}" found)
  if(rc EQUAL 0 OR found EQUAL -1)
    message(SEND_ERROR "case ${n}: ${header} with '${out_of_range}' did not fail with \"${expected}...\":\n${err}")
    set(failed 1)
  else()
    message(STATUS "case ${n}: ${header} '${out_of_range}' fails: ${expected}...")
  endif()
endforeach()
if(failed)
  message(FATAL_ERROR "a configuration out of range built, or failed for another reason")
endif()
