#include "solid/hex/hex_model.hpp"

#include <sstream>

#include <Eigen/LU>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tetfsi::solid::hex {

HexModel::HexModel(mesh::HexMesh mesh, Material material, Hex8Formulation formulation)
    : mesh_(std::move(mesh)), material_(material), formulation_(formulation) {
  material_.validate();
  const int n = mesh_.num_vertices();
  const int ne = mesh_.num_hexes();
  if (n == 0 || ne == 0) throw std::invalid_argument("HexModel: the hex mesh is empty");
  for (int e = 0; e < ne; ++e) {
    const auto& h = mesh_.hexes[e];
    for (int a = 0; a < 8; ++a) {
      if (h[a] < 0 || h[a] >= n) {
        throw std::invalid_argument("HexModel: hex " + std::to_string(e) + " refers to node " +
                                    std::to_string(h[a]) + " of " + std::to_string(n));
      }
      for (int b = 0; b < a; ++b) {
        if (h[a] == h[b]) throw std::invalid_argument("HexModel: hex " + std::to_string(e) + " repeats a node");
      }
    }
  }
  reference_.resize(3 * n);
  for (int i = 0; i < n; ++i) reference_.segment<3>(3 * i) = mesh_.vertices[i];

  // Lumped masses M_a = int rho N_a dV; also rejects elements with det J <= 0.
  masses_.setZero(n);
  for (int e = 0; e < ne; ++e) {
    const Matrix83d X = element_positions(e);
    for (const auto& xi : hex8_gauss_points()) {
      const double detJ = (X.transpose() * hex8_shape_gradient(xi)).determinant();
      if (!(detJ > 0.0)) {
        throw std::invalid_argument("HexModel: hex " + std::to_string(e) +
                                    " has det J <= 0 (degenerate, or not in VTK_HEXAHEDRON node order)");
      }
      const auto N = hex8_shape(xi);
      for (int a = 0; a < 8; ++a) masses_(mesh_.hexes[e][a]) += material_.density * N(a) * detJ;
    }
  }

  // Node adjacency (sorted), the block sparsity pattern and per-element block offsets.
  std::vector<std::vector<int>> node_elements(n);
  for (int e = 0; e < ne; ++e) {
    for (int v : mesh_.hexes[e]) node_elements[v].push_back(e);
  }
  std::vector<std::vector<int>> neighbours(n);
  for (int v = 0; v < n; ++v) {
    auto& nb = neighbours[v];
    for (int e : node_elements[v]) nb.insert(nb.end(), mesh_.hexes[e].begin(), mesh_.hexes[e].end());
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
  std::vector<int> outer(3 * n + 1, 0);
  std::vector<int> inner;
  for (int b = 0; b < n; ++b) {
    for (int l = 0; l < 3; ++l) {
      for (int a : neighbours[b]) {
        for (int k = 0; k < 3; ++k) inner.push_back(3 * a + k);
      }
      outer[3 * b + l + 1] = static_cast<int>(inner.size());
    }
  }
  pattern_ = SparseMatrix(3 * n, 3 * n);
  pattern_.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), pattern_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), pattern_.innerIndexPtr());
  std::fill(pattern_.valuePtr(), pattern_.valuePtr() + inner.size(), 0.0);
  block_offsets_.resize(64 * static_cast<std::size_t>(ne));
  for (int e = 0; e < ne; ++e) {
    const auto& h = mesh_.hexes[e];
    for (int b = 0; b < 8; ++b) {
      const auto& nb = neighbours[h[b]];
      for (int a = 0; a < 8; ++a) {
        const auto pos = std::lower_bound(nb.begin(), nb.end(), h[a]) - nb.begin();
        block_offsets_[64 * static_cast<std::size_t>(e) + a + 8 * b] = 3 * static_cast<int>(pos);
      }
    }
  }

  // Greedy colouring: the smallest colour not used by an element sharing a node.
  std::vector<int> color(ne, -1);
  std::vector<int> mark;
  for (int e = 0; e < ne; ++e) {
    for (int v : mesh_.hexes[e]) {
      for (int o : node_elements[v]) {
        if (color[o] >= 0) {
          if (static_cast<int>(mark.size()) <= color[o]) mark.resize(color[o] + 1, -1);
          mark[color[o]] = e;
        }
      }
    }
    int c = 0;
    while (c < static_cast<int>(mark.size()) && mark[c] == e) ++c;
    color[e] = c;
    if (static_cast<int>(colors_.size()) <= c) colors_.resize(c + 1);
    colors_[c].push_back(e);
  }
}

Matrix83d HexModel::element_positions(int e) const {
  Matrix83d X;
  for (int a = 0; a < 8; ++a) X.row(a) = mesh_.vertices[mesh_.hexes[e][a]].transpose();
  return X;
}

Matrix83d HexModel::element_displacements(int e, const Eigen::VectorXd& d) const {
  Matrix83d u;
  for (int a = 0; a < 8; ++a) u.row(a) = d.segment<3>(3 * mesh_.hexes[e][a]).transpose();
  return u;
}

bool HexModel::evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const {
  failed_element_ = -1;
  failed_non_finite_ = false;
  if (d.size() != reference_.size()) {
    throw std::invalid_argument("HexModel::evaluate: displacement has size " + std::to_string(d.size()) +
                                ", expected " + std::to_string(reference_.size()));
  }
  if (!d.allFinite()) {
    failed_non_finite_ = true;
    return false;
  }
  force.setZero(d.size());
  if (tangent) *tangent = pattern_;
  double* values = tangent ? tangent->valuePtr() : nullptr;
  const int* outer = pattern_.outerIndexPtr();
  std::atomic<int> failed{std::numeric_limits<int>::max()};
  for (const auto& elements : colors_) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, elements.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
      Vector24d fe;
      Matrix24d Ke;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const int e = elements[i];
        const auto status = evaluate_element(e, d, &fe, tangent ? &Ke : nullptr, nullptr);
        if (status != ElementStatus::Ok) {
          int cur = failed.load();
          while (e < cur && !failed.compare_exchange_weak(cur, e)) {
          }
          continue;
        }
        const auto& h = mesh_.hexes[e];
        for (int a = 0; a < 8; ++a) force.segment<3>(3 * h[a]) += fe.segment<3>(3 * a);
        if (!values) continue;
        const int* offsets = &block_offsets_[64 * static_cast<std::size_t>(e)];
        for (int b = 0; b < 8; ++b) {
          for (int l = 0; l < 3; ++l) {
            double* column = values + outer[3 * h[b] + l];
            for (int a = 0; a < 8; ++a) {
              double* block = column + offsets[a + 8 * b];
              for (int k = 0; k < 3; ++k) block[k] += Ke(3 * a + k, 3 * b + l);
            }
          }
        }
      }
    });
  }
  if (failed.load() != std::numeric_limits<int>::max()) {
    failed_element_ = failed.load();
    return false;
  }
  return force.allFinite();
}

ElementStatus HexModel::evaluate_element(int e, const Eigen::VectorXd& d, Vector24d* f, Matrix24d* K,
                                         double* energy) const {
  const Matrix83d X = element_positions(e), u = element_displacements(e, d);
  return formulation_ == Hex8Formulation::Enhanced ? hex8_enhanced_evaluate(material_, X, u, f, K, energy)
                                                   : hex8_evaluate(material_, X, u, f, K, energy);
}

std::string HexModel::last_error() const {
  if (failed_non_finite_) return "hex8 model: the displacement is not finite";
  if (failed_element_ < 0) return "";
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int a : mesh_.hexes[failed_element_]) centre += mesh_.vertices[a] / 8.0;
  std::ostringstream msg;
  msg << "hex8 element " << failed_element_ << " (rest centre " << centre.transpose()
      << " m) is inverted: det F <= 0 at a Gauss point"
      << (formulation_ == Hex8Formulation::Enhanced ? " (or its incompatible modes found no equilibrium)" : "");
  return msg.str();
}

std::vector<int> HexModel::failed_elements(const Eigen::VectorXd& d) const {
  const int ne = mesh_.num_hexes();
  std::vector<char> failed(ne, 0);
  if (!d.allFinite()) {
    failed.assign(ne, 1);
  } else {
    tbb::parallel_for(0, ne, [&](int e) {
      double w = 0.0;
      failed[e] = evaluate_element(e, d, nullptr, nullptr, &w) !=
                  ElementStatus::Ok;
    });
  }
  std::vector<int> out;
  for (int e = 0; e < ne; ++e)
    if (failed[e]) out.push_back(e);
  return out;
}

double HexModel::strain_energy(const Eigen::VectorXd& d) const {
  const int ne = mesh_.num_hexes();
  std::vector<double> energy(ne, 0.0);
  tbb::parallel_for(0, ne, [&](int e) {
    double w = 0.0;
    const auto status = evaluate_element(e, d, nullptr, nullptr, &w);
    energy[e] = status == ElementStatus::Ok ? w : std::numeric_limits<double>::infinity();
  });
  double total = 0.0;
  for (double w : energy) total += w;  // serial sum: deterministic
  return total;
}

void HexModel::element_stresses(const Eigen::VectorXd& d, std::vector<double>& cauchy,
                                std::vector<double>& pk2) const {
  const int ne = mesh_.num_hexes();
  cauchy.assign(6 * static_cast<std::size_t>(ne), std::numeric_limits<double>::quiet_NaN());
  pk2 = cauchy;
  tbb::parallel_for(0, ne, [&](int e) {
    Eigen::Matrix3d F, S;
    const Matrix83d X = element_positions(e), u = element_displacements(e, d);
    const bool ok = formulation_ == Hex8Formulation::Enhanced ? hex8_enhanced_average_stress(material_, X, u, F, S)
                                                              : hex8_average_stress(material_, X, u, F, S);
    if (!ok) return;
    const Eigen::Matrix3d sigma = cauchy_stress(F, S);
    for (int v = 0; v < 6; ++v) {
      cauchy[6 * e + v] = sigma(kVoigt[v][0], kVoigt[v][1]);
      pk2[6 * e + v] = S(kVoigt[v][0], kVoigt[v][1]);
    }
  });
}

}  // namespace tetfsi::solid::hex
