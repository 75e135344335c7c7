# Target libraries a driver links, as Debian packages of the target
# architecture: TROUPE_DRIVER_PACKAGES_<driver>. A cross build of a board
# listing the driver unpacks them into <build>/sysroot
# (toolchains/prepare-sysroot.sh); the packages not ending in -dev become
# dependencies of the board's .deb. Drivers that need only libc and kernel
# headers (kinematic, SocketCAN ones) have no entry.

# Secure sessions (BOARD_SECURE) link libsodium: the archive for static
# nodes is in the -dev package. powerpc has no Debian archive:
# prepare-sysroot.sh builds these two from Debian's source instead.
set(TROUPE_SECURE_PACKAGES libsodium-dev libsodium23)

set(TROUPE_DRIVER_PACKAGES_p2os libserial-dev libserial1)
set(TROUPE_DRIVER_PACKAGES_sicklms200 libserial-dev libserial1)
# ros2 links Cyclone DDS; the runtime packages are the library and what it
# loads (Debian 12's is built with iceoryx shared memory and OpenSSL). Cross
# builds of ros2 are untested: Cyclone's headers also want iceoryx's.
set(TROUPE_DRIVER_PACKAGES_ros2 cyclonedds-dev libddsc0debian libiceoryx-binding-c2 libiceoryx-posh2
    libiceoryx-hoofs2 libiceoryx-platform2 libacl1 libssl3)
