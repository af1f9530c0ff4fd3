#pragma once
/// @file cell_checks.hpp
/// Checks shared by the tet and hex volume-mesh readers (volume_mesh.hpp, hex_volume_mesh.hpp):
/// node references, faces shared by more than two cells, face-connected pieces, unused nodes.
/// `word` names the cell kind in messages ("tet", "hex").
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "mesh/complex_mesher.hpp"

namespace tetfsi::mesh::cells {

/// Refuses an empty mesh ("the mesh has no `kind`"), a non-finite node, and a cell that refers to a
/// node outside the mesh or repeats a node.
/// @throws MeshError "`label`: `word` c refers to a missing node" / "... repeats a node (degenerate)"
template <std::size_t N>
void check_cells_and_nodes(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, N>>& cells,
                           const std::string& label, const std::string& word, const std::string& kind) {
  if (cells.empty()) throw MeshError(label + ": the mesh has no " + kind);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!vertices[i].allFinite()) throw MeshError(label + ": node " + std::to_string(i) + " has a non-finite coordinate");
  const int num_nodes = static_cast<int>(vertices.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    auto v = cells[c];
    for (int a : v)
      if (a < 0 || a >= num_nodes) throw MeshError(label + ": " + word + " " + std::to_string(c) + " refers to a missing node");
    std::sort(v.begin(), v.end());
    if (std::adjacent_find(v.begin(), v.end()) != v.end())
      throw MeshError(label + ": " + word + " " + std::to_string(c) + " repeats a node (degenerate)");
  }
}

/// Refuses cells of both orientations (`negative[c]`: cell c is negatively oriented), naming the
/// first cell of the smaller group; `why` ends the message. Returns true if every cell is negative.
/// @throws MeshError "`label`: `word` c is inverted: k of n `word`s have the opposite orientation ..."
inline bool all_negative(const std::vector<bool>& negative, const std::string& label, const std::string& word,
                         const std::string& why) {
  const int n = static_cast<int>(negative.size());
  const int neg = static_cast<int>(std::count(negative.begin(), negative.end(), true));
  if (neg == 0 || neg == n) return neg == n;
  const bool few = neg <= n - neg;  // name a cell of the minority
  const int c = static_cast<int>(std::find(negative.begin(), negative.end(), few) - negative.begin());
  throw MeshError(label + ": " + word + " " + std::to_string(c) + " is inverted: " + std::to_string(few ? neg : n - neg) +
                  " of " + std::to_string(n) + " " + (word == "hex" ? "hexes" : word + "s") +
                  " have the opposite orientation of the others (" + why + ")");
}

/// Refuses two cells on the same nodes, a face (given by the local vertex lists `faces`) shared by
/// more than two cells, and cells that fall apart into more than one piece connected through
/// shared faces.
/// @throws MeshError naming the face and cell, or the number of pieces
template <std::size_t N, std::size_t F, std::size_t K>
void check_faces_and_pieces(const std::vector<std::array<int, N>>& cells, const int (&faces)[F][K],
                            const std::string& label, const std::string& word) {
  const std::string words = word == "hex" ? "hexes" : word + "s";
  std::vector<int> parent(cells.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::map<std::array<int, N>, int> same;  // sorted cell -> its first index
  for (std::size_t c = 0; c < cells.size(); ++c) {
    auto key = cells[c];
    std::sort(key.begin(), key.end());
    const auto [it, inserted] = same.try_emplace(key, static_cast<int>(c));
    if (!inserted)
      throw MeshError(label + ": " + word + " " + std::to_string(c) + " has the same nodes as " + word + " " +
                      std::to_string(it->second) + " (duplicate " + words + ")");
  }
  std::map<std::array<int, K>, std::pair<int, int>> seen;  // sorted face -> (count, first cell)
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (const auto& f : faces) {
      std::array<int, K> key{};
      for (std::size_t k = 0; k < K; ++k) key[k] = cells[c][f[k]];
      std::sort(key.begin(), key.end());
      auto [it, inserted] = seen.try_emplace(key, 0, static_cast<int>(c));
      if (++it->second.first > 2) {
        std::string nodes;
        for (int a : key) nodes += (nodes.empty() ? "" : ", ") + std::to_string(a);
        throw MeshError(label + ": the face (" + nodes + ") of " + word + " " + std::to_string(c) +
                        " is shared by more than two " + words + " (overlapping " + words + ")");
      }
      if (!inserted) parent[root(static_cast<int>(c))] = root(it->second.second);
    }
  int pieces = 0;
  for (std::size_t c = 0; c < cells.size(); ++c) pieces += root(static_cast<int>(c)) == static_cast<int>(c);
  if (pieces > 1)
    throw MeshError(label + ": the " + words + " form " + std::to_string(pieces) + " separate pieces (not connected "
                    "through shared faces); give each piece as its own solid");
}

/// Drops the nodes no cell uses and renumbers the rest in order; returns how many were dropped.
template <std::size_t N>
int drop_unused_nodes(std::vector<Eigen::Vector3d>& vertices, std::vector<std::array<int, N>>& cells) {
  std::vector<int> map(vertices.size(), -1);
  for (const auto& c : cells)
    for (int a : c) map[a] = 0;
  std::vector<Eigen::Vector3d> kept;
  int used = 0;
  for (std::size_t i = 0; i < map.size(); ++i)
    if (map[i] == 0) map[i] = used++, kept.push_back(vertices[i]);
  const int dropped = static_cast<int>(vertices.size()) - used;
  if (dropped == 0) return 0;
  for (auto& c : cells)
    for (int& a : c) a = map[a];
  vertices = std::move(kept);
  return dropped;
}

}  // namespace tetfsi::mesh::cells
