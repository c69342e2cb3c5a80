# End-to-end tests of `--precision float|double|auto` and of the float overflow checks (docs/cli.md,
# "Precision"), run by ctest as `cmake -P`:
#   -DGEOVORONOI=<path of the binary> -DWORK=<scratch folder> [-DBUILT=seq,thrust,cuda]
# Binary inputs are written byte by byte with string(ASCII) (values chosen without 0 bytes).
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/common.cmake)

# element_type(<dir/file.mhd> <MET_...>): the header names that element type
function(element_type file type)
  if(NOT EXISTS ${WORK}/${file})
    message(SEND_ERROR "FAIL: ${file} missing")
    return()
  endif()
  file(READ ${WORK}/${file} hdr)
  if(NOT hdr MATCHES "ElementType = ${type}")
    message(SEND_ERROR "FAIL: ${file}: expected ElementType = ${type}, got:\n${hdr}")
  endif()
endfunction()

# all_labelled(<dir>): label.raw holds no -1 (every voxel of the connected object reached)
function(all_labelled dir)
  file(READ ${WORK}/${dir}/label.raw hex HEX)
  string(LENGTH "${hex}" n)
  string(FIND "${hex}" "ffffffff" hole)
  if(n EQUAL 0 OR NOT hole EQUAL -1)
    message(SEND_ERROR "FAIL: ${dir}: some voxels came out unreachable (label -1)")
  endif()
endfunction()

# mhd(<name> <type> <nx> <ny> <spacing> <data>): name.mhd + name.raw, one slice
function(mhd name type nx ny spacing data)
  file(WRITE ${WORK}/${name}.raw "${data}")
  file(WRITE ${WORK}/${name}.mhd "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
             "DimSize = ${nx} ${ny} 1\nElementSpacing = ${spacing} ${spacing} ${spacing}\nElementType = ${type}\n"
             "ElementDataFile = ${name}.raw\n")
endfunction()

# A connected 12 x 10 cost field of 122 ('z') with a spacing of 1e37: under mean_cost every edge
# weighs 1.22e39, beyond float (3.4e38) and far within double.
string(REPEAT "z" 120 costs)
mhd(cost MET_UCHAR 12 10 1e37 "${costs}")
file(WRITE ${WORK}/seeds.csv "1,1,0\n9,7,0\n")
set(C --stiffness cost.mhd --seeds seeds.csv --metric mean_cost --connectivity 6)

foreach(b ${BUILT})
  if(b STREQUAL "cuda")
    continue()  # needs a device
  endif()
  # float (the default): the overflow is an error, exit 2, one line naming it and the way out
  run(float_${b} 2 voronoi ${C} --backend ${b} --out out-float-${b})
  one_line(float_${b} "overflows float")
  one_line(float_${b} "--precision double")
  if(EXISTS ${WORK}/out-float-${b})
    message(SEND_ERROR "FAIL: float_${b}: a failed run left its output folder")
  endif()
  run(explicit_float_${b} 2 voronoi ${C} --backend ${b} --precision float --out out-float-${b})
  if(NOT ERR_explicit_float_${b} STREQUAL ERR_float_${b})
    message(SEND_ERROR "FAIL: --precision float differs from the default: ${ERR_explicit_float_${b}}")
  endif()
  # double: everything reached, distances written as MET_DOUBLE
  run(double_${b} 0 voronoi ${C} --backend ${b} --precision double --out out-double-${b})
  element_type(out-double-${b}/distance.mhd MET_DOUBLE)
  all_labelled(out-double-${b})
  # auto picks double here
  run(auto_${b} 0 voronoi ${C} --backend ${b} --precision auto --out out-auto-${b})
  element_type(out-auto-${b}/distance.mhd MET_DOUBLE)
  all_labelled(out-auto-${b})
endforeach()
if("thrust" IN_LIST BUILT)  # the same message, naming the same voxel, on every backend
  if(NOT ERR_float_thrust STREQUAL ERR_float_seq)
    message(SEND_ERROR "FAIL: thrust and seq report the overflow differently:\n${ERR_float_thrust}\n${ERR_float_seq}")
  endif()
  file(READ ${WORK}/out-double-seq/distance.raw ds HEX)
  file(READ ${WORK}/out-double-thrust/distance.raw dt HEX)
  if(NOT ds STREQUAL dt)
    message(SEND_ERROR "FAIL: double distances differ between seq and thrust")
  endif()
endif()

# auto keeps float where float is enough
file(WRITE ${WORK}/soft.pgm "P2\n6 5\n255\n")
foreach(y RANGE 4)
  file(APPEND ${WORK}/soft.pgm "100 100 100 100 100 100\n")
endforeach()
file(WRITE ${WORK}/seeds2.csv "1,1\n4,3\n")
run(auto_float 0 voronoi --stiffness soft.pgm --seeds seeds2.csv --backend seq --precision auto --out out-auto-float)
element_type(out-auto-float/distance.mhd MET_FLOAT)

# a bad value
run(bad_value 2 voronoi --stiffness soft.pgm --seeds seeds2.csv --precision half --out out-bad)
one_line(bad_value "--precision")
run(bad_value_shape 2 shape-functions --stiffness soft.pgm --seeds seeds2.csv --method sibson --precision 64
    --out out-bad)
one_line(bad_value_shape "--precision")

# double input values that float cannot hold: 1.003e300 (would become +inf) and 1e-50 (would
# become 0, i.e. masked), among 1.001 elsewhere; an error in float, fine in double and auto
string(ASCII 106 188 116 147 24 4 240 63 normal)
string(ASCII 137 142 4 205 149 246 55 126 huge)
string(ASCII 31 184 212 74 122 238 141 53 tiny)
foreach(kind huge tiny)
  set(data "")
  foreach(i RANGE 29)
    if(i EQUAL 13)
      string(APPEND data "${${kind}}")
    else()
      string(APPEND data "${normal}")
    endif()
  endforeach()
  mhd(${kind} MET_DOUBLE 6 5 1 "${data}")
  run(${kind}_float 2 voronoi --stiffness ${kind}.mhd --seeds seeds2.csv --backend seq --out out-${kind})
  one_line(${kind}_float "(1,2,0)")
  one_line(${kind}_float "--precision double")
  run(${kind}_double 0 voronoi --stiffness ${kind}.mhd --seeds seeds2.csv --backend seq --precision double
      --out out-${kind}-double)
  all_labelled(out-${kind}-double)
  run(${kind}_auto 0 voronoi --stiffness ${kind}.mhd --seeds seeds2.csv --backend seq --precision auto
      --out out-${kind}-auto)
  element_type(out-${kind}-auto/distance.mhd MET_DOUBLE)
endforeach()
one_line(huge_float "beyond float's range")
one_line(tiny_float "too small for float")

# the smallest double, 5e-324 (its bytes hold NULs, which a CMake string cannot: written by printf),
# under min_stiffness in double: its edge weight 1/5e-324 overflows double itself, so the advice is to
# rescale, never the --precision double already given
mhd(subnormal MET_DOUBLE 6 5 1 "")
execute_process(COMMAND sh -c "i=0; while [ $i -lt 30 ]; do if [ $i = 13 ]; then printf '\\001\\000\\000\\000\\000\\000\\000\\000'; else printf '\\000\\000\\000\\000\\000\\000\\360\\077'; fi; i=$((i+1)); done"
                OUTPUT_FILE ${WORK}/subnormal.raw RESULT_VARIABLE rc)
file(SIZE ${WORK}/subnormal.raw subnormal_size)
if(NOT rc EQUAL 0 OR NOT subnormal_size EQUAL 240)
  message(SEND_ERROR "FAIL: could not write subnormal.raw (exit ${rc}, ${subnormal_size} bytes)")
endif()
run(subnormal_double 2 voronoi --stiffness subnormal.mhd --seeds seeds2.csv --backend seq --precision double --out out-sub)
one_line(subnormal_double "overflows double")
one_line(subnormal_double "rescale")
string(FIND "${ERR_subnormal_double}" "--precision" advises_flag)
string(FIND "${ERR_subnormal_double}" "compute in double" advises_double)
if(NOT advises_flag EQUAL -1 OR NOT advises_double EQUAL -1)
  message(SEND_ERROR "FAIL: subnormal_double: an overflow in double advises double precision: ${ERR_subnormal_double}")
endif()

# shape functions: the same precision through the whole pipeline
run(shape_float 2 shape-functions ${C} --backend seq --method laplace --out out-shape-float)
one_line(shape_float "overflows float")
run(shape_double 0 shape-functions ${C} --backend seq --method laplace --precision double --out out-shape-double)
element_type(out-shape-double/distance.mhd MET_DOUBLE)
element_type(out-shape-double/weights.mhd MET_DOUBLE)
run(shape_auto 0 shape-functions ${C} --backend seq --method sibson --precision auto --threads 1 --out out-shape-auto)
element_type(out-shape-auto/weights.mhd MET_DOUBLE)
