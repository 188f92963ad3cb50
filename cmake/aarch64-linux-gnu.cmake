# Cross build for 64-bit ARM Linux on a Debian x86-64 machine, tests run
# under qemu-user (`make test-aarch64`; packages from
# `scripts/deps.sh --aarch64`: the cross compiler, qemu-user and the arm64
# builds of the libraries from Debian's multiarch archive).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# qemu-user cannot give persp-import its limits (it ignores RLIMIT_AS and
# refuses seccomp filters, which would break the emulator) nor start it
# from an emulated process: the emulated suite imports models in process
# (src/model/model.c), and the tests of the isolation run natively only.
set(PERSP_IMPORT_IN_PROCESS_DEFAULT ON CACHE BOOL "")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
# The arm64 .pc files, not the host's (multiarch keeps both under /usr).
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
# Without -L: the dynamic loader and libc are then the multiarch
# libc6:arm64 ones under /lib/aarch64-linux-gnu, the same build as the
# libraries beside them (the cross toolchain's own copy under
# /usr/aarch64-linux-gnu, mixed with those, hangs in pthread_create).
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64)
