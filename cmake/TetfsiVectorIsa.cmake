# 256-bit vector instructions (AVX2) for the particle passes of the MPM (mpm/particles/), the hot loops
# of the MPM examples: tetfsi_use_vector_isa(target).
#
# TETFSI_AVX2 = AUTO (default): used when the compiler takes -mavx2 -mfma and the machine that
# builds has both (the usual build-where-you-run of the README). ON: always (the binary then needs
# such a CPU). OFF: never (portable baseline x86-64 code).
# Why: the per-cell sums (mpm/particles/cell_moments.hpp) keep 32-36 running sums per cell, which fit
# the 16 AVX registers of 4 doubles but not the 16 SSE2 registers of 2; on the 2-core CI machine a
# membrane-on-sphere MPM step (113,104 particles, one thread) took 15.2-18.6 ms against
# 18.2-21.7 ms without (2026-12-02, `bench_mpm --cases membrane_on_sphere`, apps/bench/mpm).
# -ffp-contract=off: no fusing of a * b + c into one rounding, so that both builds give the same
# bits (with fusing, Grid::fractions gave f = -2e-16 for particles on a cell face and the results
# differed from the baseline build at round-off). EIGEN_MAX_ALIGN_BYTES=16 keeps Eigen's
# alignment, and so the layout of fixed-size types, equal to that of the targets built without
# AVX, which share the headers.
set(TETFSI_AVX2 AUTO CACHE STRING "AVX2 for the MPM particle passes: AUTO, ON or OFF")
set_property(CACHE TETFSI_AVX2 PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${TETFSI_AVX2}" _tetfsi_avx2_mode)

set(_tetfsi_avx2 OFF)
if(_tetfsi_avx2_mode STREQUAL "ON")
  set(_tetfsi_avx2 ON)
elseif(_tetfsi_avx2_mode STREQUAL "AUTO")
  if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64" AND NOT CMAKE_CROSSCOMPILING)
    include(CheckCXXCompilerFlag)
    check_cxx_compiler_flag("-mavx2 -mfma" TETFSI_COMPILER_HAS_AVX2)
    if(TETFSI_COMPILER_HAS_AVX2)
      set(_src "${CMAKE_BINARY_DIR}/CMakeFiles/tetfsi_cpu_avx2.cpp")
      file(WRITE "${_src}" "int main() { __builtin_cpu_init(); return __builtin_cpu_supports(\"avx2\") && __builtin_cpu_supports(\"fma\") ? 0 : 1; }\n")
      try_run(TETFSI_CPU_AVX2_RUN TETFSI_CPU_AVX2_COMPILE "${CMAKE_BINARY_DIR}" "${_src}")
      if(TETFSI_CPU_AVX2_COMPILE AND TETFSI_CPU_AVX2_RUN EQUAL 0)
        set(_tetfsi_avx2 ON)
      endif()
    endif()
  endif()
elseif(NOT _tetfsi_avx2_mode STREQUAL "OFF")
  message(FATAL_ERROR "TETFSI_AVX2 must be AUTO, ON or OFF (got '${TETFSI_AVX2}')")
endif()
message(STATUS "tetfsi: AVX2 for the MPM particle passes: ${_tetfsi_avx2} (TETFSI_AVX2=${TETFSI_AVX2})")

function(tetfsi_use_vector_isa target)
  if(_tetfsi_avx2)
    target_compile_options(${target} PRIVATE -mavx2 -mfma -ffp-contract=off)
    target_compile_definitions(${target} PRIVATE EIGEN_MAX_ALIGN_BYTES=16)
  endif()
endfunction()
