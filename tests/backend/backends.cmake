# Hooks of the optional backends' test builds (backend/<name>.cmake, one per backend).
file(GLOB _gv_backend_hooks CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/*.cmake)
list(REMOVE_ITEM _gv_backend_hooks ${CMAKE_CURRENT_LIST_FILE})
foreach(h ${_gv_backend_hooks})
  include(${h})
endforeach()
