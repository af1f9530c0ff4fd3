#pragma once
/// @file csv.hpp
/// Test helper: reads a numeric CSV with a header row.
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

}  // namespace tetfsi::test
