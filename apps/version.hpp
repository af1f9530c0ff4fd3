#pragma once
/// @file version.hpp
/// TETFSI_VERSION: the CMake project version, set by apps/CMakeLists.txt.
#ifndef TETFSI_VERSION
#error "TETFSI_VERSION must be defined by the build (apps/CMakeLists.txt)"
#endif
