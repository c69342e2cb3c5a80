# End-to-end tests of the geovoronoi command-line tool (run by ctest as `cmake -P`):
#   -DGEOVORONOI=<path of the binary> -DWORK=<scratch folder> [-DBUILT=seq,thrust,cuda] [-DVERSION=x.y.z]
# BUILT: the backends the build compiled into the binary (from the CMake targets); default seq.
# Good runs must exit 0 and leave readable outputs of the right sizes; every bad input must exit 2
# with exactly one line on stderr that names the problem, and leave no output folder behind.
cmake_minimum_required(VERSION 3.20)
if(NOT GEOVORONOI OR NOT WORK)
  message(FATAL_ERROR "usage: cmake -DGEOVORONOI=<binary> -DWORK=<dir> -P run_cli.cmake")
endif()
if(NOT BUILT)
  set(BUILT seq)
endif()
string(REPLACE "," ";" BUILT "${BUILT}")
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
set(failures 0)

macro(fail msg)
  message(SEND_ERROR "FAIL: ${msg}")
  math(EXPR failures "${failures} + 1")
endmacro()

# A 12 x 10 picture: soft (100) everywhere, a stiff bar (255) in the middle, background (0) corners.
set(pgm "P2\n# test stiffness\n12 10\n255\n")
foreach(y RANGE 9)
  set(row "")
  foreach(x RANGE 11)
    if((x EQUAL 0 AND y EQUAL 0) OR (x EQUAL 11 AND y EQUAL 9))
      set(v 0)
    elseif(x EQUAL 6 AND y GREATER 1)
      set(v 255)
    else()
      set(v 100)
    endif()
    string(APPEND row "${v} ")
  endforeach()
  string(APPEND pgm "${row}\n")
endforeach()
file(WRITE ${WORK}/stiff.pgm "${pgm}")
file(WRITE ${WORK}/seeds.csv "# i,j,k\n2,2,1\n9, 7, 2   # trailing comment\n\n4,8,3\n")
file(WRITE ${WORK}/world.csv "2.2,2.4,1.0\n9.1,6.6,2.0\n")

# run(<name> <expected exit code> args...): sets OUT_<name>, ERR_<name>
function(run name expect)
  execute_process(COMMAND ${GEOVORONOI} ${ARGN} WORKING_DIRECTORY ${WORK}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
  set(OUT_${name} "${out}" PARENT_SCOPE)
  set(ERR_${name} "${err}" PARENT_SCOPE)
  if(NOT rc STREQUAL "${expect}")
    message(SEND_ERROR "FAIL: ${name}: exit code ${rc}, expected ${expect}\nstdout: ${out}\nstderr: ${err}")
    set(bad 1 PARENT_SCOPE)
  else()
    set(bad 0 PARENT_SCOPE)
  endif()
endfunction()

function(expect_file path min_size)
  if(NOT EXISTS ${path})
    message(SEND_ERROR "FAIL: missing output ${path}")
    return()
  endif()
  file(SIZE ${path} size)
  if(size LESS ${min_size})
    message(SEND_ERROR "FAIL: ${path} has ${size} bytes, expected at least ${min_size}")
  endif()
endfunction()

# ---- good runs -------------------------------------------------------------------------------
set(voxels 480)  # 12 x 10 x 4
run(voronoi 0 voronoi --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --out out-v)
if(NOT OUT_voronoi MATCHES "480 voxels, 3 seeds, backend [a-z]+, [0-9.]+ s")
  fail("voronoi summary line: ${OUT_voronoi}")
endif()
math(EXPR bytes4 "${voxels} * 4")
foreach(f distance.raw label.raw)
  expect_file(${WORK}/out-v/${f} ${bytes4})
  file(SIZE ${WORK}/out-v/${f} size)
  if(NOT size EQUAL bytes4)
    fail("${f} has ${size} bytes, expected ${bytes4}")
  endif()
endforeach()
foreach(f distance.mhd label.mhd labels.png distance.png voronoi.vti)
  expect_file(${WORK}/out-v/${f} 50)
endforeach()
file(READ ${WORK}/out-v/label.mhd hdr)
if(NOT hdr MATCHES "ElementType = MET_INT" OR NOT hdr MATCHES "DimSize = 12 10 4")
  fail("label.mhd header: ${hdr}")
endif()
file(READ ${WORK}/out-v/distance.mhd hdr)
if(NOT hdr MATCHES "ElementType = MET_FLOAT")
  fail("distance.mhd header: ${hdr}")
endif()
file(READ ${WORK}/out-v/labels.png sig LIMIT 4 HEX)
if(NOT sig STREQUAL "89504e47")
  fail("labels.png is not a PNG (${sig})")
endif()
file(GLOB partial ${WORK}/*.partial-*)
if(partial)
  fail("partial output left behind: ${partial}")
endif()

# the outputs are valid inputs: MetaImage (label.mhd: -1/0 masked, labels >= 1 inside) and world seeds
run(reread 0 voronoi --stiffness out-v/distance.mhd --seeds world.csv --world --metric mean_cost
    --connectivity 6 --backend seq --out out-r)
expect_file(${WORK}/out-r/label.raw ${bytes4})
# rerunning into an existing folder replaces its files
run(again 0 voronoi --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --connectivity 18 --metric mean_stiffness --out out-v)

foreach(method sibson distance-ratio laplace)
  run(shape_${method} 0 shape-functions --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --method ${method}
      --nodes-per-voxel 3 --out out-${method})
  math(EXPR kbytes "${voxels} * 3 * 4")
  foreach(f indices.raw weights.raw indices_sofa_planar.raw weights_sofa_planar.raw)
    file(SIZE ${WORK}/out-${method}/${f} size)
    if(NOT size EQUAL kbytes)
      fail("${method}/${f} has ${size} bytes, expected ${kbytes}")
    endif()
  endforeach()
  file(READ ${WORK}/out-${method}/indices.mhd hdr)
  if(NOT hdr MATCHES "ElementType = MET_UINT" OR NOT hdr MATCHES "ElementNumberOfChannels = 3")
    fail("${method}/indices.mhd header: ${hdr}")
  endif()
  foreach(f weights_indptr.npy weights_indices.npy weights_data.npy weight_node0.png labels.png label.mhd weights.vti)
    expect_file(${WORK}/out-${method}/${f} 50)
  endforeach()
  # the interleaved copy (weights.mhd, for ITK/ParaView) and SOFA's planar one hold the same values,
  # each voxel's K weights together in the first and each slot's N values together in the second
  file(READ ${WORK}/out-${method}/weights_sofa_planar.mhd hdr)
  if(NOT hdr MATCHES "ElementNumberOfChannels = 3" OR NOT hdr MATCHES "ElementDataFile = weights_sofa_planar.raw")
    fail("${method}/weights_sofa_planar.mhd header: ${hdr}")
  endif()
  file(READ ${WORK}/out-${method}/weights.raw inter HEX)
  file(READ ${WORK}/out-${method}/weights_sofa_planar.raw planar HEX)
  # voxel 17 (two nodes or more in every method): slot s at byte (17*3 + s)*4 interleaved, (s*N + 17)*4 planar
  foreach(slot 0 1 2)
    math(EXPR ia "(17 * 3 + ${slot}) * 8")
    math(EXPR pa "(${slot} * ${voxels} + 17) * 8")
    string(SUBSTRING "${inter}" ${ia} 8 iv)
    string(SUBSTRING "${planar}" ${pa} 8 pv)
    if(NOT iv STREQUAL pv)
      fail("${method}: weights.mhd voxel 17 slot ${slot} is ${iv}, weights_sofa_planar.mhd has ${pv}")
    endif()
  endforeach()
  # ParaView sees the weights and node indices as K-component arrays
  file(READ ${WORK}/out-${method}/weights.vti vti LIMIT 2000)
  if(NOT vti MATCHES "Name=\"weights\" NumberOfComponents=\"3\"" OR NOT vti MATCHES "Name=\"nodes\" NumberOfComponents=\"3\"")
    fail("${method}/weights.vti lacks the 3-component weights and nodes arrays: ${vti}")
  endif()
  # indptr holds voxels + 1 int64 values after a 128-byte header
  file(SIZE ${WORK}/out-${method}/weights_indptr.npy size)
  math(EXPR want "128 + (${voxels} + 1) * 8")
  if(NOT size EQUAL want)
    fail("${method}/weights_indptr.npy has ${size} bytes, expected ${want}")
  endif()
endforeach()

# --at: weights only at chosen points. With every voxel as a point, in linear order, the points x nodes
# CSR files are byte for byte the per-voxel ones (the rows of the full computation); world points
# round to the nearest voxel centre like --world seeds, so jittered world points give the same rows.
set(all_points "")
foreach(z RANGE 3)
  foreach(y RANGE 9)
    foreach(x RANGE 11)
      string(APPEND all_points "${x},${y},${z}\n")
    endforeach()
  endforeach()
endforeach()
file(WRITE ${WORK}/all_points.csv "${all_points}")
file(WRITE ${WORK}/few_points.csv "5,1,0\n3,3,2\n5,1,0\n11,9,3\n")
file(WRITE ${WORK}/few_world.csv "5.3,0.8,0.1\n2.6,3.4,2.2\n4.9,1.2,-0.3\n11.1,8.7,3.0\n")
file(WRITE ${WORK}/seeds_world.csv "2.0,2.1,1.0\n9.2,6.9,2.0\n4.1,8.0,3.0\n")
foreach(method sibson distance-ratio laplace)
  run(at_all_${method} 0 shape-functions --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --method ${method}
      --nodes-per-voxel 3 --at all_points.csv --out out-at-${method})
  foreach(f indptr indices data)
    file(READ ${WORK}/out-at-${method}/weights_at_${f}.npy at_bytes HEX)
    file(READ ${WORK}/out-${method}/weights_${f}.npy full_bytes HEX)
    if(NOT at_bytes STREQUAL full_bytes)
      fail("${method}: weights_at_${f}.npy of every voxel differs from weights_${f}.npy")
    endif()
  endforeach()
  if(EXISTS ${WORK}/out-at-${method}/weights.mhd)
    fail("${method} --at also wrote the per-voxel weights.mhd")
  endif()
  run(at_few_${method} 0 shape-functions --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --method ${method}
      --nodes-per-voxel 3 --at few_points.csv --out out-atf-${method})
  run(at_world_${method} 0 shape-functions --stiffness stiff.pgm --extrude 4 --seeds seeds_world.csv --world
      --method ${method} --nodes-per-voxel 3 --at few_world.csv --out out-atw-${method})
  file(READ ${WORK}/out-atf-${method}/weights_at.csv few_csv)
  file(READ ${WORK}/out-atw-${method}/weights_at.csv world_csv)
  if(NOT few_csv STREQUAL world_csv)
    fail("${method}: --world points give other weights than their voxels:\n${few_csv}\nvs\n${world_csv}")
  endif()
  # point 0 and point 2 are the same voxel; point 3 is the masked corner (no weights, no line)
  string(REGEX MATCHALL "\n0,[^\n]*" rows0 "${few_csv}")
  string(REGEX MATCHALL "\n2,[^\n]*" rows2 "${few_csv}")
  string(REPLACE "\n0," "\nX," rows0 "${rows0}")
  string(REPLACE "\n2," "\nX," rows2 "${rows2}")
  if(NOT few_csv MATCHES "^point,node,weight\n0," OR rows0 STREQUAL "" OR NOT rows0 STREQUAL rows2
     OR few_csv MATCHES "\n3,")
    fail("${method}: weights_at.csv rows:\n${few_csv}")
  endif()
endforeach()

# --picture-node picks the node whose weight is pictured
run(picture_node 0 shape-functions --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --method distance-ratio
    --picture-node 2 --out out-picture-node)
expect_file(${WORK}/out-picture-node/weight_node2.png 50)
if(EXISTS ${WORK}/out-picture-node/weight_node0.png)
  fail("--picture-node 2 also wrote weight_node0.png")
endif()

# ---- backends: the built set, the default rule, errors for the others, identical results ---------
run(backends 0 backends)
set(cuda_usable OFF)
foreach(b seq thrust cuda)
  if(b IN_LIST BUILT)
    if(NOT OUT_backends MATCHES "(^|\n)${b} +built")
      fail("backends: ${b} is built but not listed as built: ${OUT_backends}")
    endif()
  elseif(NOT OUT_backends MATCHES "(^|\n)${b} +not built")
    fail("backends: ${b} is not built but not listed as such: ${OUT_backends}")
  endif()
endforeach()
if("cuda" IN_LIST BUILT AND NOT OUT_backends MATCHES "(^|\n)cuda +[^\n]*unusable here")
  set(cuda_usable ON)
endif()
# the documented default: cuda when built and a device answers, else thrust when built on more than
# one hardware thread, else seq
set(threads 1)
if(OUT_backends MATCHES "(^|\n)thrust +built, OpenMP on ([0-9]+) hardware threads")
  set(threads ${CMAKE_MATCH_2})
endif()
if(cuda_usable)
  set(want_default cuda)
elseif("thrust" IN_LIST BUILT AND threads GREATER 1)
  set(want_default thrust)
else()
  set(want_default seq)
endif()
if(NOT OUT_backends MATCHES "(^|\n)default ${want_default}\n")
  fail("backends: default should be ${want_default} (built: ${BUILT}, cuda usable: ${cuda_usable}): ${OUT_backends}")
endif()
# a run without --backend chooses per problem (geovoronoi::recommended_backend): this volume is far
# below the size where thrust is faster, so seq, or cuda where a device answers
set(want_default seq)
if(cuda_usable)
  set(want_default cuda)
endif()
run(default_backend 0 voronoi --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --out out-default)
if(NOT OUT_default_backend MATCHES "backend ${want_default},")
  fail("the run without --backend did not use the default backend ${want_default}: ${OUT_default_backend}")
endif()
file(READ ${WORK}/out-default/label.raw default_labels HEX)
file(READ ${WORK}/out-default/distance.raw default_distances HEX)
# the same picture extruded to 2300 slices has 271,400 domain voxels, above the rule's 2^18: thrust
# (when built, no device) with more than one thread, seq with one; the rule counts the threads the
# run would use (--threads), not the machine's
set(want_many seq)
if(cuda_usable)
  set(want_many cuda)
elseif("thrust" IN_LIST BUILT)
  set(want_many thrust)
endif()
set(want_one seq)
if(cuda_usable)
  set(want_one cuda)
endif()
run(default_large_two 0 voronoi --stiffness stiff.pgm --extrude 2300 --seeds seeds.csv --threads 2 --out out-default-large)
if(NOT OUT_default_large_two MATCHES "backend ${want_many},")
  fail("a 271,400-voxel run with --threads 2 and no --backend should use ${want_many}: ${OUT_default_large_two}")
endif()
run(default_large_one 0 voronoi --stiffness stiff.pgm --extrude 2300 --seeds seeds.csv --threads 1 --out out-default-large)
if(NOT OUT_default_large_one MATCHES "backend ${want_one},")
  fail("a 271,400-voxel run with --threads 1 and no --backend should use ${want_one}: ${OUT_default_large_one}")
endif()
file(REMOVE_RECURSE ${WORK}/out-default-large)
# shape functions share their searches among threads at any size
# (geovoronoi::recommended_shape_backend): the small volume goes to thrust with --threads 2
run(default_shape_two 0 shape-functions --method distance-ratio --stiffness stiff.pgm --extrude 4 --seeds seeds.csv
    --threads 2 --out out-default-shape)
if(NOT OUT_default_shape_two MATCHES "backend ${want_many},")
  fail("shape-functions with --threads 2 and no --backend should use ${want_many}: ${OUT_default_shape_two}")
endif()
run(default_shape_one 0 shape-functions --method distance-ratio --stiffness stiff.pgm --extrude 4 --seeds seeds.csv
    --threads 1 --out out-default-shape)
if(NOT OUT_default_shape_one MATCHES "backend ${want_one},")
  fail("shape-functions with --threads 1 and no --backend should use ${want_one}: ${OUT_default_shape_one}")
endif()
file(REMOVE_RECURSE ${WORK}/out-default-shape)

foreach(b seq thrust cuda)
  set(o out-b-${b})
  if(NOT b IN_LIST BUILT)
    set(expect 2)
    set(needle "backend '${b}' is not built")
  elseif(b STREQUAL "cuda" AND NOT cuda_usable)
    set(expect 2)
    set(needle "backend 'cuda': no")
  else()
    set(expect 0)
  endif()
  run(backend_${b} ${expect} voronoi --stiffness stiff.pgm --extrude 4 --seeds seeds.csv --backend ${b} --out ${o})
  if(expect EQUAL 0)
    if(NOT OUT_backend_${b} MATCHES "backend ${b},")
      fail("--backend ${b}: summary names another backend: ${OUT_backend_${b}}")
    endif()
    # every backend returns bitwise-identical distances and labels
    file(READ ${WORK}/${o}/label.raw labels HEX)
    file(READ ${WORK}/${o}/distance.raw distances HEX)
    if(NOT labels STREQUAL default_labels OR NOT distances STREQUAL default_distances)
      fail("--backend ${b}: distance.raw or label.raw differ from the default backend's")
    endif()
  else()
    string(STRIP "${ERR_backend_${b}}" e)
    string(FIND "${e}" "\n" nl)
    string(FIND "${e}" "${needle}" hit)
    if(NOT nl EQUAL -1 OR hit EQUAL -1)
      fail("--backend ${b}: expected one line mentioning \"${needle}\", got: ${ERR_backend_${b}}")
    endif()
    if(EXISTS ${WORK}/${o})
      fail("--backend ${b}: output folder left behind")
    endif()
  endif()
endforeach()
if("cuda" IN_LIST BUILT AND NOT cuda_usable)
  # the demo refuses an unusable cuda the same way, before doing any work
  run(demo_cuda 2 demo --backend cuda --out demo-cuda)
  if(NOT ERR_demo_cuda MATCHES "backend 'cuda': no" OR EXISTS ${WORK}/demo-cuda)
    fail("demo --backend cuda without a device: ${ERR_demo_cuda}")
  endif()
endif()

# ---- help and version: stdout, exit 0, nothing on stderr -------------------------------------
run(version 0 --version)
if(NOT OUT_version MATCHES "^geovoronoi [0-9]+\\.[0-9]+\\.[0-9]+\n$" OR NOT ERR_version STREQUAL "")
  fail("--version: '${OUT_version}' (stderr '${ERR_version}')")
endif()
if(VERSION AND NOT OUT_version STREQUAL "geovoronoi ${VERSION}\n")
  fail("--version says '${OUT_version}', the CMake project version is ${VERSION}")
endif()
run(overview 0 --help)
run(overview_help 0 help)
if(NOT OUT_overview STREQUAL OUT_overview_help)
  fail("--help and help differ")
endif()
foreach(c voronoi shape-functions cut voxelize demo backends)
  if(NOT OUT_overview MATCHES "\n  ${c} ")
    fail("--help does not list the command ${c}: ${OUT_overview}")
  endif()
  run(help_${c} 0 help ${c})
  run(dash_help_${c} 0 ${c} --help)
  run(h_${c} 0 ${c} -h)
  if(NOT OUT_help_${c} STREQUAL OUT_dash_help_${c} OR NOT OUT_help_${c} STREQUAL OUT_h_${c})
    fail("help ${c}, ${c} --help and ${c} -h differ")
  endif()
  if(NOT ERR_help_${c} STREQUAL "" OR NOT ERR_dash_help_${c} STREQUAL "")
    fail("help ${c} wrote to stderr: ${ERR_help_${c}} ${ERR_dash_help_${c}}")
  endif()
  foreach(part "usage: geovoronoi ${c}" "writes" "example:\n  geovoronoi ${c}")
    string(FIND "${OUT_help_${c}}" "${part}" hit)
    if(hit EQUAL -1)
      fail("help ${c} lacks '${part}': ${OUT_help_${c}}")
    endif()
  endforeach()
endforeach()
# every option's default is stated
foreach(part "(default: min_stiffness)" "(default: 26)" "(default: 1)" "(default: the fastest built one")
  string(FIND "${OUT_help_voronoi}" "${part}" hit)
  if(hit EQUAL -1)
    fail("help voronoi does not state '${part}'")
  endif()
endforeach()
foreach(part "(default: 4)" "distance-ratio, sibson or laplace")
  string(FIND "${OUT_help_shape-functions}" "${part}" hit)
  if(hit EQUAL -1)
    fail("help shape-functions does not state '${part}'")
  endif()
endforeach()
string(FIND "${OUT_help_demo}" "(default: demo-out)" hit)
if(hit EQUAL -1)
  fail("help demo does not state its default folder")
endif()
# --help wins over the other options, even bad ones, and does no work
run(help_with_options 0 voronoi --stiffness nope.mhd --help --out x-help)
if(NOT OUT_help_with_options STREQUAL OUT_help_voronoi OR EXISTS ${WORK}/x-help)
  fail("voronoi --help with other options: ${OUT_help_with_options}")
endif()

# ---- bad input: exit 2, one line on stderr naming the problem, no output folder ----------------
file(WRITE ${WORK}/outside.csv "2,2,1\n40,2,1\n")
file(WRITE ${WORK}/masked.csv "0,0,0\n")
file(WRITE ${WORK}/dup.csv "2,2,1\n3,3,1\n2,2,1\n")
file(WRITE ${WORK}/text.csv "2,two,1\n")
file(WRITE ${WORK}/frac.csv "2.5,2,1\n")
file(WRITE ${WORK}/empty.csv "# nothing\n\n")
file(WRITE ${WORK}/short.csv "2\n")
file(WRITE ${WORK}/lying.mhd "ObjectType = Image\nNDims = 3\nDimSize = 1000000 1000000 1000000\nElementType = MET_FLOAT\nElementDataFile = lying.raw\n")
file(WRITE ${WORK}/lying.raw "0123456789")
file(WRITE ${WORK}/truncated.mhd "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_FLOAT\nElementDataFile = lying.raw\n")
file(WRITE ${WORK}/garbage.npy "this is not numpy")
file(WRITE ${WORK}/stiff.tif "II*")

set(S --stiffness stiff.pgm --extrude 4)
set(SC "--stiffness,stiff.pgm,--extrude,4")
set(cases
  "no_command|missing command"
  "bad_command|frobnicate|unknown command"
  "unknown_option|voronoi,${SC},--seeds,seeds.csv,--out,x1,--colour,red|unknown option"
  "missing_value|voronoi,${SC},--seeds,seeds.csv,--out|needs a value"
  "no_stiffness|voronoi,--seeds,seeds.csv,--out,x2|--stiffness"
  "no_seeds|voronoi,${SC},--out,x3|--seeds"
  "no_out|voronoi,${SC},--seeds,seeds.csv|--out"
  "missing_file|voronoi,--stiffness,nope.mhd,--seeds,seeds.csv,--out,x4|nope.mhd"
  "lying_header|voronoi,--stiffness,lying.mhd,--seeds,seeds.csv,--out,x5|lying.mhd"
  "truncated|voronoi,--stiffness,truncated.mhd,--seeds,seeds.csv,--out,x6|truncated"
  "garbage_npy|voronoi,--stiffness,garbage.npy,--seeds,seeds.csv,--out,x7|garbage.npy"
  "unknown_format|voronoi,--stiffness,stiff.tif,--seeds,seeds.csv,--out,x8|unknown volume format"
  "extrude_not_picture|voronoi,--stiffness,out-v/distance.mhd,--extrude,3,--seeds,seeds.csv,--out,x9|--extrude"
  "bad_extrude|voronoi,--stiffness,stiff.pgm,--extrude,0,--seeds,seeds.csv,--out,x10|--extrude"
  "seed_outside|voronoi,${SC},--seeds,outside.csv,--out,x11|outside.csv:2: the seed on line 2 at (40"
  "seed_masked|voronoi,${SC},--seeds,masked.csv,--out,x12|masked.csv:1: the seed on line 1 at (0"
  "seed_duplicate|voronoi,${SC},--seeds,dup.csv,--out,x13|dup.csv:3: the seeds on lines 1 and 3 share the voxel"
  "seed_text|voronoi,${SC},--seeds,text.csv,--out,x14|not a number"
  "seed_fraction|voronoi,${SC},--seeds,frac.csv,--out,x15|not an integer"
  "seed_empty|voronoi,${SC},--seeds,empty.csv,--out,x16|no seeds"
  "seed_short|voronoi,${SC},--seeds,short.csv,--out,x17|expected"
  "seed_file_missing|voronoi,${SC},--seeds,nope.csv,--out,x18|nope.csv"
  "bad_metric|voronoi,${SC},--seeds,seeds.csv,--metric,euclid,--out,x19|unknown metric"
  "bad_connectivity|voronoi,${SC},--seeds,seeds.csv,--connectivity,7,--out,x20|connectivity"
  "bad_backend|voronoi,${SC},--seeds,seeds.csv,--backend,opencl,--out,x21|unknown backend"
  "bad_out_parent|voronoi,${SC},--seeds,seeds.csv,--out,no/such/dir|does not exist"
  "no_method|shape-functions,${SC},--seeds,seeds.csv,--out,x22|--method"
  "bad_method|shape-functions,${SC},--seeds,seeds.csv,--method,kriging,--out,x23|unknown method"
  "bad_k|shape-functions,${SC},--seeds,seeds.csv,--method,sibson,--nodes-per-voxel,0,--out,x24|--nodes-per-voxel"
  "demo_bad_option|demo,--size,3|unknown option"
  "bad_picture_node|shape-functions,${SC},--seeds,seeds.csv,--method,sibson,--picture-node,3,--out,x25|--picture-node 3"
  "at_outside|shape-functions,${SC},--seeds,seeds.csv,--method,sibson,--at,outside.csv,--out,x26|outside.csv:2: point (40"
  "at_empty|shape-functions,${SC},--seeds,seeds.csv,--method,sibson,--at,empty.csv,--out,x27|no points in the file"
  "help_unknown|help,frobnicate|unknown command 'frobnicate'"
  "help_two|help,voronoi,demo|at most one"
)
foreach(c ${cases})
  string(REPLACE "|" ";" parts "${c}")
  list(GET parts 0 name)
  list(LENGTH parts n)
  math(EXPR last "${n} - 1")
  list(GET parts ${last} needle)
  set(args "")
  if(n GREATER 2)
    list(GET parts 1 argstr)
    string(REPLACE "," ";" args "${argstr}")
  endif()
  run(${name} 2 ${args})
  string(STRIP "${ERR_${name}}" e)
  string(FIND "${e}" "\n" nl)
  if(NOT nl EQUAL -1)
    fail("${name}: stderr has more than one line: ${ERR_${name}}")
  endif()
  string(FIND "${e}" "${needle}" hit)
  if(hit EQUAL -1)
    fail("${name}: stderr does not mention '${needle}': ${e}")
  endif()
endforeach()
file(GLOB leftovers ${WORK}/x[0-9]* ${WORK}/*.partial-*)
if(leftovers)
  fail("bad runs left outputs behind: ${leftovers}")
endif()

if(failures GREATER 0)
  message(FATAL_ERROR "${failures} CLI check(s) failed")
endif()
message(STATUS "all CLI checks passed")
