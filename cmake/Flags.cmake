# Floating-point rules for a bit-exact reference.
#
#  * -ffp-contract=off: a*b+c must be two roundings, never one fused multiply-add; GL blending is
#    "product, product, add" and any contraction changes stored bits.
#  * no unsafe math optimisations of any kind (GCC's "fast math" family): NaN, inf, signed zero
#    and denormals are data here; associative and reciprocal rewrites are switched off explicitly.
#  * F16C (x86-64, every CPU since 2012): fp32<->fp16 conversion in one instruction with an
#    explicit rounding mode. With OITREF_F16C=OFF the portable C++ converter is used instead; a
#    test proves both give the same bits for every input, so the choice only changes speed.
#    The command-line tool checks at start-up that the CPU has F16C when it was built with it.

add_library(oitref_flags INTERFACE)
# The floating-point options and F16C travel with the installed package (its headers' inline
# arithmetic must round as the library's does); the warnings stay with this build.
target_compile_options(oitref_flags INTERFACE
  -ffp-contract=off -fno-associative-math -fno-reciprocal-math
  $<BUILD_INTERFACE:-Wall -Wextra>)
# GCC notes, once per file, that a 32-byte vector passed by value is passed differently by code
# built with and without AVX (the portable build has none). oitref's lanes (lanes.h, the blend and
# moment kernels) pass by value only between functions of one build; the AVX2 kernels chosen at
# run time take and give theirs by reference. The note says nothing about this code.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(oitref_flags INTERFACE -Wno-psabi)
endif()
# GCC 12 at -O3 warns -Wrestrict inside std::string concatenation (a false positive, GCC bug
# 105651, fixed in GCC 13).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(oitref_flags INTERFACE -Wno-restrict)
endif()

include(CheckCXXCompilerFlag)
set(_f16c_default OFF)
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64|amd64")
  check_cxx_compiler_flag(-mf16c OITREF_COMPILER_HAS_F16C)
  if(OITREF_COMPILER_HAS_F16C)
    set(_f16c_default ON)
  endif()
endif()
option(OITREF_F16C "Use the x86 F16C instructions for fp16 conversion (same bits as the portable path)" ${_f16c_default})
if(OITREF_F16C)
  # -mf16c implies AVX encodings; it never enables FMA, and -ffp-contract=off forbids fusing anyway.
  target_compile_options(oitref_flags INTERFACE -mf16c)
  target_compile_definitions(oitref_flags INTERFACE OITREF_HAVE_F16C=1)
endif()
message(STATUS "oitref: F16C fast path ${OITREF_F16C}")

# Sanitizers (CI): OITREF_SANITIZE is a -fsanitize= list, e.g. "address,undefined" or "thread".
# UBSan stops at the first report so a CI run cannot pass over one. OITREF_FUZZ adds the
# coverage instrumentation libFuzzer needs (clang only) and builds tests/fuzz.
set(OITREF_SANITIZE "" CACHE STRING "Build with -fsanitize=<list> (address,undefined | thread)")
option(OITREF_FUZZ "Build the libFuzzer targets in tests/fuzz (clang)" OFF)
set(_sanitize "${OITREF_SANITIZE}")
if(OITREF_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "OITREF_FUZZ needs clang (CXX=clang++): libFuzzer is part of clang")
  endif()
  set(_sanitize "fuzzer-no-link,${_sanitize}")
endif()
if(_sanitize)
  string(REGEX REPLACE ",$" "" _sanitize "${_sanitize}")
  target_compile_options(oitref_flags INTERFACE -fsanitize=${_sanitize} -fno-omit-frame-pointer -g)
  if(_sanitize MATCHES "undefined")
    target_compile_options(oitref_flags INTERFACE -fno-sanitize-recover=undefined)
  endif()
  target_link_options(oitref_flags INTERFACE -fsanitize=${_sanitize})
  if(_sanitize MATCHES "thread")
    target_compile_definitions(oitref_flags INTERFACE OITREF_STD_THREADS=1)  # see src/core/pipeline/renderer.cpp
  endif()
  message(STATUS "oitref: sanitizers ${_sanitize}")
endif()
