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

# The cut tests' problem, written into @p dir: slab.pgm, a 12 x 10 picture of stiffness 200 (ASCII PGM,
# extruded to 3 slices by the tests); slab_carved.pgm, the same with the columns x = 5, 6 outside (0),
# what --carve 5:6,0:9,0:2 makes of it; blade.obj, a blade at x = 3.5 for y from 2 to 8 through all
# slices (paths from a seed at x = 1 go round it).
function(write_cut_slab dir)
  set(row "")
  set(row_carved "")
  foreach(x RANGE 11)
    string(APPEND row " 200")
    if(x EQUAL 5 OR x EQUAL 6)
      string(APPEND row_carved " 0")
    else()
      string(APPEND row_carved " 200")
    endif()
  endforeach()
  string(REPEAT "${row}\n" 10 rows)
  string(REPEAT "${row_carved}\n" 10 rows_carved)
  file(WRITE ${dir}/slab.pgm "P2\n12 10\n255\n${rows}")
  file(WRITE ${dir}/slab_carved.pgm "P2\n12 10\n255\n${rows_carved}")
  file(WRITE ${dir}/blade.obj "v 3.5 2 -5\nv 3.5 8 -5\nv 3.5 8 5\nv 3.5 2 5\nf 1 2 3 4\n")
endfunction()
