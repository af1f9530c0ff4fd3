#include "solid/tet/tet_model.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>

#include "solid/solid_error.hpp"
#include "support/number_text.hpp"

namespace tetfsi::solid {
namespace {

std::vector<int> flatten(const std::vector<std::array<int, 4>>& tets) {
  std::vector<int> flat;
  flat.reserve(tets.size() * 4);
  for (const auto& t : tets) flat.insert(flat.end(), t.begin(), t.end());
  return flat;
}

/// Nearest (Frobenius) positive semi-definite matrix: clamp negative eigenvalues to zero.
Eigen::Matrix<double, 9, 9> project_to_psd(const Eigen::Matrix<double, 9, 9>& C) {
  const Eigen::Matrix<double, 9, 9> sym = 0.5 * (C + C.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(sym);
  if (eig.eigenvalues().minCoeff() >= 0) return sym;
  const Eigen::Matrix<double, 9, 1> clamped = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

TetModel::TetModel(const mesh::TetMesh& mesh, const TetMaterial& material, const TetModelOptions& options)
    : num_nodes_(mesh.num_vertices()),
      material_(material),
      params_(ConstitutiveParams::from(material)),
      options_(options),
      tets_(mesh.tets) {
  material_.validate();
  if (mesh.num_tets() == 0) throw SolidError("TetModel: the mesh has no tets");
  X_.resize(3 * num_nodes_);
  for (int v = 0; v < num_nodes_; ++v) X_.segment<3>(3 * v) = mesh.vertices[v];
  mass_.setZero(num_nodes_);
  grads_.resize(tets_.size());
  volume_.resize(tets_.size());
  for (size_t t = 0; t < tets_.size(); ++t) {
    const auto& v = tets_[t];
    for (int i : v)
      if (i < 0 || i >= num_nodes_) throw SolidError("TetModel: tet " + std::to_string(t) + " has a bad vertex index");
    Eigen::Matrix3d Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = mesh.vertices[v[k + 1]] - mesh.vertices[v[0]];
    const double vol = Dm.determinant() / 6.0;
    const double scale = Dm.colwise().norm().maxCoeff();
    if (!(vol > 1e-12 * scale * scale * scale))
      throw SolidError("TetModel: rest tet " + std::to_string(t) + " is degenerate or inverted (volume " +
                       number_text(vol) + " m^3)");
    const Eigen::Matrix3d Dinv = Dm.inverse();
    grads_[t].block<3, 3>(1, 0) = Dinv;
    grads_[t].row(0) = -Dinv.colwise().sum();
    volume_[t] = vol;
    for (int i : v) mass_[i] += material_.density * vol / 4.0;
  }
  assembler_ = BlockAssembler(num_nodes_, 4, flatten(tets_));
}

Eigen::Matrix3d TetModel::deformation_gradient(const Eigen::VectorXd& d, int t) const {
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 4; ++i) F += d.segment<3>(3 * tets_[t][i]) * grads_[t].row(i);
  return F;
}

bool TetModel::evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const {
  return evaluate_with(d, force, tangent, options_.project_spd);
}

bool TetModel::evaluate_exact(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const {
  return evaluate_with(d, force, tangent, false);
}

bool TetModel::evaluate_with(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent,
                             bool project) const {
  if (d.size() != 3 * num_nodes_) throw SolidError("TetModel::evaluate: displacement has the wrong size");
  const int nt = num_tets();
  element_vectors_.resize(static_cast<size_t>(nt) * 12);
  // The element matrices are made and summed into the tangent a range of kElementsPerRange tets at
  // a time (BlockAssembler::add_element_matrices: the same sums as all at once), so that 9.4 MB of
  // them are held instead of 1,152 bytes per tet (102 MB for the flagship's sheets at 962k fluid tets).
  constexpr int kElementsPerRange = 8192;
  if (tangent) element_matrices_.resize(static_cast<size_t>(std::min(nt, kElementsPerRange)) * 144);
  // Every law but the stable neo-Hookean stops at an inverted element (StVK collapses, ln J and
  // J^{-2/3} are undefined).
  const bool stops_at_inversion = params_.law != ConstitutiveLaw::kNeoHookeanStable;
  std::atomic<int> first_bad{std::numeric_limits<int>::max()};
  std::atomic<int> inverted{0};

  // Element t of the range starting at `first`: its force vector, and its matrix into the range's buffer.
  auto element = [&](int t, int first) {
    const Eigen::Matrix3d F = deformation_gradient(d, t);
    const double J = F.determinant();
    const bool bad = !std::isfinite(J) || (stops_at_inversion && J <= options_.min_det) || F.norm() > options_.max_stretch;
    if (J <= 0) inverted.fetch_add(1, std::memory_order_relaxed);
    if (bad) {
      int cur = first_bad.load();
      while (t < cur && !first_bad.compare_exchange_weak(cur, t)) {}
    }
    const auto& g = grads_[t];
    const double V = volume_[t];
    const Eigen::Matrix3d P = first_piola(params_, F);
    double* fe = element_vectors_.data() + static_cast<size_t>(t) * 12;
    for (int i = 0; i < 4; ++i)
      Eigen::Map<Eigen::Vector3d>(fe + 3 * i) = V * P * g.row(i).transpose();
    if (!tangent) return;
    // Material tangent C = dP/dF as a 9 x 9 matrix over column-major vec(F).
    Eigen::Matrix<double, 9, 9> C = first_piola_tangent(params_, F);
    if (project) C = project_to_psd(C);
    // K_e(3i+a, 3j+c) = V [dP(e_c g_j^T) g_i]_a, with vec(dP) = sum_b C(:, c + 3b) g_jb.
    double* ke = element_matrices_.data() + static_cast<size_t>(t - first) * 144;
    for (int j = 0; j < 4; ++j)
      for (int c = 0; c < 3; ++c) {
        const Eigen::Matrix<double, 9, 1> vdP = C.col(c) * g(j, 0) + C.col(c + 3) * g(j, 1) + C.col(c + 6) * g(j, 2);
        const Eigen::Map<const Eigen::Matrix3d> dP(vdP.data());
        double* col = ke + (3 * j + c) * 12;
        for (int i = 0; i < 4; ++i)
          Eigen::Map<Eigen::Vector3d>(col + 3 * i) = V * dP * g.row(i).transpose();
      }
  };
  for (int first = 0; first < nt; first += kElementsPerRange) {
    const int end = std::min(nt, first + kElementsPerRange);
    tbb::parallel_for(first, end, [&](int t) { element(t, first); });
    // After a bad tet the tangent is not needed; the ranges still run for the count of inverted tets.
    if (tangent && first_bad.load() == std::numeric_limits<int>::max())
      assembler_.add_element_matrices(element_matrices_.data(), first, end, *tangent);
  }
  last_inverted_ = inverted.load();
  const int bad = first_bad.load();
  if (bad != std::numeric_limits<int>::max()) {
    const Eigen::Matrix3d F = deformation_gradient(d, bad);
    const double J = F.determinant();
    std::ostringstream msg;
    msg << "tet " << bad << " (vertices " << tets_[bad][0] << ' ' << tets_[bad][1] << ' ' << tets_[bad][2]
        << ' ' << tets_[bad][3] << ") ";
    if (!std::isfinite(J))
      msg << "has a non-finite deformation gradient";
    else if (F.norm() > options_.max_stretch)
      msg << "is stretched by a factor " << F.norm() << " > " << options_.max_stretch
          << ": the simulation diverged (reduce the time step, add damping, or use scheme \"chentanez\")";
    else
      msg << "is inverted or degenerate (det F = " << J << " <= " << options_.min_det
          << "); the law \"" << hyperelastic_law_name(params_.law)
          << "\" cannot recover from inversion, use constitutive \"neohookean_stable\"";
    last_error_ = msg.str();
    return false;
  }
  last_error_.clear();
  assembler_.assemble_vector(element_vectors_, force);
  return true;
}

void TetModel::release_workspace() const {
  std::vector<double>().swap(element_matrices_);
  std::vector<double>().swap(element_vectors_);
}

double TetModel::strain_energy(const Eigen::VectorXd& d) const {
  // Sum in fixed element order (deterministic); cheap compared to evaluate().
  double w = 0;
  for (int t = 0; t < num_tets(); ++t) w += volume_[t] * energy_density(params_, deformation_gradient(d, t));
  return w;
}

Eigen::VectorXd TetModel::volume_ratios(const Eigen::VectorXd& d) const {
  Eigen::VectorXd r(num_tets());
  tbb::parallel_for(0, num_tets(), [&](int t) { r[t] = deformation_gradient(d, t).determinant(); });
  return r;
}

Eigen::MatrixXd TetModel::cauchy_stresses(const Eigen::VectorXd& d) const {
  Eigen::MatrixXd s(num_tets(), 6);
  tbb::parallel_for(0, num_tets(), [&](int t) {
    const Eigen::Matrix3d c = cauchy_stress(params_, deformation_gradient(d, t));
    s.row(t) << c(0, 0), c(1, 1), c(2, 2), c(1, 2), c(0, 2), c(0, 1);
  });
  return s;
}

}  // namespace tetfsi::solid
