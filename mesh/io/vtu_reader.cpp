#include "mesh/io/vtu_reader.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "mesh/io/zlib_blocks.hpp"

namespace tetfsi::mesh::io {
namespace {

using Attributes = std::map<std::string, std::string>;

struct Parser {
  const std::string& text;
  std::string name;

  [[noreturn]] void fail(const std::string& why) const { throw std::runtime_error("read_vtu(" + name + "): " + why); }

  // Attributes of the tag starting at `pos` (which points at '<'); `end` receives the index after '>'.
  Attributes attributes(std::size_t pos, std::size_t& end) const {
    end = text.find('>', pos);
    if (end == std::string::npos) fail("unterminated tag");
    Attributes a;
    std::size_t i = text.find_first_of(" \t\r\n/>", pos + 1);
    while (i < end) {
      const std::size_t eq = text.find('=', i);
      if (eq == std::string::npos || eq > end) break;
      std::size_t k0 = text.find_first_not_of(" \t\r\n", i);
      std::string key = text.substr(k0, eq - k0);
      while (!key.empty() && std::isspace(static_cast<unsigned char>(key.back()))) key.pop_back();
      const std::size_t q0 = text.find_first_of("\"'", eq);
      if (q0 == std::string::npos || q0 > end) fail("malformed attribute '" + key + "'");
      const std::size_t q1 = text.find(text[q0], q0 + 1);
      if (q1 == std::string::npos) fail("unterminated attribute '" + key + "'");
      a[key] = text.substr(q0 + 1, q1 - q0 - 1);
      i = q1 + 1;
      if (q1 >= end) {  // a '>' inside the quotes: the tag ends at the next one
        end = text.find('>', q1);
        if (end == std::string::npos) fail("unterminated tag");
      }
    }
    ++end;
    return a;
  }

  std::size_t find_tag(const std::string& tag, std::size_t from, std::size_t to) const {
    std::size_t p = from;
    while ((p = text.find("<" + tag, p)) != std::string::npos && p < to) {
      const char c = text[p + 1 + tag.size()];
      if (c == ' ' || c == '>' || c == '/' || c == '\n' || c == '\t' || c == '\r') return p;
      ++p;
    }
    return std::string::npos;
  }
};

std::vector<unsigned char> base64_decode(const std::string& s, std::size_t begin, std::size_t end, const Parser& p) {
  static const auto table = [] {
    std::array<int, 256> t{};
    t.fill(-1);
    const char* chars = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(chars[i])] = i;
    return t;
  }();
  std::vector<unsigned char> out;
  int quad[4];
  int n = 0, pad = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (std::isspace(c)) continue;
    if (c == '=') {
      quad[n++] = 0;
      ++pad;
    } else {
      if (table[c] < 0 || pad) p.fail("invalid base64 data");
      quad[n++] = table[c];
    }
    if (n == 4) {  // each 4-character group decodes on its own, so separately encoded blocks work
      const unsigned v = (quad[0] << 18) | (quad[1] << 12) | (quad[2] << 6) | quad[3];
      out.push_back(static_cast<unsigned char>(v >> 16));
      if (pad < 2) out.push_back(static_cast<unsigned char>(v >> 8));
      if (pad < 1) out.push_back(static_cast<unsigned char>(v));
      n = 0;
      pad = 0;
    }
  }
  if (n != 0) p.fail("truncated base64 data");
  return out;
}

template <class T>
void convert(const unsigned char* data, std::size_t count, std::vector<double>& out) {
  for (std::size_t i = 0; i < count; ++i) {
    T v;
    std::memcpy(&v, data + i * sizeof(T), sizeof(T));
    out.push_back(static_cast<double>(v));
  }
}

std::size_t type_size(const std::string& type) {
  static const std::map<std::string, std::size_t> sizes = {
      {"Int8", 1}, {"UInt8", 1}, {"Int16", 2}, {"UInt16", 2}, {"Int32", 4}, {"UInt32", 4},
      {"Int64", 8}, {"UInt64", 8}, {"Float32", 4}, {"Float64", 8}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
}

struct Array {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

// How the file stores binary data: the header word size, the compressor, the raw appended section.
struct Encoding {
  std::size_t header_bytes = 4;      ///< header_type UInt32 (4) or UInt64 (8)
  bool zlib = false;                 ///< compressor="vtkZLibDataCompressor"
  const unsigned char* appended = nullptr;  ///< first byte after the '_' of <AppendedData encoding="raw">
  std::size_t appended_size = 0;
};

// Sequential reads from a byte range, failing with a message when it runs out.
struct Cursor {
  const unsigned char* data;
  std::size_t size;
  std::size_t pos = 0;
  const Parser& p;
  const std::string& array;

  const unsigned char* take(std::uint64_t n) {
    if (n > size - pos) p.fail("DataArray '" + array + "' is truncated (needs " + std::to_string(n) + " more bytes, " + std::to_string(size - pos) + " left)");
    const unsigned char* at = data + pos;
    pos += n;
    return at;
  }
  std::uint64_t word(std::size_t header_bytes) {
    const unsigned char* at = take(header_bytes);
    if (header_bytes == 8) {
      std::uint64_t v;
      std::memcpy(&v, at, 8);
      return v;
    }
    std::uint32_t v;
    std::memcpy(&v, at, 4);
    return v;
  }
};

// The uncompressed payload of a binary array: [byte count][bytes], or with zlib the block header
// and blocks of zlib_blocks.hpp.
std::vector<unsigned char> payload(Cursor& c, const Encoding& e) {
  if (!e.zlib) {
    const std::uint64_t n = c.word(e.header_bytes);
    const unsigned char* at = c.take(n);
    return {at, at + n};
  }
  const std::uint64_t nb = c.word(e.header_bytes), block = c.word(e.header_bytes), last = c.word(e.header_bytes);
  if (nb > c.size / e.header_bytes || last > block) c.p.fail("DataArray '" + c.array + "' has a malformed compression header");
  std::vector<std::uint64_t> sizes(nb);
  std::uint64_t compressed = 0;
  for (auto& size : sizes) {
    size = c.word(e.header_bytes);
    compressed += std::min<std::uint64_t>(size, c.size + 1);  // stops growing once past c.size
    if (compressed > c.size) break;
  }
  if (compressed > c.size - c.pos)
    c.p.fail("DataArray '" + c.array + "' is truncated or its compression header is corrupt (" +
             std::to_string(compressed) + " compressed bytes declared, " + std::to_string(c.size - c.pos) + " left)");
  // Grown block by block, so memory follows the data that really inflates.
  std::vector<unsigned char> out;
  for (std::uint64_t b = 0; b < nb; ++b) {
    const std::uint64_t n = (b + 1 == nb && last) ? last : block;
    // Deflate expands at most 1032:1 (zlib FAQ): a larger block size is a corrupt header, not data.
    if (n > 1032 * sizes[b] + 64)
      c.p.fail("DataArray '" + c.array + "' declares a block of " + std::to_string(n) + " bytes from " +
               std::to_string(sizes[b]) + " compressed bytes");
    const unsigned char* from = c.take(sizes[b]);
    const std::size_t at = out.size();
    out.resize(at + n);
    if (!inflate_zlib_block(from, sizes[b], out.data() + at, n))
      c.p.fail("DataArray '" + c.array + "': zlib block " + std::to_string(b) + " is corrupt");
  }
  return out;
}

// Parses the DataArray whose tag starts at `pos`.
Array read_array(const Parser& p, std::size_t pos, const Encoding& e) {
  std::size_t body = 0;
  Attributes a = p.attributes(pos, body);
  Array out;
  out.name = a.count("Name") ? a["Name"] : "";
  if (a.count("NumberOfComponents")) {
    try {
      out.components = std::stoi(a["NumberOfComponents"]);
    } catch (const std::exception&) {
      p.fail("DataArray '" + out.name + "' has NumberOfComponents=\"" + a["NumberOfComponents"] + "\", not an integer");
    }
  }
  const std::string type = a["type"];
  const std::size_t size = type_size(type);
  if (size == 0) p.fail("DataArray '" + out.name + "' has unsupported type '" + type + "'");
  const std::string format = a.count("format") ? a["format"] : "ascii";
  std::vector<unsigned char> bytes;
  if (format == "appended") {
    if (!e.appended) p.fail("DataArray '" + out.name + "' is appended but the file has no raw <AppendedData>");
    std::size_t offset = 0;
    try {
      offset = std::stoull(a.at("offset"));
    } catch (const std::exception&) {
      p.fail("DataArray '" + out.name + "' lacks a valid offset");
    }
    if (offset > e.appended_size) p.fail("DataArray '" + out.name + "' has an offset past the appended data");
    Cursor c{e.appended + offset, e.appended_size - offset, 0, p, out.name};
    bytes = payload(c, e);
  } else if (p.text[body - 2] == '/') {
    return out;  // <DataArray ... />: empty
  } else {
    const std::size_t close = p.text.find("</DataArray>", body);
    if (close == std::string::npos) p.fail("DataArray '" + out.name + "' is not closed");
    if (format == "ascii") {
      std::istringstream in(p.text.substr(body, close - body));
      double v;
      while (in >> v) out.values.push_back(v);
      if (!in.eof()) p.fail("DataArray '" + out.name + "' has a non-numeric ASCII value");
    } else if (format == "binary") {
      const auto text = base64_decode(p.text, body, close, p);
      Cursor c{text.data(), text.size(), 0, p, out.name};
      bytes = payload(c, e);
    } else {
      p.fail("DataArray '" + out.name + "' uses format=\"" + format + "\" (only ascii, binary and appended are supported)");
    }
  }
  if (format != "ascii") {
    if (bytes.size() % size != 0)
      p.fail("DataArray '" + out.name + "' holds " + std::to_string(bytes.size()) + " bytes, not a multiple of " + type);
    const unsigned char* d = bytes.data();
    const std::size_t count = bytes.size() / size;
    out.values.reserve(count);
    if (type == "Int8") convert<std::int8_t>(d, count, out.values);
    else if (type == "UInt8") convert<std::uint8_t>(d, count, out.values);
    else if (type == "Int16") convert<std::int16_t>(d, count, out.values);
    else if (type == "UInt16") convert<std::uint16_t>(d, count, out.values);
    else if (type == "Int32") convert<std::int32_t>(d, count, out.values);
    else if (type == "UInt32") convert<std::uint32_t>(d, count, out.values);
    else if (type == "Int64") convert<std::int64_t>(d, count, out.values);
    else if (type == "UInt64") convert<std::uint64_t>(d, count, out.values);
    else if (type == "Float32") convert<float>(d, count, out.values);
    else convert<double>(d, count, out.values);
  }
  if (out.components < 1 || out.values.size() % out.components != 0) {
    p.fail("DataArray '" + out.name + "' has " + std::to_string(out.values.size()) +
           " values, not a multiple of " + std::to_string(out.components) + " components");
  }
  return out;
}

}  // namespace
UnstructuredGrid parse_vtu(const std::string& whole, const std::string& name) {
  // The XML part ends where raw appended data (bytes that may look like tags) begins.
  const std::size_t appended_pos = whole.find("<AppendedData");
  const std::string text = whole.substr(0, appended_pos);
  Parser p{text, name};
  const std::size_t file_pos = p.find_tag("VTKFile", 0, text.size());
  if (file_pos == std::string::npos) p.fail("no <VTKFile> element (not a VTK XML file)");
  std::size_t after = 0;
  Attributes file = p.attributes(file_pos, after);
  if (file["type"] != "UnstructuredGrid") p.fail("VTKFile type is '" + file["type"] + "', expected UnstructuredGrid");
  Encoding encoding;
  if (file.count("compressor") && !file["compressor"].empty()) {
    if (file["compressor"] != "vtkZLibDataCompressor")
      p.fail("compressor " + file["compressor"] + " is not supported (only vtkZLibDataCompressor)");
    encoding.zlib = true;
  }
  if (file.count("byte_order") && file["byte_order"] != "LittleEndian") p.fail("only LittleEndian files are supported");
  if (file.count("header_type")) {
    if (file["header_type"] == "UInt64") encoding.header_bytes = 8;
    else if (file["header_type"] != "UInt32") p.fail("unsupported header_type '" + file["header_type"] + "'");
  }
  if (appended_pos != std::string::npos) {
    const Parser whole_parser{whole, name};
    std::size_t data = 0;
    Attributes appended = whole_parser.attributes(appended_pos, data);
    if (appended["encoding"] != "raw")
      p.fail("<AppendedData encoding=\"" + appended["encoding"] + "\"> is not supported (only raw)");
    const std::size_t underscore = whole.find('_', data);
    if (underscore == std::string::npos) p.fail("<AppendedData> lacks the '_' that starts the data");
    encoding.appended = reinterpret_cast<const unsigned char*>(whole.data()) + underscore + 1;
    encoding.appended_size = whole.size() - underscore - 1;
  }
  const std::size_t piece_pos = p.find_tag("Piece", after, text.size());
  if (piece_pos == std::string::npos) p.fail("no <Piece> element");
  if (p.find_tag("Piece", piece_pos + 1, text.size()) != std::string::npos) p.fail("more than one <Piece> is not supported");
  Attributes piece = p.attributes(piece_pos, after);
  long long num_points = -1, num_cells = -1;
  try {
    num_points = std::stoll(piece.at("NumberOfPoints"));
    num_cells = std::stoll(piece.at("NumberOfCells"));
  } catch (const std::exception&) {
    p.fail("<Piece> lacks a valid NumberOfPoints or NumberOfCells");
  }
  if (num_points < 0 || num_cells < 0) p.fail("negative NumberOfPoints or NumberOfCells");

  // The DataArrays inside <Section> ... </Section>.
  auto section = [&](const std::string& tag) {
    std::vector<Array> arrays;
    const std::size_t open = p.find_tag(tag, after, text.size());
    if (open == std::string::npos) return arrays;
    std::size_t body = 0;
    p.attributes(open, body);
    if (text[body - 2] == '/') return arrays;
    const std::size_t close = text.find("</" + tag + ">", body);
    if (close == std::string::npos) p.fail("<" + tag + "> is not closed");
    for (std::size_t pos = p.find_tag("DataArray", body, close); pos != std::string::npos;
         pos = p.find_tag("DataArray", pos + 1, close)) {
      arrays.push_back(read_array(p, pos, encoding));
    }
    return arrays;
  };

  UnstructuredGrid grid;
  const auto points = section("Points");
  if (points.size() != 1 || points[0].components != 3 ||
      points[0].values.size() != 3 * static_cast<std::size_t>(num_points)) {
    p.fail("<Points> must hold one 3-component array of NumberOfPoints = " + std::to_string(num_points) + " points");
  }
  for (long long i = 0; i < num_points; ++i) {
    grid.points.emplace_back(points[0].values[3 * i], points[0].values[3 * i + 1], points[0].values[3 * i + 2]);
  }
  const Array* connectivity = nullptr;
  const Array* offsets = nullptr;
  const Array* types = nullptr;
  const auto cells = section("Cells");
  for (const auto& a : cells) {
    if (a.name == "connectivity") connectivity = &a;
    if (a.name == "offsets") offsets = &a;
    if (a.name == "types") types = &a;
  }
  if (!connectivity || !offsets || !types) p.fail("<Cells> needs the arrays connectivity, offsets and types");
  if (offsets->values.size() != static_cast<std::size_t>(num_cells) ||
      types->values.size() != static_cast<std::size_t>(num_cells)) {
    p.fail("offsets/types do not have NumberOfCells = " + std::to_string(num_cells) + " entries");
  }
  double previous = 0.0;
  for (double o : offsets->values) {
    if (o < previous || o > static_cast<double>(connectivity->values.size())) p.fail("offsets are not increasing within the connectivity");
    previous = o;
  }
  if (num_cells > 0 && previous != static_cast<double>(connectivity->values.size())) {
    p.fail("the last offset does not match the connectivity length");
  }
  for (double c : connectivity->values) {
    if (c < 0 || c >= static_cast<double>(num_points) || c != std::floor(c)) {
      p.fail("connectivity refers to point " + std::to_string(c) + " of " + std::to_string(num_points));
    }
    grid.connectivity.push_back(static_cast<std::int64_t>(c));
  }
  for (double o : offsets->values) grid.offsets.push_back(static_cast<std::int64_t>(o));
  for (double t : types->values) {
    if (!(t >= 0 && t <= 255 && t == std::floor(t))) p.fail("cell type " + std::to_string(t) + " is not a VTK cell type (0..255)");
    grid.types.push_back(static_cast<std::uint8_t>(t));
  }
  for (auto& a : section("PointData")) {
    if (a.values.size() != static_cast<std::size_t>(num_points) * a.components) p.fail("point field '" + a.name + "' has the wrong size");
    grid.point_data.push_back({a.name, a.components, std::move(a.values)});
  }
  for (auto& a : section("CellData")) {
    if (a.values.size() != static_cast<std::size_t>(num_cells) * a.components) p.fail("cell field '" + a.name + "' has the wrong size");
    grid.cell_data.push_back({a.name, a.components, std::move(a.values)});
  }
  return grid;
}

UnstructuredGrid read_vtu(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("read_vtu(" + path.string() + "): cannot open the file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_vtu(buffer.str(), path.string());
}

HexMesh to_hex_mesh(const UnstructuredGrid& grid, const std::string& name) {
  HexMesh mesh;
  mesh.vertices = grid.points;
  std::int64_t begin = 0;
  for (int c = 0; c < grid.num_cells(); ++c) {
    const std::int64_t end = grid.offsets[c];
    if (grid.types[c] != static_cast<std::uint8_t>(VtkCell::Hexahedron) || end - begin != 8) {
      throw std::runtime_error("read_hex_mesh_vtu(" + name + "): cell " + std::to_string(c) + " has VTK type " +
                               std::to_string(grid.types[c]) + " with " + std::to_string(end - begin) +
                               " points; only hexahedra (type 12, 8 points) are supported");
    }
    std::array<int, 8> h{};
    for (int a = 0; a < 8; ++a) h[a] = static_cast<int>(grid.connectivity[begin + a]);
    mesh.hexes.push_back(h);
    begin = end;
  }
  if (mesh.hexes.empty()) throw std::runtime_error("read_hex_mesh_vtu(" + name + "): the file has no cells");
  return mesh;
}

HexMesh read_hex_mesh_vtu(const std::filesystem::path& path) { return to_hex_mesh(read_vtu(path), path.string()); }

}  // namespace tetfsi::mesh::io
