# Included before project(): picks the compiler a board builds with. A board
# names its default toolchain (BOARD_TOOLCHAIN, a file under toolchains/
# without ".cmake", or "native" for the host compiler), so
#   cmake -S . -B build/pioneer-p3dx -G Ninja -DTROUPE_BOARD=pioneer-p3dx
# cross-builds for armhf. -DTROUPE_TOOLCHAIN=<name> builds a board with
# another toolchain (the core for every target); an explicit
# -DCMAKE_TOOLCHAIN_FILE wins over both.

set(TROUPE_BOARD "host" CACHE STRING "Board to build: a folder under boards/")
set(TROUPE_TOOLCHAIN "" CACHE STRING
    "Toolchain: a file under toolchains/ without .cmake, or 'native'; empty: the board's default")

if(NOT EXISTS ${CMAKE_CURRENT_LIST_DIR}/${TROUPE_BOARD}/board.cmake)
  file(GLOB _boards RELATIVE ${CMAKE_CURRENT_LIST_DIR} ${CMAKE_CURRENT_LIST_DIR}/*/board.cmake)
  string(REPLACE "/board.cmake" "" _boards "${_boards}")
  message(FATAL_ERROR "No board '${TROUPE_BOARD}'. Boards: ${_boards}")
endif()

# The board file in a scope of its own: only its toolchain is wanted here.
function(_troupe_board_toolchain out)
  set(BOARD_TOOLCHAIN native)
  include(${CMAKE_CURRENT_LIST_DIR}/${TROUPE_BOARD}/board.cmake)
  set(${out} ${BOARD_TOOLCHAIN} PARENT_SCOPE)
endfunction()

if(TROUPE_TOOLCHAIN)
  set(_toolchain ${TROUPE_TOOLCHAIN})
else()
  _troupe_board_toolchain(_toolchain)
endif()

if(_toolchain STREQUAL "native")
  set(_toolchain_file "")
else()
  set(_toolchain_file ${CMAKE_CURRENT_LIST_DIR}/../toolchains/${_toolchain}.cmake)
  cmake_path(NORMAL_PATH _toolchain_file)
  if(NOT EXISTS ${_toolchain_file})
    file(GLOB _files RELATIVE ${CMAKE_CURRENT_LIST_DIR}/../toolchains ${CMAKE_CURRENT_LIST_DIR}/../toolchains/*-*.cmake)
    string(REPLACE ".cmake" "" _files "${_files}")
    message(FATAL_ERROR "No toolchain '${_toolchain}' (board ${TROUPE_BOARD}). Toolchains: native;${_files}")
  endif()
endif()

if(DEFINED TROUPE_CHOSEN_TOOLCHAIN)
  # The compiler of a build folder is fixed at its first configure.
  if(NOT TROUPE_CHOSEN_TOOLCHAIN STREQUAL _toolchain)
    message(FATAL_ERROR "This build folder uses toolchain '${TROUPE_CHOSEN_TOOLCHAIN}'; "
                        "board ${TROUPE_BOARD} with TROUPE_TOOLCHAIN='${TROUPE_TOOLCHAIN}' needs '${_toolchain}'. "
                        "Configure it in a fresh build folder.")
  endif()
elseif(NOT DEFINED CMAKE_TOOLCHAIN_FILE)
  # First configure of this build folder, no toolchain given: the board's.
  if(_toolchain_file)
    set(CMAKE_TOOLCHAIN_FILE ${_toolchain_file} CACHE FILEPATH "Chosen from boards/${TROUPE_BOARD}")
  endif()
  set(TROUPE_CHOSEN_TOOLCHAIN ${_toolchain} CACHE INTERNAL "")
endif()
