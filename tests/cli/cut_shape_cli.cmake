# End-to-end tests of `geovoronoi cut --method` (docs/cli.md, "cut"), run by ctest as `cmake -P`:
#   -DGEOVORONOI=<path of the binary> -DWORK=<scratch folder> [-DBUILT=seq,thrust,cuda]
# The shape-function files in before/ and after/ must equal `shape-functions` runs on the problem
# without and with the change byte for byte; changed_weights.mhd must be 1 exactly where a voxel's
# row (node indices or weights) differs; the timing lines must be printed; bad options exit 2.
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/common.cmake)

# check_changed_weights(<dir> <k> <voxel>): DIR/changed_weights.raw is 1 exactly where the rows of
# before/ and after/ differ (K interleaved 4-byte channels in indices.raw and weights.raw), and 1 at
# the linear index <voxel>, where the change must show
function(check_changed_weights dir k voxel)
  math(EXPR row_bytes "${k} * 4")
  unset(ones)
  check_change_mask(${dir} changed_weights ${row_bytes} weights.raw indices.raw)
  if(NOT DEFINED ones)
    return()
  endif()
  file(READ ${WORK}/${dir}/changed_weights.raw ch HEX)
  math(EXPR o1 "${voxel} * 2")
  string(SUBSTRING "${ch}" ${o1} 2 c)
  if(ones EQUAL 0 OR NOT c STREQUAL "01")
    message(SEND_ERROR "FAIL: ${dir}: ${ones} voxels' weights changed, and voxel ${voxel} is ${c}, expected 01")
  endif()
endfunction()

# timing_lines(<name> <method>): stdout has the weights' update and full-recompute lines, with times
function(timing_lines name method)
  foreach(re "weights update +[0-9]+\\.[0-9]+ s +\\(${method}, library update_shape_functions\\(\\) on backend [a-z() ]+; [0-9]+ of 360 rows recomputed, [0-9]+ changed\\)"
             "weights recompute +[0-9]+\\.[0-9]+ s +\\(${method}, shape_functions\\(\\) on backend [a-z]+\\) +[0-9.]+x; identical bit for bit")
    if(NOT "${OUT_${name}}" MATCHES "${re}")
      message(SEND_ERROR "FAIL: ${name}: stdout lacks a line matching '${re}': ${OUT_${name}}")
    endif()
  endforeach()
endfunction()

# The problem of cut_command_cli.cmake: a 12 x 10 picture of stiffness 200 extruded to 3 slices,
# two seeds, a blade at x = 3.5 (y 2..8, every slice) beside seed 0; the same field with the
# columns x = 5, 6 outside, what --carve 5:6,0:9,0:2 makes of it.
write_cut_slab(${WORK})
file(WRITE ${WORK}/seeds.csv "1,5,1\n10,5,1\n8,1,1\n")
set(S --stiffness slab.pgm --extrude 3 --seeds seeds.csv)
# voxel (4,5,1), just behind the blade from seed 0: its distance and so its weights change
set(behind 184)

set(shape_files indices.mhd indices.raw weights.mhd weights.raw indices_sofa_planar.mhd indices_sofa_planar.raw
                weights_sofa_planar.mhd weights_sofa_planar.raw weights.vti weights_indptr.npy weights_indices.npy
                weights_data.npy weight_node0.png)
foreach(b ${BUILT})
  if(b STREQUAL "cuda")
    continue()  # needs a device
  endif()
  foreach(m distance-ratio sibson laplace)
    set(n ${m}_${b})
    run(cut_${n} 0 cut ${S} --cut blade.obj --method ${m} --backend ${b} --out cut-${n})
    timing_lines(cut_${n} ${m})
    # before/ and after/ are what shape-functions writes without and with the cut
    run(plain_${n} 0 shape-functions ${S} --method ${m} --backend ${b} --out plain-${n})
    run(after_${n} 0 shape-functions ${S} --cut blade.obj --method ${m} --backend ${b} --out after-${n})
    foreach(f ${shape_files})
      if(NOT EXISTS ${WORK}/cut-${n}/before/${f} OR NOT EXISTS ${WORK}/cut-${n}/after/${f})
        message(SEND_ERROR "FAIL: cut_${n}: ${f} missing")
        continue()
      endif()
      same_file(cut-${n}/before/${f} plain-${n}/${f})
      same_file(cut-${n}/after/${f} after-${n}/${f})
    endforeach()
    check_changed_weights(cut-${n} 4 ${behind})
  endforeach()
endforeach()

# carving and a cut together, K = 2, --picture-node: after/ equals shape-functions on the carved field
run(both 0 cut ${S} --cut blade.obj --carve 5:6,0:9,0:2 --method sibson --nodes-per-voxel 2 --picture-node 2
    --backend seq --out both)
run(both_full 0 shape-functions --stiffness slab_carved.pgm --extrude 3 --seeds seeds.csv --cut blade.obj
    --method sibson --nodes-per-voxel 2 --picture-node 2 --backend seq --out both-full)
timing_lines(both sibson)
foreach(f weights.raw indices.raw weights_data.npy weight_node2.png)
  same_file(both/after/${f} both-full/${f})
endforeach()
check_changed_weights(both 2 ${behind})

# --precision double: the weights in double, still equal to shape-functions
run(dbl 0 cut ${S} --cut blade.obj --method laplace --precision double --backend seq --out dbl)
run(dbl_full 0 shape-functions ${S} --cut blade.obj --method laplace --precision double --backend seq --out dbl-full)
same_file(dbl/after/weights.raw dbl-full/weights.raw)
file(READ ${WORK}/dbl/after/weights.mhd hdr)
if(NOT hdr MATCHES "ElementType = MET_DOUBLE")
  message(SEND_ERROR "FAIL: dbl: after/weights.mhd is not MET_DOUBLE")
endif()

# without --method: the diagram only, as before
run(plain 0 cut ${S} --cut blade.obj --backend seq --out no-method)
if(EXISTS ${WORK}/no-method/changed_weights.mhd OR EXISTS ${WORK}/no-method/after/weights.mhd
   OR NOT EXISTS ${WORK}/no-method/changed.mhd)
  message(SEND_ERROR "FAIL: cut without --method wrote shape functions, or not the diagram's files")
endif()
string(FIND "${OUT_plain}" "weights" hit)
if(NOT hit EQUAL -1)
  message(SEND_ERROR "FAIL: cut without --method speaks of weights: ${OUT_plain}")
endif()

# help
run(help 0 help cut)
foreach(needle "--method M" "--nodes-per-voxel K" "changed_weights.mhd")
  string(FIND "${OUT_help}" "${needle}" hit)
  if(hit EQUAL -1)
    message(SEND_ERROR "FAIL: help cut lacks '${needle}'")
  endif()
endforeach()

# bad input: exit 2, one line, nothing left behind
run(bad_method 2 cut ${S} --cut blade.obj --method voronoi --backend seq --out bad1)
one_line(bad_method "unknown method 'voronoi' (distance-ratio, sibson or laplace)")
run(bad_k 2 cut ${S} --cut blade.obj --method sibson --nodes-per-voxel 0 --backend seq --out bad2)
one_line(bad_k "--nodes-per-voxel must be an integer from 1 to 64")
run(k_alone 2 cut ${S} --cut blade.obj --nodes-per-voxel 3 --backend seq --out bad3)
one_line(k_alone "--nodes-per-voxel needs --method")
run(bad_node 2 cut ${S} --cut blade.obj --method sibson --picture-node 3 --backend seq --out bad4)
one_line(bad_node "--picture-node 3: must be less than the number of nodes (3)")
run(no_value 2 cut ${S} --cut blade.obj --backend seq --out bad5 --method)
one_line(no_value "--method needs a value")
foreach(d bad1 bad2 bad3 bad4 bad5)
  if(EXISTS ${WORK}/${d})
    message(SEND_ERROR "FAIL: a failed run left ${d}")
  endif()
endforeach()
