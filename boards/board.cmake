# Loads boards/${TROUPE_BOARD}/board.cmake, which is data: the list of drivers
# compiled in, and a few build switches. Everything else about a board
# follows from that list.
#
# A board file sets:
#   BOARD_DRIVERS        driver folder names under drivers/
#   BOARD_CONFIG_FORMAT  "json" (the node parses JSON configs at run time) or
#                        "binary" (configs are compiled by flatc at build time
#                        and the node carries no parser)
#   BOARD_HOST_TOOLS     ON to also build the client, CLI, simulator and tests
#   BOARD_NODE_CONFIGS   example node configs (JSON, relative to the board folder)

set(TROUPE_BOARD_DIR ${CMAKE_CURRENT_LIST_DIR}/${TROUPE_BOARD})
if(NOT EXISTS ${TROUPE_BOARD_DIR}/board.cmake)
  file(GLOB _boards RELATIVE ${CMAKE_CURRENT_LIST_DIR} ${CMAKE_CURRENT_LIST_DIR}/*/board.cmake)
  string(REPLACE "/board.cmake" "" _boards "${_boards}")
  message(FATAL_ERROR "No board '${TROUPE_BOARD}'. Boards: ${_boards}")
endif()

set(BOARD_DRIVERS "")
set(BOARD_CONFIG_FORMAT "json")
set(BOARD_HOST_TOOLS OFF)
set(BOARD_NODE_CONFIGS "")
include(${TROUPE_BOARD_DIR}/board.cmake)

set(TROUPE_BOARD_DRIVERS ${BOARD_DRIVERS})
set(TROUPE_BOARD_CONFIG_FORMAT ${BOARD_CONFIG_FORMAT})
set(TROUPE_BOARD_HOST_TOOLS ${BOARD_HOST_TOOLS})
message(STATUS "Board ${TROUPE_BOARD}: drivers [${TROUPE_BOARD_DRIVERS}], configs ${TROUPE_BOARD_CONFIG_FORMAT}")

# What the board's driver list turns into, written at configure time:
#  - driver_options.fbs: the union of the drivers' option tables, which the
#    node config schema (runtime/config.fbs) includes. A config naming a
#    driver the board lacks is then refused by name.
#  - driver_table.cc: the table of driver factories troupe-node looks up.
# Driver <d> lives in drivers/<d>/, defines table `Options` in namespace
# troupe.drivers.<d> (drivers/<d>/<d>.fbs) and the factory
# troupe::drivers::<d>::kEntry.
set(_fbs "// Generated from boards/${TROUPE_BOARD}/board.cmake; do not edit.\n")
set(_union "")
set(_decls "")
set(_entries "")
foreach(_d ${TROUPE_BOARD_DRIVERS})
  if(NOT EXISTS ${PROJECT_SOURCE_DIR}/drivers/${_d}/${_d}.fbs)
    message(FATAL_ERROR "Board ${TROUPE_BOARD} lists driver '${_d}', but drivers/${_d}/${_d}.fbs does not exist")
  endif()
  string(APPEND _fbs "include \"${_d}.fbs\";\n")
  string(APPEND _union "  ${_d}: troupe.drivers.${_d}.Options,\n")
  string(APPEND _decls "namespace troupe::drivers::${_d} { extern const DriverEntry kEntry; }\n")
  string(APPEND _entries "    &troupe::drivers::${_d}::kEntry,\n")
endforeach()
string(APPEND _fbs "\nnamespace troupe.config;\n\n/// The drivers of board ${TROUPE_BOARD}.\nunion DriverOptions {\n${_union}}\n")
file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/generated/runtime)
set(TROUPE_DRIVER_OPTIONS_FBS ${PROJECT_BINARY_DIR}/generated/runtime/driver_options.fbs)
file(CONFIGURE OUTPUT ${TROUPE_DRIVER_OPTIONS_FBS} CONTENT "${_fbs}")
set(TROUPE_DRIVER_TABLE_CC ${PROJECT_BINARY_DIR}/generated/runtime/driver_table.cc)
file(CONFIGURE OUTPUT ${TROUPE_DRIVER_TABLE_CC} CONTENT
"// Generated from boards/${TROUPE_BOARD}/board.cmake; do not edit.
#include \"runtime/driver.h\"

${_decls}
namespace troupe {
const DriverEntry* const kBoardDrivers[] = {
${_entries}    nullptr,
};
const char* const kBoardName = \"${TROUPE_BOARD}\";
}  // namespace troupe
")
