#include "mesh/io/ply_reader.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "mesh/complex_mesher.hpp"  // MeshError

namespace tetfsi::mesh::io {
namespace {

std::string number_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

enum class Type { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

bool type_of(const std::string& word, Type& t) {
  static const std::pair<const char*, Type> names[] = {
      {"char", Type::Int8},     {"int8", Type::Int8},       {"uchar", Type::Uint8},   {"uint8", Type::Uint8},
      {"short", Type::Int16},   {"int16", Type::Int16},     {"ushort", Type::Uint16}, {"uint16", Type::Uint16},
      {"int", Type::Int32},     {"int32", Type::Int32},     {"uint", Type::Uint32},   {"uint32", Type::Uint32},
      {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64}, {"float64", Type::Float64}};
  for (const auto& [n, type] : names)
    if (word == n) return t = type, true;
  return false;
}

std::size_t size_of(Type t) {
  switch (t) {
    case Type::Int8: case Type::Uint8: return 1;
    case Type::Int16: case Type::Uint16: return 2;
    case Type::Int32: case Type::Uint32: case Type::Float32: return 4;
    case Type::Float64: return 8;
  }
  return 1;
}

bool is_integer(Type t) { return t != Type::Float32 && t != Type::Float64; }

struct Property {
  std::string name;
  Type type = Type::Float32;
  bool list = false;
  Type count_type = Type::Uint8;  ///< list length type
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

/// Reads values from the body of the file, ASCII or binary, never past its end.
class Body {
 public:
  Body(std::string_view data, Format format, const std::string& name)
      : data_(data), format_(format), name_(name) {}

  double value(Type t, const char* what) {
    return format_ == Format::Ascii ? ascii(t, what) : binary(t, what);
  }
  std::size_t position() const { return pos_; }

 private:
  [[noreturn]] void fail(const std::string& msg) const {
    throw MeshError(name_ + ": PLY body: " + msg + " (the file is cut or malformed)");
  }

  double ascii(Type t, const char* what) {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    if (pos_ >= data_.size()) fail(std::string("the file ends before ") + what);
    std::size_t end = pos_;
    while (end < data_.size() && !std::isspace(static_cast<unsigned char>(data_[end]))) ++end;
    if (end - pos_ > 64) fail(std::string("a number of more than 64 characters in ") + what);
    const std::string token(data_.substr(pos_, end - pos_));
    pos_ = end;
    char* stop = nullptr;
    const double x = std::strtod(token.c_str(), &stop);
    if (stop != token.c_str() + token.size()) fail("\"" + token + "\" is not a number (in " + what + ")");
    if (is_integer(t) && x != std::floor(x)) fail("\"" + token + "\" is not an integer (in " + what + ")");
    return x;
  }

  double binary(Type t, const char* what) {
    const std::size_t n = size_of(t);
    if (data_.size() - pos_ < n) fail(std::string("the file ends before ") + what);
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    const bool little_host = [] {
      const std::uint16_t one = 1;
      unsigned char first;
      std::memcpy(&first, &one, 1);
      return first == 1;
    }();
    if ((format_ == Format::BinaryLittle) != little_host)
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
      case Type::Int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case Type::Uint8: return b[0];
      case Type::Int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::Uint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::Int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::Uint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::Float32: { float v; std::memcpy(&v, b, 4); return v; }
      case Type::Float64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
  }

  std::string_view data_;
  Format format_;
  const std::string& name_;
  std::size_t pos_ = 0;
};

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t body_start = 0;
};

Header parse_header(std::string_view content, const std::string& name) {
  auto fail = [&](const std::string& msg) { throw MeshError(name + ": PLY header: " + msg); };
  constexpr std::size_t kMaxHeader = 1 << 16;
  Header h;
  std::size_t pos = 0;
  bool have_format = false, ended = false;
  int line_no = 0;
  while (!ended) {
    const std::size_t eol = content.find('\n', pos);
    if (eol == std::string_view::npos || eol > kMaxHeader)
      fail("no \"end_header\" line within the first 64 KiB (the file is cut or not PLY)");
    std::string line(content.substr(pos, eol - pos));
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    ++line_no;
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (line_no == 1) {
      if (line != "ply") fail("the first line must be \"ply\"");
      continue;
    }
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      std::string f, version;
      words >> f >> version;
      if (f == "ascii") h.format = Format::Ascii;
      else if (f == "binary_little_endian") h.format = Format::BinaryLittle;
      else if (f == "binary_big_endian") h.format = Format::BinaryBig;
      else fail("unknown format \"" + f + "\" (expected ascii, binary_little_endian or binary_big_endian)");
      if (version != "1.0") fail("format version \"" + version + "\" (expected 1.0)");
      have_format = true;
    } else if (key == "element") {
      Element e;
      std::string count;
      words >> e.name >> count;
      if (e.name.empty() || count.empty() || count.find_first_not_of("0123456789") != std::string::npos ||
          count.size() > 12)
        fail("line " + std::to_string(line_no) + ": expected \"element <name> <count>\"");
      e.count = std::stoull(count);
      h.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (h.elements.empty()) fail("line " + std::to_string(line_no) + ": a property before any element");
      Property p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string ct, it;
        words >> ct >> it >> p.name;
        p.list = true;
        if (!type_of(ct, p.count_type) || !is_integer(p.count_type) || !type_of(it, p.type) || p.name.empty())
          fail("line " + std::to_string(line_no) + ": expected \"property list <integer type> <type> <name>\"");
      } else {
        words >> p.name;
        if (!type_of(type, p.type) || p.name.empty())
          fail("line " + std::to_string(line_no) + ": expected \"property <type> <name>\"");
      }
      h.elements.back().properties.push_back(std::move(p));
    } else if (key == "end_header") {
      ended = true;
    } else {
      fail("line " + std::to_string(line_no) + ": unknown keyword \"" + key.substr(0, 40) + "\"");
    }
  }
  if (!have_format) fail("no \"format\" line");
  h.body_start = pos;
  return h;
}

int find_property(const Element& e, std::initializer_list<const char*> names) {
  for (std::size_t i = 0; i < e.properties.size(); ++i)
    for (const char* n : names)
      if (e.properties[i].name == n) return static_cast<int>(i);
  return -1;
}

}  // namespace

SurfaceMesh parse_ply(std::string_view content, const std::string& name) {
  const Header h = parse_header(content, name);
  const std::string_view body = content.substr(h.body_start);
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  for (const auto& e : h.elements) {
    // Each item takes at least one byte (binary) or two characters (ASCII): a count beyond the
    // body's size is a lie, refused before anything is allocated for it.
    const std::uint64_t min_bytes = h.format == Format::Ascii ? 2 : 1;
    if (!e.properties.empty() && e.count > body.size() / min_bytes)
      throw MeshError(name + ": PLY: element \"" + e.name + "\" claims " + std::to_string(e.count) +
                      " items but the file has only " + std::to_string(body.size()) + " bytes after its header");
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face = &e;
  }
  if (vertex == nullptr || vertex->count == 0) throw MeshError(name + ": PLY: no vertex element (or 0 vertices)");
  if (face == nullptr || face->count == 0) throw MeshError(name + ": PLY: no face element (or 0 faces): no triangles");
  const int px = find_property(*vertex, {"x"}), py = find_property(*vertex, {"y"}), pz = find_property(*vertex, {"z"});
  if (px < 0 || py < 0 || pz < 0) throw MeshError(name + ": PLY: the vertex element lacks x, y or z");
  const int pf = find_property(*face, {"vertex_indices", "vertex_index"});
  if (pf < 0 || !face->properties[pf].list || !is_integer(face->properties[pf].type))
    throw MeshError(name + ": PLY: the face element lacks an integer list \"vertex_indices\"");

  SurfaceMesh s;
  std::vector<double> indices;
  std::vector<std::size_t> polygon_start;
  Body in(body, h.format, name);
  for (const auto& e : h.elements) {
    const bool is_vertex = &e == vertex, is_face = &e == face;
    if (is_vertex) s.vertices.reserve(e.count);
    for (std::uint64_t item = 0; item < e.count; ++item) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.list) {
          const double v = in.value(p.type, is_vertex ? "the vertex list" : "an element item");
          if (is_vertex && (int(k) == px || int(k) == py || int(k) == pz)) {
            if (!std::isfinite(v))
              throw MeshError(name + ": PLY: vertex " + std::to_string(item) + " has a non-finite coordinate");
            x[int(k) == px ? 0 : int(k) == py ? 1 : 2] = v;
          }
          continue;
        }
        const double n = in.value(p.count_type, "a list length");
        if (n < 0 || n > 1e6)
          throw MeshError(name + ": PLY: a list of " + number_text(n) + " entries (expected 0 to 1e6)");
        if (is_face && int(k) == pf) {
          if (n < 3)
            throw MeshError(name + ": PLY: face " + std::to_string(item) + " has " + std::to_string(int(n)) +
                            " vertices (a face needs at least 3)");
          polygon_start.push_back(indices.size());
        }
        for (int j = 0; j < int(n); ++j) {
          const double v = in.value(p.type, is_face ? "the face list" : "a list");
          if (is_face && int(k) == pf) indices.push_back(v);
        }
      }
      if (is_vertex) s.vertices.push_back(x);
    }
  }
  polygon_start.push_back(indices.size());
  const double nv = static_cast<double>(s.vertices.size());
  for (std::size_t f = 0; f + 1 < polygon_start.size(); ++f) {
    const std::size_t a = polygon_start[f], b = polygon_start[f + 1];
    for (std::size_t j = a; j < b; ++j)
      if (!(indices[j] >= 0 && indices[j] < nv))
        throw MeshError(name + ": PLY: face " + std::to_string(f) + " refers to vertex " + number_text(indices[j]) + " of " +
                        std::to_string(s.vertices.size()));
    for (std::size_t j = a + 1; j + 1 < b; ++j)
      s.triangles.push_back({int(indices[a]), int(indices[j]), int(indices[j + 1])});
  }
  return s;
}

SurfaceMesh read_ply(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw MeshError(path + ": not a regular file");
  const auto bytes = fs::file_size(path, ec);
  if (ec) throw MeshError(path + ": cannot read the file size: " + ec.message());
  if (bytes > kMaxPlyBytes)
    throw MeshError(path + ": " + std::to_string(bytes) + " bytes; PLY surfaces of more than 1 GiB are refused");
  std::ifstream in(path, std::ios::binary);
  std::string content(bytes, '\0');
  if (!in.read(content.data(), static_cast<std::streamsize>(bytes)))
    throw MeshError(path + ": cannot read the file");
  return parse_ply(content, path);
}

}  // namespace tetfsi::mesh::io
