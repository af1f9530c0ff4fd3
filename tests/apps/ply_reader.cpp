#include "ply_reader.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tetfsi::test {

PlyData read_ply(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + file.string());
  std::string line;
  std::getline(in, line);
  if (line != "ply") throw std::runtime_error("not a PLY file");
  std::size_t nv = 0, nf = 0;
  PlyData d;
  std::string element;
  bool face_list_ok = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream ss(line);
    std::string word;
    ss >> word;
    if (word == "format") {
      std::string fmt;
      ss >> fmt;
      if (fmt != "binary_little_endian") throw std::runtime_error("format " + fmt);
    } else if (word == "element") {
      std::size_t n;
      ss >> element >> n;
      (element == "vertex" ? nv : nf) = n;
    } else if (word == "property") {
      std::string type, name;
      ss >> type;
      if (type == "list") {
        std::string count_type, index_type;
        ss >> count_type >> index_type >> name;
        face_list_ok = element == "face" && count_type == "uchar" && index_type == "int";
      } else {
        ss >> name;
        if (type != "float") throw std::runtime_error("unexpected property type " + type);
        d.vertex_properties.push_back(name);
      }
    }
  }
  if (!face_list_ok) throw std::runtime_error("no 'list uchar int' face property");
  const std::size_t per_vertex = d.vertex_properties.size();
  const bool vel = per_vertex == 6 && d.vertex_properties[3] == "vx";
  std::vector<float> buf(per_vertex);
  for (std::size_t i = 0; i < nv; ++i) {
    in.read(reinterpret_cast<char*>(buf.data()), 4 * per_vertex);
    d.positions.emplace_back(buf[0], buf[1], buf[2]);
    if (vel) d.velocities.emplace_back(buf[3], buf[4], buf[5]);
  }
  for (std::size_t f = 0; f < nf; ++f) {
    unsigned char n;
    std::int32_t idx[3];
    in.read(reinterpret_cast<char*>(&n), 1);
    if (n != 3) throw std::runtime_error("face with " + std::to_string(n) + " vertices");
    in.read(reinterpret_cast<char*>(idx), 12);
    d.triangles.push_back({idx[0], idx[1], idx[2]});
  }
  if (!in) throw std::runtime_error("file shorter than its header says");
  in.peek();
  if (!in.eof()) throw std::runtime_error("bytes after the last face");
  return d;
}

}  // namespace tetfsi::test
