# End-to-end tests of `--cut MESH` on voronoi and shape-functions (docs/cli.md, "Cuts"), run by ctest
# as `cmake -P`:
#   -DGEOVORONOI=<path of the binary> -DWORK=<scratch folder> [-DBUILT=seq,thrust,cuda]
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/common.cmake)

# unreached(<dir> <expect TRUE/FALSE>): whether label.raw holds a -1
function(unreached dir expect)
  file(READ ${WORK}/${dir}/label.raw hex HEX)
  string(FIND "${hex}" "ffffffff" hole)
  if(hole EQUAL -1)
    set(got FALSE)
  else()
    set(got TRUE)
  endif()
  if(NOT got STREQUAL "${expect}")
    message(SEND_ERROR "FAIL: ${dir}: unreachable voxels ${got}, expected ${expect}")
  endif()
endfunction()

# A 12 x 10 x 1 slab of stiffness 122 ('z'), unit spacing, one seed at x = 1.
string(REPEAT "z" 120 values)
file(WRITE ${WORK}/slab.raw "${values}")
file(WRITE ${WORK}/slab.mhd "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
           "DimSize = 12 10 1\nElementSpacing = 1 1 1\nElementType = MET_UCHAR\nElementDataFile = slab.raw\n")
file(WRITE ${WORK}/seeds.csv "1,5,0\n")
file(WRITE ${WORK}/two.csv "1,5,0\n10,5,0\n")
# the plane x = 5.5 across the whole slab, as OBJ and as ASCII STL; a short blade that cuts nothing
# apart (y from 2 to 8)
file(WRITE ${WORK}/wall.obj "v 5.5 -5 -5\nv 5.5 20 -5\nv 5.5 20 5\nv 5.5 -5 5\nf 1 2 3\nf 1 3 4\n")
file(WRITE ${WORK}/wall.stl "solid wall\nfacet normal 1 0 0\nouter loop\nvertex 5.5 -5 -5\nvertex 5.5 20 -5\n"
           "vertex 5.5 20 5\nendloop\nendfacet\nfacet normal 1 0 0\nouter loop\nvertex 5.5 -5 -5\n"
           "vertex 5.5 20 5\nvertex 5.5 -5 5\nendloop\nendfacet\nendsolid wall\n")
file(WRITE ${WORK}/blade.obj "v 3.5 2 -5\nv 3.5 8 -5\nv 3.5 8 5\nv 3.5 2 5\nf 1 2 3 4\n")
file(WRITE ${WORK}/bad.obj "v 1 2 3\nf 1 2 7\n")
file(WRITE ${WORK}/wall.ply "ply\n")
set(S --stiffness slab.mhd --connectivity 26)

foreach(b ${BUILT})
  if(b STREQUAL "cuda")
    continue()  # needs a device
  endif()
  run(plain_${b} 0 voronoi ${S} --seeds seeds.csv --backend ${b} --out plain-${b})
  unreached(plain-${b} FALSE)
  # the wall separates the slab: the far side is unreachable, with either file format
  run(obj_${b} 0 voronoi ${S} --seeds seeds.csv --backend ${b} --cut wall.obj --out obj-${b})
  unreached(obj-${b} TRUE)
  run(stl_${b} 0 voronoi ${S} --seeds seeds.csv --backend ${b} --cut wall.stl --out stl-${b})
  file(READ ${WORK}/obj-${b}/label.raw a HEX)
  file(READ ${WORK}/stl-${b}/label.raw c HEX)
  if(NOT a STREQUAL c)
    message(SEND_ERROR "FAIL: ${b}: the OBJ and the STL wall give different labels")
  endif()
  # the blade alone leaves everything reachable but lengthens paths: distances differ from plain
  run(blade_${b} 0 voronoi ${S} --seeds seeds.csv --backend ${b} --cut blade.obj --out blade-${b})
  unreached(blade-${b} FALSE)
  file(READ ${WORK}/plain-${b}/distance.raw d0 HEX)
  file(READ ${WORK}/blade-${b}/distance.raw d1 HEX)
  if(d0 STREQUAL d1)
    message(SEND_ERROR "FAIL: ${b}: the blade changed no distance")
  endif()
  # repeated: blade and wall together
  run(both_${b} 0 voronoi ${S} --seeds seeds.csv --backend ${b} --cut blade.obj --cut wall.obj --out both-${b})
  unreached(both-${b} TRUE)
  # with a seed on each side every voxel is reached again, and shape functions run with the cut
  run(two_${b} 0 voronoi ${S} --seeds two.csv --backend ${b} --cut wall.obj --out two-${b})
  unreached(two-${b} FALSE)
  run(shape_${b} 0 shape-functions ${S} --seeds two.csv --backend ${b} --cut wall.obj --method sibson
      --out shape-${b})
  if(NOT EXISTS ${WORK}/shape-${b}/weights.mhd)
    message(SEND_ERROR "FAIL: shape_${b}: no weights.mhd")
  endif()
endforeach()

# results agree across the built CPU backends
if("thrust" IN_LIST BUILT)
  foreach(f label.raw distance.raw)
    file(READ ${WORK}/both-seq/${f} x HEX)
    file(READ ${WORK}/both-thrust/${f} y HEX)
    if(NOT x STREQUAL y)
      message(SEND_ERROR "FAIL: seq and thrust differ in ${f} with cuts")
    endif()
  endforeach()
endif()

# bad input: exit 2, one line naming the file
run(bad_mesh 2 voronoi ${S} --seeds seeds.csv --backend seq --cut bad.obj --out bad1)
one_line(bad_mesh "bad.obj")
run(bad_ext 2 voronoi ${S} --seeds seeds.csv --backend seq --cut wall.ply --out bad2)
one_line(bad_ext ".stl or .obj")
run(missing 2 voronoi ${S} --seeds seeds.csv --backend seq --cut nowhere.stl --out bad3)
one_line(missing "nowhere.stl")
run(twice_seeds 2 voronoi ${S} --seeds seeds.csv --seeds seeds.csv --backend seq --out bad4)
one_line(twice_seeds "given twice")
