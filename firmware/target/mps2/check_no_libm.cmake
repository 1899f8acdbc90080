# No libm transcendental in a board image: fails if the ELF's symbol table (defined or undefined) names one.
#   cmake -DNM=<nm> -DELF=<image.elf> [-DBUILD_DIR=<dir> -DBUILD_TARGET=<target> -DEXPECT_CAUGHT=<symbol>] -P this
# With EXPECT_CAUGHT it is the positive control: it builds BUILD_TARGET first and passes only if the check finds
# the named symbol, so a check that can no longer see libm fails too.
# The list: every C99 transcendental and the libm functions whose results differ between glibc and newlib, in their
# float, double and long double names, plus newlib's internal kernels (__ieee754_* except sqrt, __kernel_*).
# sqrt and floor-like functions are exact or correctly rounded everywhere and are allowed.
cmake_minimum_required(VERSION 3.25)
set(names sin cos tan sincos asin acos atan atan2 sinh cosh tanh asinh acosh atanh exp exp2 exp10 expm1 log log2
    log10 log1p logb pow hypot cbrt erf erfc lgamma tgamma remainder remquo fmod drem)
list(JOIN names "|" alternatives)
set(forbidden "^(${alternatives})[fl]?$|^__ieee754_|^__kernel_(sin|cos|tan|rem_pio2)")

if(DEFINED BUILD_TARGET)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} --target ${BUILD_TARGET}
                  RESULT_VARIABLE build_rc OUTPUT_VARIABLE build_out ERROR_VARIABLE build_out)
  if(NOT build_rc EQUAL 0)
    message(FATAL_ERROR "could not build ${BUILD_TARGET}:\n${build_out}")
  endif()
endif()
if(NOT EXISTS "${ELF}")
  message(FATAL_ERROR "${ELF} is missing: build the image first")
endif()
execute_process(COMMAND ${NM} "${ELF}" RESULT_VARIABLE nm_rc OUTPUT_VARIABLE nm_out ERROR_VARIABLE nm_err)
if(NOT nm_rc EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${ELF}: ${nm_err}")
endif()

string(REPLACE "\n" ";" lines "${nm_out}")
set(found "")
set(symbols 0)
set(saw_main FALSE)
foreach(line IN LISTS lines)
  string(REGEX MATCH "[^ \t]+$" symbol "${line}")
  if(symbol STREQUAL "")
    continue()
  endif()
  math(EXPR symbols "${symbols} + 1")
  if(symbol STREQUAL "main")
    set(saw_main TRUE)
  endif()
  if(symbol MATCHES "${forbidden}" AND NOT symbol MATCHES "^__ieee754_sqrt")
    list(APPEND found "${symbol}")
  endif()
endforeach()
if(NOT saw_main)
  message(FATAL_ERROR "no 'main' among the ${symbols} symbols of ${ELF}: the symbol table was not read")
endif()
list(REMOVE_DUPLICATES found)

if(DEFINED EXPECT_CAUGHT)
  if(NOT EXPECT_CAUGHT IN_LIST found)
    message(FATAL_ERROR "the check missed ${EXPECT_CAUGHT} in ${ELF} (found: '${found}')")
  endif()
  message("positive control: the check catches ${found} in ${ELF}")
  return()
endif()
if(found)
  message(FATAL_ERROR "libm transcendental symbols in ${ELF}: ${found}\n"
                      "use est::fmath (est/math/fmath.hpp): libm results differ between glibc and newlib")
endif()
message("${ELF}: ${symbols} symbols, no libm transcendental")
