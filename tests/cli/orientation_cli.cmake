# End-to-end tests of orientation (docs/cli.md, "Orientation"): a rotated MetaImage input keeps its
# direction matrix in every output (MetaImage TransformMatrix, .vti Direction), and --world seeds and
# --at points use it. Run by ctest as `cmake -P`:
#   -DGEOVORONOI=<path of the binary> -DWORK=<scratch folder>
cmake_minimum_required(VERSION 3.20)
if(NOT GEOVORONOI OR NOT WORK)
  message(FATAL_ERROR "usage: cmake -DGEOVORONOI=<binary> -DWORK=<dir> -P orientation_cli.cmake")
endif()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# run(<name> <expected exit code> args...): sets OUT_<name>, ERR_<name>
function(run name expect)
  execute_process(COMMAND ${GEOVORONOI} ${ARGN} WORKING_DIRECTORY ${WORK}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
  set(OUT_${name} "${out}" PARENT_SCOPE)
  set(ERR_${name} "${err}" PARENT_SCOPE)
  if(NOT rc STREQUAL "${expect}")
    message(SEND_ERROR "FAIL: ${name}: exit code ${rc}, expected ${expect}\nstdout: ${out}\nstderr: ${err}")
  endif()
endfunction()

# has(<file> <text>): the file contains the text
function(has file text)
  file(READ ${WORK}/${file} content)
  string(FIND "${content}" "${text}" at)
  if(at EQUAL -1)
    message(SEND_ERROR "FAIL: ${file} does not contain '${text}'")
  endif()
endfunction()

function(same a b)
  file(SHA256 ${WORK}/${a} ha)
  file(SHA256 ${WORK}/${b} hb)
  if(NOT ha STREQUAL hb)
    message(SEND_ERROR "FAIL: ${a} and ${b} differ")
  endif()
endfunction()

# A 6 x 5 x 2 MET_UCHAR volume, every voxel 100 ('d'), but one stiff column (200, 0xC8 is not text:
# use 'x' = 120). Index axis x points along world +y, axis y along world -x, z along z; ITK's
# TransformMatrix lists those axis directions one after another.
set(M "0 1 0 -1 0 0 0 0 1")
string(REPEAT "d" 60 raw)
string(SUBSTRING "${raw}" 0 20 a)
string(SUBSTRING "${raw}" 21 39 b)
set(raw "${a}x${b}")
file(WRITE ${WORK}/rot.raw "${raw}")
file(WRITE ${WORK}/rot.mhd "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
     "TransformMatrix = ${M}\nOffset = 10 20 30\nElementSpacing = 0.5 2 1\nDimSize = 6 5 2\n"
     "ElementType = MET_UCHAR\nElementDataFile = rot.raw\n")

# Voxel (1,1,0) lies at origin + D (0.5, 2, 0) = (10 - 2, 20 + 0.5, 30); voxel (4,3,1) at
# (10 - 6, 20 + 2, 31). In the identity's reading these world points lie far outside the grid.
file(WRITE ${WORK}/seeds-voxel.csv "1,1,0\n4,3,1\n")
file(WRITE ${WORK}/seeds-world.csv "8,20.5,30\n4.2,21.9,31.1\n")

run(voxel 0 voronoi --stiffness rot.mhd --seeds seeds-voxel.csv --backend seq --out out-voxel)
run(world 0 voronoi --stiffness rot.mhd --seeds seeds-world.csv --world --backend seq --out out-world)
same(out-voxel/label.raw out-world/label.raw)
same(out-voxel/distance.raw out-world/distance.raw)
foreach(f distance.mhd label.mhd)
  has(out-world/${f} "TransformMatrix = ${M}\n")
  has(out-world/${f} "Offset = 10 20 30\n")
  has(out-world/${f} "ElementSpacing = 0.5 2 1\n")
endforeach()
has(out-world/voronoi.vti "Direction=\"0 -1 0 1 0 0 0 0 1\"")
has(out-world/voronoi.vti "Origin=\"10 20 30\"")

# a world seed outside the rotated grid names its line
file(WRITE ${WORK}/seeds-outside.csv "8,20.5,30\n10,19,30\n")
run(outside 2 voronoi --stiffness rot.mhd --seeds seeds-outside.csv --world --backend seq --out out-outside)
string(FIND "${ERR_outside}" "seeds-outside.csv:2" at)
if(at EQUAL -1)
  message(SEND_ERROR "FAIL: outside: the error does not name line 2: ${ERR_outside}")
endif()

# shape functions: every MetaImage and .vti output carries the matrix; --at --world points are the
# voxels they name
run(shape 0 shape-functions --stiffness rot.mhd --seeds seeds-world.csv --world --method sibson --backend seq
    --out out-shape)
foreach(f distance.mhd label.mhd indices.mhd weights.mhd indices_sofa_planar.mhd weights_sofa_planar.mhd)
  has(out-shape/${f} "TransformMatrix = ${M}\n")
endforeach()
has(out-shape/weights.vti "Direction=\"0 -1 0 1 0 0 0 0 1\"")
file(WRITE ${WORK}/at-voxel.csv "0,0,0\n2,3,1\n5,4,1\n")
# (2,3,1): (10 - 6, 20 + 1, 31); (5,4,1): (10 - 8, 20 + 2.5, 31)
file(WRITE ${WORK}/at-world.csv "10,20,30\n4,21,31\n2,22.5,31\n")
run(at_voxel 0 shape-functions --stiffness rot.mhd --seeds seeds-voxel.csv --method laplace --backend seq
    --at at-voxel.csv --out out-at-voxel)
run(at_world 0 shape-functions --stiffness rot.mhd --seeds seeds-world.csv --method laplace --backend seq
    --at at-world.csv --world --out out-at-world)
same(out-at-voxel/weights_at.csv out-at-world/weights_at.csv)

# the round trip: an output read back as input keeps the matrix
run(again 0 voronoi --stiffness out-world/distance.mhd --seeds seeds-world.csv --world --metric mean_cost
    --backend seq --out out-again)
has(out-again/label.mhd "TransformMatrix = ${M}\n")

# a singular or non-orthonormal matrix is bad input (exit 2), named in one line
file(WRITE ${WORK}/sing.mhd "NDims = 3\nTransformMatrix = 1 0 0 1 0 0 0 0 1\nDimSize = 6 5 2\n"
     "ElementType = MET_UCHAR\nElementDataFile = rot.raw\n")
run(singular 2 voronoi --stiffness sing.mhd --seeds seeds-voxel.csv --backend seq --out out-sing)
string(FIND "${ERR_singular}" "TransformMatrix: the direction matrix" at)
if(at EQUAL -1 OR NOT ERR_singular MATCHES "singular")
  message(SEND_ERROR "FAIL: singular: ${ERR_singular}")
endif()
file(WRITE ${WORK}/skew.mhd "NDims = 3\nTransformMatrix = 1 0 0 0.1 1 0 0 0 1\nDimSize = 6 5 2\n"
     "ElementType = MET_UCHAR\nElementDataFile = rot.raw\n")
run(skew 2 voronoi --stiffness skew.mhd --seeds seeds-voxel.csv --backend seq --out out-skew)
if(NOT ERR_skew MATCHES "not orthonormal")
  message(SEND_ERROR "FAIL: skew: ${ERR_skew}")
endif()
