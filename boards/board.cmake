# Loads boards/${TROUPE_BOARD}/board.cmake, which is data: the list of drivers
# compiled in, and a few build switches. Everything else about a board
# follows from that list.
#
# A board file sets:
#   BOARD_DRIVERS          driver folder names under drivers/, one a line
#   BOARD_TOOLCHAIN        default toolchain: a file under toolchains/ without
#                          .cmake, or "native" (read before project(), by
#                          boards/toolchain.cmake)
#   BOARD_CONFIG_FORMAT    "json" (the node parses JSON configs at run time) or
#                          "binary" (configs are compiled by flatc at build time
#                          and the node carries no parser)
#   BOARD_HOST_TOOLS       ON to also build the client, CLI, simulator and tests
#   BOARD_NODE_CONFIGS     node configs (JSON, relative to the board folder);
#                          the first is the one the bundle's service runs
#   BOARD_BUILD_TYPE       CMAKE_BUILD_TYPE when the command line gives none
#   BOARD_COMPILE_OPTIONS  compile options of every target
#   BOARD_LINK_OPTIONS     link options of every program
#   BOARD_LTO              ON for link-time optimisation
#   BOARD_STATIC           ON to link the programs fully statically (glibc,
#                          libstdc++ and libgcc from the cross toolchain's
#                          own static archives): the node then runs on any
#                          Linux of its architecture, whatever its userland.
#                          -DTROUPE_STATIC=ON|OFF overrides it.
#   BOARD_SECURE           ON to build troupe-node with secure sessions
#                          (Noise IK on libsodium, wire/noise): a config with
#                          "key" and "clients" then serves only those clients.
#                          The target's libsodium comes into the sysroot
#                          (boards/target_packages.cmake). Host-tool boards
#                          always have them. -DTROUPE_SECURE=ON|OFF overrides it.
# The small boards share theirs in boards/small.cmake.

# boards/toolchain.cmake checked that the board exists, before project().
set(TROUPE_BOARD_DIR ${CMAKE_CURRENT_LIST_DIR}/${TROUPE_BOARD})

set(BOARD_DRIVERS "")
set(BOARD_TOOLCHAIN native)
set(BOARD_CONFIG_FORMAT "json")
set(BOARD_HOST_TOOLS OFF)
set(BOARD_NODE_CONFIGS "")
set(BOARD_BUILD_TYPE "")
set(BOARD_COMPILE_OPTIONS "")
set(BOARD_LINK_OPTIONS "")
set(BOARD_LTO OFF)
set(BOARD_STATIC OFF)
set(BOARD_SECURE OFF)
include(${TROUPE_BOARD_DIR}/board.cmake)

set(TROUPE_BOARD_DRIVERS ${BOARD_DRIVERS})
set(TROUPE_BOARD_CONFIG_FORMAT ${BOARD_CONFIG_FORMAT})
set(TROUPE_BOARD_HOST_TOOLS ${BOARD_HOST_TOOLS})
set(TROUPE_BOARD_NODE_CONFIGS ${BOARD_NODE_CONFIGS})
if(CMAKE_CROSSCOMPILING)
  set(_target ${TROUPE_TARGET_TRIPLE})
else()
  set(_target "native ${CMAKE_SYSTEM_PROCESSOR}")
endif()
message(STATUS "Board ${TROUPE_BOARD} (${_target}): drivers [${TROUPE_BOARD_DRIVERS}], configs ${TROUPE_BOARD_CONFIG_FORMAT}")

if(NOT CMAKE_BUILD_TYPE AND BOARD_BUILD_TYPE)
  set(CMAKE_BUILD_TYPE ${BOARD_BUILD_TYPE} CACHE STRING "Build type (from boards/${TROUPE_BOARD})" FORCE)
endif()
add_compile_options(${BOARD_COMPILE_OPTIONS})
add_link_options(${BOARD_LINK_OPTIONS})

# Static programs. Why glibc and not musl: Debian's musl (musl-tools,
# musl-dev) is built for the host architecture only, has no powerpc at all
# (no archive), and Debian's libstdc++ is compiled against glibc, so a C++
# program on musl would need a libstdc++ of its own. The cross toolchains'
# libc6-dev-<arch>-cross and libstdc++-12-dev-<arch>-cross already hold
# libc.a and libstdc++.a for every target. What glibc static costs: its
# stdio, locale and malloc come along (boards/README.md has the sizes), and
# looking up a host name (getaddrinfo with a name, not a number) would load
# NSS modules of the same glibc at run time, which a foreign system lacks:
# give a static node numeric listen addresses.
set(TROUPE_STATIC ${BOARD_STATIC} CACHE BOOL "Link troupe-node fully statically (default: the board's BOARD_STATIC)")
if(TROUPE_STATIC)
  # Executables only: a shared library (the tests' preloaded allocation
  # counter) cannot be static, and a static node loads none anyway.
  string(APPEND CMAKE_EXE_LINKER_FLAGS " -static")
  message(STATUS "Board ${TROUPE_BOARD}: programs linked statically (TROUPE_STATIC)")
endif()
# Secure sessions: the board's switch, or the command line's. The host-tool
# boards build clients and tests of secure sessions, so their node has them
# too.
set(TROUPE_SECURE ${BOARD_SECURE} CACHE BOOL "Build troupe-node with secure sessions (default: the board's BOARD_SECURE)")
if(TROUPE_BOARD_HOST_TOOLS)
  set(TROUPE_NODE_SECURE ON)
else()
  set(TROUPE_NODE_SECURE ${TROUPE_SECURE})
endif()
if(BOARD_LTO AND NOT TROUPE_SANITIZE)
  include(CheckIPOSupported)
  check_ipo_supported(RESULT _lto OUTPUT _why LANGUAGES CXX)
  if(_lto)
    set(CMAKE_INTERPROCEDURAL_OPTIMIZATION ON)
  else()
    message(WARNING "Board ${TROUPE_BOARD} asks for link-time optimisation, which this compiler lacks: ${_why}")
  endif()
endif()

include(${CMAKE_CURRENT_LIST_DIR}/target_packages.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/sysroot.cmake)

# What the board's driver list turns into, written at configure time:
#  - driver_options.fbs: the union of the drivers' option tables, which the
#    node config schema (runtime/config.fbs) includes. A config naming a
#    driver the board lacks is then refused by name.
#  - driver_table.cc: the table of driver factories troupe-node looks up.
# Driver <d> lives in drivers/<d>/, defines table `Options` in namespace
# troupe.drivers.<d> (drivers/<d>/<d>.fbs) and the factory
# troupe::drivers::<d>::kEntry.
# troupe_driver_options_fbs(<board> <out.fbs> <driver>...): writes the union
# of those drivers' option tables, as config.fbs includes it. Also used for
# the other boards' schemas, which `troupe config compile` carries.
function(troupe_driver_options_fbs board out)
  set(fbs "// Generated from boards/${board}/board.cmake; do not edit.\n")
  set(union "")
  foreach(d ${ARGN})
    if(NOT EXISTS ${PROJECT_SOURCE_DIR}/drivers/${d}/${d}.fbs)
      message(FATAL_ERROR "Board ${board} lists driver '${d}', but drivers/${d}/${d}.fbs does not exist")
    endif()
    string(APPEND fbs "include \"${d}.fbs\";\n")
    string(APPEND union "  ${d}: troupe.drivers.${d}.Options,\n")
  endforeach()
  string(APPEND fbs "\nnamespace troupe.config;\n\n/// The drivers of board ${board}.\nunion DriverOptions {\n${union}}\n")
  file(CONFIGURE OUTPUT ${out} CONTENT "${fbs}")
endfunction()

set(_decls "")
set(_entries "")
foreach(_d ${TROUPE_BOARD_DRIVERS})
  string(APPEND _decls "namespace troupe::drivers::${_d} { extern const DriverEntry kEntry; }\n")
  string(APPEND _entries "    &troupe::drivers::${_d}::kEntry,\n")
endforeach()
file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/generated/runtime)
set(TROUPE_DRIVER_OPTIONS_FBS ${PROJECT_BINARY_DIR}/generated/runtime/driver_options.fbs)
troupe_driver_options_fbs(${TROUPE_BOARD} ${TROUPE_DRIVER_OPTIONS_FBS} ${TROUPE_BOARD_DRIVERS})
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
