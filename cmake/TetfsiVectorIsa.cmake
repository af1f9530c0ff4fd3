# 256-bit vector instructions (AVX2 with FMA) for the particle passes of the MPM (fluid/mpm/), the
# hot loops of the MPM examples: tetfsi_use_vector_isa(target).
#
# TETFSI_AVX2 = AUTO (default): used when the compiler takes -mavx2 -mfma and the machine that
# builds has both (the usual build-where-you-run of the README). ON: always (the binary then needs
# such a CPU). OFF: never (portable baseline x86-64 code).
# Why: the per-cell sums (fluid/mpm/cell_moments.hpp) keep 32-36 running sums per cell, which fit
# the 16 AVX registers of 4 doubles but not the 16 SSE2 registers of 2; on the 2-core CI machine a
# membrane-on-sphere step (113,104 particles, one thread) took 14.3-15.5 ms against 17.3-22.3 ms
# without (interleaved runs, 2026-12-02). Results differ from the baseline build at round-off
# (FMA contraction); a given build stays deterministic.
set(TETFSI_AVX2 AUTO CACHE STRING "AVX2+FMA for the MPM particle passes: AUTO, ON or OFF")
set_property(CACHE TETFSI_AVX2 PROPERTY STRINGS AUTO ON OFF)

set(_tetfsi_avx2 OFF)
if(TETFSI_AVX2 STREQUAL "ON")
  set(_tetfsi_avx2 ON)
elseif(TETFSI_AVX2 STREQUAL "AUTO" AND CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64" AND NOT CMAKE_CROSSCOMPILING)
  include(CheckCXXCompilerFlag)
  check_cxx_compiler_flag("-mavx2 -mfma" TETFSI_COMPILER_HAS_AVX2)
  if(TETFSI_COMPILER_HAS_AVX2)
    set(_src "${CMAKE_BINARY_DIR}/CMakeFiles/tetfsi_cpu_avx2.cpp")
    file(WRITE "${_src}" "int main() { __builtin_cpu_init(); return __builtin_cpu_supports(\"avx2\") && __builtin_cpu_supports(\"fma\") ? 0 : 1; }\n")
    try_run(_run_result _compile_result "${CMAKE_BINARY_DIR}" "${_src}")
    if(_compile_result AND _run_result EQUAL 0)
      set(_tetfsi_avx2 ON)
    endif()
  endif()
elseif(NOT TETFSI_AVX2 STREQUAL "AUTO" AND NOT TETFSI_AVX2 STREQUAL "OFF")
  message(FATAL_ERROR "TETFSI_AVX2 must be AUTO, ON or OFF (got '${TETFSI_AVX2}')")
endif()
message(STATUS "tetfsi: AVX2+FMA for the MPM particle passes: ${_tetfsi_avx2} (TETFSI_AVX2=${TETFSI_AVX2})")

function(tetfsi_use_vector_isa target)
  if(_tetfsi_avx2)
    target_compile_options(${target} PRIVATE -mavx2 -mfma)
  endif()
endfunction()
