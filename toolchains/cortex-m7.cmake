# Cortex-M7 (single-precision FPv5), run on qemu's mps2-an500 board.
set(EST_BOARD cortex-m7)
set(EST_QEMU_MACHINE mps2-an500)
set(EST_CPU_FLAGS "-mcpu=cortex-m7 -mthumb -mfloat-abi=hard -mfpu=fpv5-sp-d16")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
