# write_fingers_pgm(<path>): the two-finger picture of the branching-grid CLI tests, 12 x 24 pixels
# (P2): a palm (rows y = 0..3, stiffness 150) and two fingers up to y = 23, x = 0..4 (100) and
# x = 6..11 (200), apart by the empty column x = 5, which lies inside the coarse cells x = 4..7 of
# factor 4: a regular grid of those cells has one voxel for both fingers there.
function(write_fingers_pgm path)
  set(rows "")
  foreach(y RANGE 23)
    set(row "")
    foreach(x RANGE 11)
      if(y LESS 4)
        string(APPEND row " 150")
      elseif(x LESS 5)
        string(APPEND row " 100")
      elseif(x EQUAL 5)
        string(APPEND row " 0")
      else()
        string(APPEND row " 200")
      endif()
    endforeach()
    string(APPEND rows "${row}\n")
  endforeach()
  file(WRITE ${path} "P2\n12 24\n255\n${rows}")
endfunction()
