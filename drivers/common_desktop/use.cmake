# include() this from a desktop driver's CMakeLists.txt to get the
# troupe_desktop library, whichever of those drivers the board lists.
if(NOT TARGET troupe_desktop)
  add_subdirectory(${CMAKE_CURRENT_LIST_DIR} ${PROJECT_BINARY_DIR}/drivers/common_desktop)
endif()
