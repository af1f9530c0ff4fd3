#include "solid/loads/follower_pressure.hpp"

namespace tetfsi::solid {
namespace {
Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}
}  // namespace

void add_follower_pressure(const std::vector<PressureLoad>& loads, const Eigen::VectorXd& reference,
                           const Eigen::VectorXd& u, double scale, Eigen::VectorXd& force, SparseMatrix* dfdu) {
  auto position = [&](int v) -> Eigen::Vector3d { return reference.segment<3>(3 * v) + u.segment<3>(3 * v); };
  for (const auto& load : loads) {
    const double p = scale * load.pressure;
    if (p == 0.0) continue;
    for (const auto& face : load.faces) {
      const int n = face_node_count(face);
      for_each_face_point(face, position, [&](const FacePoint& g, const Eigen::Vector3d&, const Eigen::Vector3d& xs,
                                              const Eigen::Vector3d& xt) {
        const Eigen::Vector3d area = g.weight * xs.cross(xt);
        for (int a = 0; a < n; ++a) force.segment<3>(3 * face[a]) -= p * g.N(a) * area;
        if (!dfdu) return;
        const Eigen::Matrix3d Xs = cross_matrix(xs), Xt = cross_matrix(xt);
        for (int b = 0; b < n; ++b) {
          const Eigen::Matrix3d dA = g.weight * (g.dNdt(b) * Xs - g.dNds(b) * Xt);
          for (int a = 0; a < n; ++a) {
            const Eigen::Matrix3d block = -p * g.N(a) * dA;
            for (int j = 0; j < 3; ++j)
              for (int i = 0; i < 3; ++i) dfdu->coeffRef(3 * face[a] + i, 3 * face[b] + j) += block(i, j);
          }
        }
      });
    }
  }
}

FollowerLoadedModel::FollowerLoadedModel(const ElasticModel& base, std::vector<PressureLoad> pressures)
    : base_(base), pressures_(std::move(pressures)) {}

bool FollowerLoadedModel::evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const {
  if (!base_.evaluate(d, force, tangent)) return false;
  Eigen::VectorXd fp = Eigen::VectorXd::Zero(force.size());
  if (!tangent) {
    add_follower_pressure(pressures_, base_.reference_positions(), d, 1.0, fp, nullptr);
    force -= fp;
    return force.allFinite();
  }
  SparseMatrix dfdu = *tangent * 0.0;  // the tangent's pattern, zero values
  add_follower_pressure(pressures_, base_.reference_positions(), d, 1.0, fp, &dfdu);
  force -= fp;
  const SparseMatrix sym = SparseMatrix(dfdu.transpose());
  *tangent -= 0.5 * (dfdu + sym);
  return force.allFinite();
}

}  // namespace tetfsi::solid
