# The firmware's rules, enforced by the build (DEVELOPERS.md, "Rules of the firmware").

# Determinism, for every translation unit of the project: host and target must produce the same bits, so no FMA
# contraction, no fast-math, and no host vectorization (AVX changes Eigen's summation order).
add_compile_options(-ffp-contract=off -fno-fast-math)
add_compile_definitions(EIGEN_DONT_VECTORIZE EIGEN_MPL2_ONLY)

set(EST_WARNINGS -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow -Wdouble-promotion -Werror)

# est_firmware_rules(<target>): the rules for code that is built for the board.
function(est_firmware_rules target)
  target_compile_options(${target} PRIVATE ${EST_WARNINGS}
    $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti -fno-threadsafe-statics>)
endfunction()

# est_host_warnings(<target>): host tools and tests get the same warnings, but keep exceptions (Catch2, CLI11).
function(est_host_warnings target)
  target_compile_options(${target} PRIVATE ${EST_WARNINGS})
endfunction()
