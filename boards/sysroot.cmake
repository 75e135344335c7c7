# The target libraries of a cross build. The board's drivers name Debian
# packages (target_packages.cmake); they are unpacked into <build>/sysroot at
# configure time and searched like the cross compiler's own folders, so a
# driver's find_library(serial) or plain `serial` link works unchanged.
# Sets TROUPE_BOARD_RUNTIME_PACKAGES (what a .deb of the board depends on)
# and TROUPE_SYSROOT_LIB (for LD_LIBRARY_PATH under qemu-user; empty when
# no sysroot is needed).

set(_packages "")
foreach(_d ${TROUPE_BOARD_DRIVERS})
  list(APPEND _packages ${TROUPE_DRIVER_PACKAGES_${_d}})
endforeach()
if(TROUPE_SECURE)
  list(APPEND _packages ${TROUPE_SECURE_PACKAGES})
endif()
list(REMOVE_DUPLICATES _packages)
set(TROUPE_BOARD_RUNTIME_PACKAGES ${_packages})
list(FILTER TROUPE_BOARD_RUNTIME_PACKAGES EXCLUDE REGEX "-dev$")

set(TROUPE_SYSROOT_LIB "")
if(CMAKE_CROSSCOMPILING AND _packages)
  set(TROUPE_SYSROOT ${PROJECT_BINARY_DIR}/sysroot)
  execute_process(
    COMMAND sh ${PROJECT_SOURCE_DIR}/toolchains/prepare-sysroot.sh ${TROUPE_TARGET_DEB_ARCH} ${TROUPE_SYSROOT} ${_packages}
    RESULT_VARIABLE _rc)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "Board ${TROUPE_BOARD} needs the ${TROUPE_TARGET_DEB_ARCH} packages [${_packages}] "
                        "for its drivers; toolchains/prepare-sysroot.sh could not unpack them (see above)")
  endif()
  list(APPEND CMAKE_FIND_ROOT_PATH ${TROUPE_SYSROOT})
  include_directories(SYSTEM ${TROUPE_SYSROOT}/usr/include)
  set(TROUPE_SYSROOT_LIB ${TROUPE_SYSROOT}/usr/lib/${TROUPE_TARGET_TRIPLE})
  link_directories(${TROUPE_SYSROOT_LIB})
  # A static node needs the drivers' libraries as archives. Debian ships
  # some -dev packages without one (libserial-dev has only libserial.so):
  # say so here rather than let the linker say "cannot find -lserial".
  file(GLOB _archives ${TROUPE_SYSROOT_LIB}/*.a)
  if(TROUPE_STATIC AND NOT _archives)
    list(JOIN _packages ", " _names)
    message(FATAL_ERROR "Board ${TROUPE_BOARD} with TROUPE_STATIC: its drivers link libraries of ${_names}, "
                        "and these Debian packages hold no static archive (lib*.a) for ${TROUPE_TARGET_DEB_ARCH}. "
                        "Build those libraries as static archives into ${TROUPE_SYSROOT_LIB}, or build the board "
                        "without TROUPE_STATIC.")
  endif()
endif()
