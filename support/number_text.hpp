#pragma once
/// @file number_text.hpp
/// A number for a message, in %.6g (1e-08, 0.0123, 1.5e+06): std::to_string prints six fixed
/// decimals, so a tolerance of 1e-8 read "0.000000" and a volume of 3e-12 m^3 read "0.000000".
#include <cstdio>
#include <string>

namespace tetfsi {

inline std::string number_text(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

}  // namespace tetfsi
