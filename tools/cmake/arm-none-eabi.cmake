# Toolchain file for the Cortex-M4F build (STM32F4-class ECU, QEMU mps2-an386).
# Debian 12: gcc-arm-none-eabi + libnewlib-arm-none-eabi.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "objcopy")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "size")
# Static libraries only while CMake probes the compiler: there is no OS to link against.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(TV_M4F_FLAGS "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
set(CMAKE_C_FLAGS_INIT "${TV_M4F_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${TV_M4F_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_ASM_FLAGS_INIT "${TV_M4F_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${TV_M4F_FLAGS} -Wl,--gc-sections")
# The optimisation level is the preset's (CMakePresets.json, m4f: -O3 -DNDEBUG). An -O2 here was
# followed by the -O3 -DNDEBUG that CMake appends for GCC, so every image was -O3 while the
# documents said -O2; the preset now says what is built.

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
