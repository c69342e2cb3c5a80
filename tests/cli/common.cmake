# Shared preamble and helpers of the CLI end-to-end scripts (tests/cli/*_cli.cmake), included after
# the script's own header comment. Needs -DGEOVORONOI=<binary> -DWORK=<scratch folder>; BUILT (the
# backends compiled in, comma-separated) defaults to seq; CLI_TIMEOUT (seconds per run) to 120.
if(NOT GEOVORONOI OR NOT WORK)
  get_filename_component(_gv_script "${CMAKE_SCRIPT_MODE_FILE}" NAME)
  message(FATAL_ERROR "usage: cmake -DGEOVORONOI=<binary> -DWORK=<dir> -P ${_gv_script}")
endif()
if(NOT BUILT)
  set(BUILT seq)
endif()
string(REPLACE "," ";" BUILT "${BUILT}")
if(NOT CLI_TIMEOUT)
  set(CLI_TIMEOUT 120)
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# run(<name> <expected exit code> args...): sets OUT_<name>, ERR_<name>, RC_<name>
function(run name expect)
  execute_process(COMMAND ${GEOVORONOI} ${ARGN} WORKING_DIRECTORY ${WORK}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT ${CLI_TIMEOUT})
  set(OUT_${name} "${out}" PARENT_SCOPE)
  set(ERR_${name} "${err}" PARENT_SCOPE)
  set(RC_${name} "${rc}" PARENT_SCOPE)
  if(NOT rc STREQUAL "${expect}")
    message(SEND_ERROR "FAIL: ${name}: exit code ${rc}, expected ${expect}\nstdout: ${out}\nstderr: ${err}")
  endif()
endfunction()

# one_line(<name> <needle>): ERR_<name> is exactly one line and contains needle
function(one_line name needle)
  string(STRIP "${ERR_${name}}" e)
  string(FIND "${e}" "\n" nl)
  string(FIND "${e}" "${needle}" hit)
  if(e STREQUAL "" OR NOT nl EQUAL -1 OR hit EQUAL -1)
    message(SEND_ERROR "FAIL: ${name}: expected one stderr line containing '${needle}', got: ${ERR_${name}}")
  endif()
endfunction()
