#include "mesh/io/msh_reader.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace tetfsi::mesh::io {
namespace {

constexpr int kGmshTet4 = 4;
constexpr int kGmshHex8 = 5;

/// Name of a 3-D Gmsh element type for messages (gmsh.info "MSH file format", element types).
std::string element_name(int type) {
  switch (type) {
    case 4: return "4-node tetrahedron";
    case 5: return "8-node hexahedron";
    case 6: return "6-node prism";
    case 7: return "5-node pyramid";
    case 11: return "10-node tetrahedron";
    case 12: return "27-node hexahedron";
    case 17: return "20-node hexahedron";
    default: return "3-D element";
  }
}

/// Dimension of a Gmsh element type (gmsh.info "MSH file format", element types): 0, 1 and 2 for
/// the point, line, triangle and quadrangle families, 3 for everything else.
int element_dimension(int type) {
  switch (type) {
    case 15: return 0;                                   // point
    case 1: case 8: case 26: case 27: case 28: return 1;  // lines (2, 3, 4, 5, 6 nodes)
    case 2: case 3: case 9: case 10: case 16: case 20: case 21: case 22: case 23: case 24: case 25: return 2;
    default: return 3;
  }
}

/// The nodes and the 3-D elements of one wanted type (4-node tets or 8-node hexes).
struct MshCells {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int>> cells;
};

class MshParser {
 public:
  /// `wanted`: the Gmsh type every 3-D element must have; `hint`: appended to the refusal of others.
  MshParser(const std::string& text, std::string name, int wanted, std::string hint)
      : in_(text), name_(std::move(name)), wanted_(wanted), hint_(std::move(hint)) {}

  MshCells parse() {
    std::string line;
    bool have_format = false, have_nodes = false, have_elements = false;
    while (next_line(line)) {
      if (line == "$MeshFormat") {
        read_format();
        have_format = true;
      } else if (line == "$Nodes") {
        if (!have_format) fail("$Nodes before $MeshFormat");
        version_ == 2 ? read_nodes_22() : read_nodes_41();
        expect_end("$EndNodes");
        have_nodes = true;
      } else if (line == "$Elements") {
        if (!have_nodes) fail("$Elements before $Nodes");
        version_ == 2 ? read_elements_22() : read_elements_41();
        expect_end("$EndElements");
        have_elements = true;
      } else if (line.size() > 1 && line[0] == '$' && line.rfind("$End", 0) != 0) {
        skip_section(line.substr(1));
      }
    }
    if (!have_format) fail("no $MeshFormat section (not a Gmsh .msh file)");
    if (!have_nodes || !have_elements) fail("no $Nodes or no $Elements section");
    return mesh_;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw std::runtime_error("read_msh(" + name_ + "): " + why); }

  bool next_line(std::string& line) {
    while (std::getline(in_, line)) {
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
      if (!line.empty()) return true;
    }
    return false;
  }

  template <class T>
  T number(const char* what) {
    T v{};
    if (!(in_ >> v)) fail(std::string("expected ") + what);
    return v;
  }

  void read_format() {
    const std::string version = number<std::string>("the format version");
    const int file_type = number<int>("the file type");
    number<int>("the data size");
    if (version == "2.2") version_ = 2;
    else if (version == "4.1") version_ = 4;
    else fail("format version " + version + " is not supported (write version 4.1 or 2.2, e.g. gmsh -format msh41)");
    if (file_type != 0) fail("binary .msh files are not supported: write ASCII (gmsh -bin 0)");
    expect_end("$EndMeshFormat");
  }

  void expect_end(const std::string& end) {
    std::string line;
    if (!next_line(line)) fail("missing " + end);
    if (line != end) fail("expected " + end + ", got '" + line.substr(0, 40) + "'");
  }

  void skip_section(const std::string& section) {
    std::string line;
    while (next_line(line))
      if (line == "$End" + section) return;
    fail("section $" + section + " is not closed");
  }

  void add_node(long long tag, const Eigen::Vector3d& x) {
    if (!index_.emplace(tag, static_cast<int>(mesh_.vertices.size())).second) fail("node tag " + std::to_string(tag) + " appears twice");
    mesh_.vertices.push_back(x);
  }

  Eigen::Vector3d point() {
    Eigen::Vector3d x;
    for (int a = 0; a < 3; ++a) x[a] = number<double>("a node coordinate");
    return x;
  }

  void read_nodes_22() {
    const long long n = number<long long>("the number of nodes");
    if (n < 0) fail("negative number of nodes");
    for (long long i = 0; i < n; ++i) {
      const long long tag = number<long long>("a node tag");
      add_node(tag, point());
    }
  }

  /// The 4.1 section header "numEntityBlocks numItems minTag maxTag"; returns numEntityBlocks.
  long long block_header(const std::string& item) {
    const long long blocks = number<long long>(("the number of " + item + " blocks").c_str());
    for (int k = 0; k < 3; ++k) number<long long>(("the " + item + " count and tag range").c_str());
    if (blocks < 0) fail("negative number of " + item + " blocks");
    return blocks;
  }

  void read_nodes_41() {
    const long long blocks = block_header("node");
    for (long long b = 0; b < blocks; ++b) {
      const int dim = number<int>("an entity dimension");
      number<int>("an entity tag");
      const int parametric = number<int>("the parametric flag");
      const long long n = number<long long>("the number of nodes in a block");
      if (n < 0) fail("negative number of nodes in a block");
      // Tags grown one by one as they are read, not sized from the count: a count the file cannot
      // hold (fuzz_msh found 8.7e12; VolumeMesh.GmshCountsTheFileCannotHoldAreRefused) must end
      // in "expected a node tag", not in an allocation of 8 bytes per claimed node.
      std::vector<long long> tags;
      for (long long i = 0; i < n; ++i) tags.push_back(number<long long>("a node tag"));
      for (long long i = 0; i < n; ++i) {
        add_node(tags[i], point());
        for (int k = 0; parametric && k < dim; ++k) number<double>("a parametric coordinate");
      }
    }
  }

  /// Reads the rest of the current element line as tags.
  std::vector<long long> element_line() {
    std::string line;
    if (!next_line(line)) fail("the $Elements section ends early");
    std::istringstream ls(line);
    std::vector<long long> v;
    long long x;
    while (ls >> x) v.push_back(x);
    if (!ls.eof()) fail("non-integer value in element line '" + line.substr(0, 60) + "'");
    return v;
  }

  void add_element(long long tag, int type, const long long* nodes, std::size_t count) {
    if (element_dimension(type) < 3) return;  // boundary and tagging elements
    const std::size_t wanted_nodes = wanted_ == kGmshHex8 ? 8 : 4;
    if (type != wanted_ || count != wanted_nodes)
      fail("element " + std::to_string(tag) + " has Gmsh type " + std::to_string(type) + " (" + element_name(type) +
           "); only " + (wanted_ == kGmshHex8 ? "8-node hexahedra" : "4-node tetrahedra") + " (type " +
           std::to_string(wanted_) + ") are supported as 3-D elements here" + hint_);
    std::vector<int> c(wanted_nodes);
    for (std::size_t k = 0; k < wanted_nodes; ++k) {
      const auto it = index_.find(nodes[k]);
      if (it == index_.end()) fail("element " + std::to_string(tag) + " refers to unknown node " + std::to_string(nodes[k]));
      c[k] = it->second;
    }
    mesh_.cells.push_back(std::move(c));
  }

  void read_elements_22() {
    const long long n = number<long long>("the number of elements");
    std::string rest;
    std::getline(in_, rest);
    for (long long i = 0; i < n; ++i) {
      const auto v = element_line();  // tag type ntags tags... nodes...
      if (v.size() < 3 || v[2] < 0 || v.size() < 3 + static_cast<std::size_t>(v[2]))
        fail("malformed element line " + std::to_string(i + 1));
      const std::size_t first = 3 + static_cast<std::size_t>(v[2]);
      add_element(v[0], static_cast<int>(v[1]), v.data() + first, v.size() - first);
    }
  }

  void read_elements_41() {
    const long long blocks = block_header("element");
    for (long long b = 0; b < blocks; ++b) {
      number<int>("an entity dimension");
      number<int>("an entity tag");
      const int type = number<int>("an element type");
      const long long n = number<long long>("the number of elements in a block");
      std::string rest;
      std::getline(in_, rest);
      for (long long i = 0; i < n; ++i) {
        const auto v = element_line();  // tag nodes...
        if (v.empty()) fail("empty element line");
        add_element(v[0], type, v.data() + 1, v.size() - 1);
      }
    }
  }

  std::istringstream in_;
  std::string name_;
  int wanted_;
  std::string hint_;
  int version_ = 0;
  MshCells mesh_;
  std::unordered_map<long long, int> index_;
};

}  // namespace

namespace {
std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("read_msh(" + path.string() + "): cannot open the file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}
}  // namespace

TetMesh parse_msh_tets(const std::string& text, const std::string& name) {
  MshCells cells = MshParser(text, name, kGmshTet4, " (a hexahedral mesh is for model \"hex8\")").parse();
  TetMesh m;
  m.vertices = std::move(cells.vertices);
  for (const auto& c : cells.cells) m.tets.push_back({c[0], c[1], c[2], c[3]});
  return m;
}

TetMesh read_msh_tets(const std::filesystem::path& path) { return parse_msh_tets(file_text(path), path.string()); }

HexMesh parse_msh_hexes(const std::string& text, const std::string& name) {
  MshCells cells = MshParser(text, name, kGmshHex8, " (a tetrahedral mesh is for model \"tet_fem\")").parse();
  HexMesh m;
  m.vertices = std::move(cells.vertices);
  for (const auto& c : cells.cells) m.hexes.push_back({c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]});
  return m;
}

HexMesh read_msh_hexes(const std::filesystem::path& path) { return parse_msh_hexes(file_text(path), path.string()); }

}  // namespace tetfsi::mesh::io
