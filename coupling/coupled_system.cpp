#include "coupling/coupled_system.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace tetfsi::coupling {

void CoupledSystem::check_sizes() const {
  const auto n = A.rows(), m = P.rows();
  auto fail = [](const std::string& what) { throw std::invalid_argument("coupled system: " + what); };
  if (A.cols() != n) fail("A is not square");
  if (P.cols() != m) fail("P is not square");
  if (H.rows() != m || H.cols() != n)
    fail("H is " + std::to_string(H.rows()) + "x" + std::to_string(H.cols()) + ", expected " +
         std::to_string(m) + "x" + std::to_string(n));
  if (b.size() != n) fail("b has " + std::to_string(b.size()) + " entries, expected " + std::to_string(n));
  if (r.size() != m) fail("r has " + std::to_string(r.size()) + " entries, expected " + std::to_string(m));
}

BlockResiduals residuals(const CoupledSystem& s, const Eigen::VectorXd& u, const Eigen::VectorXd& p) {
  const Eigen::VectorXd Au = s.A * u, Htp = s.H.transpose() * p, Hu = s.H * u, Pp = s.P * p;
  auto rel = [](double res, double a, double b, double c) {
    const double scale = std::max({a, b, c});
    return scale > 0 ? res / scale : res;
  };
  BlockResiduals out;
  out.solid = rel((Au - Htp - s.b).norm(), s.b.norm(), Au.norm(), Htp.norm());
  out.fluid = rel((Hu + Pp - s.r).norm(), s.r.norm(), Hu.norm(), Pp.norm());
  return out;
}

SparseMatrix paper_form_matrix(const CoupledSystem& s) {
  s.check_sizes();
  const int n = s.num_solid_dofs(), m = s.num_pressures();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(s.A.nonZeros() + 2 * s.H.nonZeros() + s.P.nonZeros());
  for (int k = 0; k < s.A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(s.A, k); it; ++it) t.emplace_back(it.row(), it.col(), it.value());
  for (int k = 0; k < s.H.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(s.H, k); it; ++it) {
      t.emplace_back(n + it.row(), it.col(), it.value());   // H  (fluid row)
      t.emplace_back(it.col(), n + it.row(), -it.value());  // −Hᵀ = −J (solid row)
    }
  for (int k = 0; k < s.P.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(s.P, k); it; ++it) t.emplace_back(n + it.row(), n + it.col(), it.value());
  SparseMatrix K(n + m, n + m);
  K.setFromTriplets(t.begin(), t.end());
  return K;
}

}  // namespace tetfsi::coupling
