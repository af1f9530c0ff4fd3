#pragma once
/// @file csv.hpp
/// Test helpers for output files: a numeric CSV with a header row, text lines, .pvd frames.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace tetfsi::test {

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  /// Value of column `name` in row `r` (throws if the column does not exist).
  double at(std::size_t r, const std::string& name) const {
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == name) return rows.at(r).at(c);
    throw std::runtime_error("no column " + name);
  }
};

inline Csv read_csv(const std::filesystem::path& file) {
  Csv csv;
  std::ifstream in(file);
  std::string line, cell;
  if (std::getline(in, line)) {
    std::stringstream ss(line);
    while (std::getline(ss, cell, ',')) csv.header.push_back(cell);
  }
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<double> row;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    csv.rows.push_back(row);
  }
  return csv;
}

/// Lines of a text.
inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string line;
  while (std::getline(ss, line)) out.push_back(line);
  return out;
}

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Checks the frames of a .pvd as read back by vtk_describe ("time points cells fields..." per
/// line): frame k is at time k * frame_dt [s] and has the description `expected` (" points cells ...").
inline void expect_pvd_frames(const std::vector<std::string>& frames, double frame_dt, const std::string& expected) {
  for (std::size_t k = 0; k < frames.size(); ++k) {
    std::istringstream ss(frames[k]);
    double t;
    std::string rest;
    ss >> t;
    std::getline(ss, rest);
    EXPECT_NEAR(t, frame_dt * k, 1e-12) << "frame " << k;
    EXPECT_EQ(rest, expected) << "frame " << k;
  }
}

}  // namespace tetfsi::test
