# The Depends: of a board's .deb, computed from troupe-node itself when CPack
# packs it (CPACK_PROJECT_CONFIG_FILE runs this script for every generator;
# only the DEB one needs it). A package must say what the binary needs, or
# apt installs it where it cannot run: on an older libc the loader refuses
# the binary at every start ("version `GLIBC_2.35' not found").
#
# Why not dpkg-shlibdeps: it finds a library's package through dpkg's
# database of the machine it runs on, and a cross build's target libraries
# are not installed there (Debian's cross packages carry only coarse shlibs
# floors, "libc6 (>= 2.36)", and powerpc has no archive at all). The binary
# says more precisely what it needs:
#  - each NEEDED library is mapped to its Debian package by the shlibs files
#    of the toolchain's cross packages, of the board's sysroot packages
#    (toolchains/prepare-sysroot.sh keeps them) or, natively, of the package
#    dpkg says owns the library;
#  - each version it needs from a library (readelf's version needs: GLIBC_2.35
#    from libc.so.6, GLIBCXX_3.4.29 from libstdc++.so.6, GCC_3.5 from
#    libgcc_s.so.1) gives a floor: glibc's tags are its release numbers, and
#    the other tags are looked up in the Debian symbols files of those
#    libraries, whose "TAG@TAG VERSION" lines give the package version that
#    brought each tag;
#  - a library without version tags gets the floor of its shlibs entry.
# A statically linked node needs no library: its package depends on nothing.
#
# Set by boards/CMakeLists.txt in the generated CPack project file:
#   TROUPE_DEB_NODE           the troupe-node to read
#   TROUPE_DEB_READELF        readelf of the target
#   TROUPE_DEB_SHLIBS         shlibs files (soname -> package) to search first
#   TROUPE_DEB_SYMBOLS        Debian symbols files (version tag -> floor)
#   TROUPE_DEB_NATIVE         ON when the node runs on the build machine: other
#                             libraries are looked up with dpkg-query -S
#   TROUPE_DEB_TRIPLE         the multiarch folder of its libraries
#   TROUPE_DEB_EXTRA_DEPENDS  dependencies added as they are

if(NOT CPACK_GENERATOR STREQUAL "DEB" OR NOT DEFINED TROUPE_DEB_NODE)
  return()
endif()

function(_troupe_deb_fail why)
  message(FATAL_ERROR "Depends of ${CPACK_PACKAGE_NAME}: ${why}")
endfunction()

execute_process(COMMAND ${TROUPE_DEB_READELF} --wide --dynamic --version-info ${TROUPE_DEB_NODE}
                OUTPUT_VARIABLE _elf RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  _troupe_deb_fail("${TROUPE_DEB_READELF} cannot read ${TROUPE_DEB_NODE}")
endif()
string(REPLACE "\n" ";" _lines "${_elf}")

# NEEDED sonames, and per soname the version tags needed from it.
set(_sonames "")
set(_file "")
set(_in_needs OFF)
foreach(_line IN LISTS _lines)
  if(_line MATCHES "\\(NEEDED\\)[^[]*\\[([^]]+)\\]")
    list(APPEND _sonames ${CMAKE_MATCH_1})
  elseif(_line MATCHES "^Version needs section")
    set(_in_needs ON)
  elseif(_line MATCHES "^Version (symbols|definition) section")
    set(_in_needs OFF)
  elseif(_in_needs AND _line MATCHES "File: ([^ ]+)")
    set(_file ${CMAKE_MATCH_1})
  elseif(_in_needs AND _file AND _line MATCHES "Name: ([^ ]+)")
    list(APPEND _tags_${_file} ${CMAKE_MATCH_1})
  endif()
endforeach()

# "Version tag -> floor" from the symbols files: lines " TAG@TAG VERSION".
foreach(_symbols IN LISTS TROUPE_DEB_SYMBOLS)
  file(STRINGS ${_symbols} _defs REGEX "^ ([A-Za-z0-9_.]+)@([A-Za-z0-9_.]+) [0-9]")
  foreach(_def IN LISTS _defs)
    # The first file that dates a tag wins: the target's come first.
    if(_def MATCHES "^ ([A-Za-z0-9_.]+)@([A-Za-z0-9_.]+) ([^ ]+)" AND CMAKE_MATCH_1 STREQUAL CMAKE_MATCH_2)
      set(_tag ${CMAKE_MATCH_1})
      if(NOT DEFINED _floor_${_tag})
        set(_floor_${_tag} ${CMAKE_MATCH_3})
      endif()
    endif()
  endforeach()
endforeach()

# The larger of two Debian versions (dpkg's own ordering).
function(_troupe_deb_max out a b)
  if(NOT b)
    set(${out} "${a}" PARENT_SCOPE)
    return()
  endif()
  if(NOT a)
    set(${out} ${b} PARENT_SCOPE)
    return()
  endif()
  execute_process(COMMAND dpkg --compare-versions ${b} gt ${a} RESULT_VARIABLE _gt)
  if(_gt EQUAL 0)
    set(${out} ${b} PARENT_SCOPE)
  else()
    set(${out} ${a} PARENT_SCOPE)
  endif()
endfunction()

# The shlibs entry of a soname: "libc.so.6" is "libc 6", "libfoo-1.2.so" is
# "libfoo 1.2". Sets <out>_package and <out>_floor (may be empty).
function(_troupe_deb_shlibs out soname)
  # (Two if()s: a failed MATCHES after an OR clears the groups of the first.)
  if(soname MATCHES "^(.+)\\.so\\.(.+)$")
    set(_key "${CMAKE_MATCH_1} ${CMAKE_MATCH_2} ")
  elseif(soname MATCHES "^(.+)-([0-9.]+)\\.so$")
    set(_key "${CMAKE_MATCH_1} ${CMAKE_MATCH_2} ")
  else()
    return()
  endif()
  set(_files ${TROUPE_DEB_SHLIBS})
  if(TROUPE_DEB_NATIVE)
    # The package that owns the library of the node's architecture on this
    # machine (not /lib32's or another multiarch folder's), and its shlibs.
    execute_process(COMMAND dpkg-query -S "*/${TROUPE_DEB_TRIPLE}/${soname}" OUTPUT_VARIABLE _owners ERROR_QUIET)
    if(_owners MATCHES "^([^:,]+)")
      execute_process(COMMAND dpkg-query --control-path ${CMAKE_MATCH_1} shlibs
                      OUTPUT_VARIABLE _path OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      list(APPEND _files ${_path})
    endif()
  endif()
  foreach(_f IN LISTS _files)
    if(NOT EXISTS "${_f}")
      continue()
    endif()
    file(STRINGS ${_f} _entries)
    foreach(_entry IN LISTS _entries)
      string(FIND "${_entry}" "${_key}" _at)
      # "[udeb: ]libc 6 libc6:armhf (>= 2.36)"
      if(_at EQUAL 0 AND _entry MATCHES "^[^ ]+ [^ ]+ ([a-z0-9][a-z0-9+.-]+)(:[a-z0-9]+)? *(\\(>= *([^)]+)\\))?")
        set(${out}_package ${CMAKE_MATCH_1} PARENT_SCOPE)
        set(${out}_floor "${CMAKE_MATCH_4}" PARENT_SCOPE)
        return()
      endif()
    endforeach()
  endforeach()
endfunction()

set(_depends "")
set(_packages "")
foreach(_soname IN LISTS _sonames)
  unset(_lib_package)
  unset(_lib_floor)
  _troupe_deb_shlibs(_lib ${_soname})
  if(NOT _lib_package)
    _troupe_deb_fail("troupe-node needs ${_soname}, and no shlibs file names its package "
                     "(a driver's library belongs in boards/target_packages.cmake)")
  endif()
  set(_floor "")
  if(DEFINED _tags_${_soname})
    foreach(_tag IN LISTS _tags_${_soname})
      if(_tag MATCHES "^GLIBC_([0-9][0-9.]*)$")
        _troupe_deb_max(_floor "${_floor}" ${CMAKE_MATCH_1})
      elseif(DEFINED _floor_${_tag})
        _troupe_deb_max(_floor "${_floor}" ${_floor_${_tag}})
      else()
        _troupe_deb_fail("troupe-node needs version ${_tag} of ${_soname}, which no symbols file "
                         "[${TROUPE_DEB_SYMBOLS}] dates")
      endif()
    endforeach()
  else()
    set(_floor "${_lib_floor}")
  endif()
  # Several sonames of one package (libc.so.6, libm.so.6): the highest floor.
  _troupe_deb_max(_dep_${_lib_package} "${_dep_${_lib_package}}" "${_floor}")
  list(APPEND _packages ${_lib_package})
endforeach()
list(REMOVE_DUPLICATES _packages)
foreach(_p IN LISTS _packages)
  if(_dep_${_p})
    list(APPEND _depends "${_p} (>= ${_dep_${_p}})")
  else()
    list(APPEND _depends ${_p})
  endif()
endforeach()
list(APPEND _depends ${TROUPE_DEB_EXTRA_DEPENDS})
list(JOIN _depends ", " CPACK_DEBIAN_PACKAGE_DEPENDS)
message(STATUS "${CPACK_PACKAGE_NAME} Depends: ${CPACK_DEBIAN_PACKAGE_DEPENDS}")
