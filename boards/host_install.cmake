# What `cmake --install` puts under the prefix on a host-tools board, laid
# out as the build tree is (bin/, share/troupe/, lib/), so that a program
# finds its data the same way in both:
#
#   bin/                       every program of build/<preset>/bin/ (troupe,
#                              troupe-node, troupe-sim, ...); the examples'
#                              programs stay in the build tree
#   share/troupe/              what the programs read at run time (the viewer's
#                              page), and schemas/*.fbs: the wire protocol
#   include/troupe/wire/       the C++ client library's headers
#   lib/libtroupe_*.a          the client library (static) and what it links
#   lib/cmake/Troupe/          find_package(Troupe): Troupe::client
#   lib/pkgconfig/troupe-client.pc
#   lib/python3/dist-packages/troupe   the Python client
#
# Included at the end of the top-level CMakeLists.txt, when every program
# exists. boards/CMakeLists.txt installs troupe-node and makes the package.

# ---- Programs -----------------------------------------------------------------

# Every executable that lands in bin/, found by walking the folders: a new
# program is installed without being named here.
function(troupe_collect_programs dir out_var)
  set(found ${${out_var}})
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(t ${targets})
    get_target_property(type ${t} TYPE)
    get_target_property(out_dir ${t} RUNTIME_OUTPUT_DIRECTORY)
    get_target_property(src_dir ${t} SOURCE_DIR)
    if(type STREQUAL "EXECUTABLE" AND out_dir STREQUAL "${PROJECT_BINARY_DIR}/bin"
       AND NOT src_dir MATCHES "^${PROJECT_SOURCE_DIR}/examples(/|$)" AND NOT t STREQUAL "troupe-node")
      list(APPEND found ${t})
    endif()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub ${subdirs})
    troupe_collect_programs(${sub} found)
  endforeach()
  set(${out_var} ${found} PARENT_SCOPE)
endfunction()
set(_programs "")
troupe_collect_programs(${PROJECT_SOURCE_DIR} _programs)
install(TARGETS ${_programs} RUNTIME DESTINATION bin)

install(DIRECTORY ${TROUPE_SHARE_DIR}/ DESTINATION share/troupe)
install(FILES ${TROUPE_WIRE_SCHEMAS} DESTINATION share/troupe/schemas)

# ---- The C++ client library ---------------------------------------------------

# troupe_client and every library of this project it links, however deep
# (the export must hold them all).
function(troupe_link_closure target out_var)
  set(seen ${${out_var}})
  if(NOT TARGET ${target} OR target IN_LIST seen)
    return()
  endif()
  get_target_property(imported ${target} IMPORTED)
  if(imported)
    return()
  endif()
  list(APPEND seen ${target})
  get_target_property(links ${target} LINK_LIBRARIES)
  foreach(dep ${links})
    if(TARGET ${dep})
      troupe_link_closure(${dep} seen)
    endif()
  endforeach()
  set(${out_var} ${seen} PARENT_SCOPE)
endfunction()
set(_client_libs "")
troupe_link_closure(troupe_client _client_libs)
foreach(lib ${_client_libs})
  # Troupe::client, Troupe::wire, ...
  string(REGEX REPLACE "^troupe_" "" _export_name ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${_export_name})
  # Sanitized libraries need the sanitizers' runtime in every program.
  if(TROUPE_SANITIZE)
    target_link_options(${lib} INTERFACE -fsanitize=address,undefined)
  endif()
endforeach()
# The headers use C++20 (std::span); found from include/troupe as in the tree.
target_compile_features(troupe_wire INTERFACE cxx_std_20)
target_include_directories(troupe_wire INTERFACE $<INSTALL_INTERFACE:include/troupe>)
install(TARGETS ${_client_libs} EXPORT TroupeTargets ARCHIVE DESTINATION lib)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/wire/ DESTINATION include/troupe/wire
        FILES_MATCHING PATTERN "*.h"
        PATTERN "cli" EXCLUDE PATTERN "python" EXCLUDE PATTERN "record" EXCLUDE)
install(DIRECTORY ${TROUPE_GENERATED_DIR}/wire/schemas/ DESTINATION include/troupe/wire/schemas
        FILES_MATCHING PATTERN "*_generated.h")

include(CMakePackageConfigHelpers)
set(_cmake_dir lib/cmake/Troupe)
install(EXPORT TroupeTargets NAMESPACE Troupe:: DESTINATION ${_cmake_dir})
# The generated headers include FlatBuffers' (libflatbuffers-dev), and a
# library of the closure may link its target.
file(WRITE ${PROJECT_BINARY_DIR}/install/TroupeConfig.cmake
     "# find_package(Troupe): the C++ client library as Troupe::client.\n"
     "include(CMakeFindDependencyMacro)\n"
     "find_dependency(FlatBuffers CONFIG)\n"
     "include(\"\${CMAKE_CURRENT_LIST_DIR}/TroupeTargets.cmake\")\n")
write_basic_package_version_file(${PROJECT_BINARY_DIR}/install/TroupeConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/install/TroupeConfig.cmake
              ${PROJECT_BINARY_DIR}/install/TroupeConfigVersion.cmake
        DESTINATION ${_cmake_dir})

# pkg-config: the same library for builds without CMake. The libraries are
# listed users first (client before wire).
set(_pc_libs "")
foreach(lib ${_client_libs})
  string(APPEND _pc_libs " -l${lib}")
endforeach()
set(_pc_flags "")
if(TROUPE_SANITIZE)
  set(_pc_flags " -fsanitize=address,undefined")
endif()
file(WRITE ${PROJECT_BINARY_DIR}/install/troupe-client.pc
"prefix=\${pcfiledir}/../..
includedir=\${prefix}/include/troupe
libdir=\${prefix}/lib

Name: troupe-client
Description: Troupe's C++ client library (nodes, troupe-sim; one proxy per interface)
Version: ${PROJECT_VERSION}
Cflags: -std=c++20 -I\${includedir}${_pc_flags}
Libs: -L\${libdir}${_pc_libs}${_pc_flags}
")
install(FILES ${PROJECT_BINARY_DIR}/install/troupe-client.pc DESTINATION lib/pkgconfig)

# ---- The Python client ------------------------------------------------------

set(TROUPE_PYTHON_INSTALL_DIR lib/python3/dist-packages CACHE STRING
    "Where the Python package troupe is installed, under the prefix (Debian's python3 reads /usr/lib/python3/dist-packages)")
install(DIRECTORY ${TROUPE_PYTHON_DIR}/troupe DESTINATION ${TROUPE_PYTHON_INSTALL_DIR}
        PATTERN "__pycache__" EXCLUDE)
