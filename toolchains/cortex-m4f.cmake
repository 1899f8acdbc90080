# Cortex-M4F (single-precision FPv4), run on qemu's mps2-an386 board.
set(EST_BOARD cortex-m4f)
set(EST_QEMU_MACHINE mps2-an386)
set(EST_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
