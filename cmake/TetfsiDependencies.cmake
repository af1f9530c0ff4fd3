# Every dependency comes from Debian 12 packages (scripts/setup.sh installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(TBB REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(assimp REQUIRED)
find_package(ZLIB REQUIRED)           # .vtu compression (mesh/io/zlib_blocks.hpp)
find_package(MPI REQUIRED COMPONENTS C)   # hypre in Debian is built against Open MPI

# CGAL is header-only; only mesh/ links it (each CGAL translation unit: ~60 s, 3.6 GB).
find_package(CGAL REQUIRED)

# SuiteSparse 5.12 ships no CMake config: import the libraries by hand.
find_path(SUITESPARSE_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse REQUIRED)
foreach(lib umfpack cholmod amd colamd camd ccolamd suitesparseconfig)
  find_library(SUITESPARSE_${lib}_LIBRARY ${lib} REQUIRED)
  list(APPEND SUITESPARSE_LIBRARIES ${SUITESPARSE_${lib}_LIBRARY})
endforeach()
add_library(tetfsi_suitesparse INTERFACE)
target_include_directories(tetfsi_suitesparse SYSTEM INTERFACE ${SUITESPARSE_INCLUDE_DIR})
target_link_libraries(tetfsi_suitesparse INTERFACE ${SUITESPARSE_LIBRARIES})

# hypre 2.26 (BoomerAMG); Debian ships no CMake config for it.
find_path(HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre REQUIRED)
find_library(HYPRE_LIBRARY HYPRE REQUIRED)
add_library(tetfsi_hypre INTERFACE)
target_include_directories(tetfsi_hypre SYSTEM INTERFACE ${HYPRE_INCLUDE_DIR})
target_link_libraries(tetfsi_hypre INTERFACE ${HYPRE_LIBRARY} MPI::MPI_C)

# OpenVDB 10 (volume files; only fluid/io/vdb_writer.cpp and its test include it). Debian's
# FindOpenVDB.cmake also asks for Boost.Iostreams development files that nothing here needs, and
# Imath's CMake config names a Python module Debian does not install: import both by hand. The
# headers use Imath's half (<Imath/half.h>) and TBB.
find_path(OPENVDB_INCLUDE_DIR openvdb/openvdb.h REQUIRED)
find_library(OPENVDB_LIBRARY openvdb REQUIRED)
find_library(IMATH_LIBRARY NAMES Imath-3_1 Imath REQUIRED)
add_library(tetfsi_openvdb INTERFACE)
target_include_directories(tetfsi_openvdb SYSTEM INTERFACE ${OPENVDB_INCLUDE_DIR})
target_link_libraries(tetfsi_openvdb INTERFACE ${OPENVDB_LIBRARY} ${IMATH_LIBRARY} TBB::tbb)

# Debian's python3-vtk9 and python3-matplotlib install into the system interpreter, not into any
# other python3 on PATH (the tests' scripts and `tetfsi report` use it).
find_program(TETFSI_SYSTEM_PYTHON python3 PATHS /usr/bin NO_DEFAULT_PATH REQUIRED)
if(TETFSI_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
