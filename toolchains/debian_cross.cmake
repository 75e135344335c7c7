# Shared part of the toolchain files: Debian's cross compilers
# (g++-<triple>), whose C library and libstdc++ live in /usr/<triple>.
# A toolchain file sets TROUPE_TARGET_TRIPLE, TROUPE_TARGET_PROCESSOR,
# TROUPE_TARGET_DEB_ARCH and TROUPE_TARGET_QEMU, then includes this file.
#
# Target libraries that Debian does not install for cross builds (libserial:
# its -dev package is not Multi-Arch) are unpacked into a sysroot folder of
# the build tree by toolchains/prepare-sysroot.sh; boards/board.cmake adds it
# to the search paths.

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR ${TROUPE_TARGET_PROCESSOR})
set(CMAKE_LIBRARY_ARCHITECTURE ${TROUPE_TARGET_TRIPLE})

set(CMAKE_C_COMPILER ${TROUPE_TARGET_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${TROUPE_TARGET_TRIPLE}-g++)

# Headers and libraries come from the target's folders only, never from the
# host's /usr/include and /usr/lib; programs (flatc) from the host.
set(CMAKE_FIND_ROOT_PATH /usr/${TROUPE_TARGET_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Runs target programs (tests, `cmake -E env`) under qemu-user with the
# target's loader and libraries.
set(CMAKE_CROSSCOMPILING_EMULATOR ${TROUPE_TARGET_QEMU} -L /usr/${TROUPE_TARGET_TRIPLE})

# The project reads these (boards/board.cmake, bundles); try_compile projects
# get them too.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES TROUPE_TARGET_TRIPLE TROUPE_TARGET_DEB_ARCH TROUPE_TARGET_QEMU)
