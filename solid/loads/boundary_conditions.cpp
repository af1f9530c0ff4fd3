#include "solid/loads/boundary_conditions.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tetfsi::solid {

void fix_nodes(BoundaryConditions& bc, const std::vector<int>& nodes) {
  for (int c = 0; c < 3; ++c) fix_component(bc, nodes, c);
}

void fix_component(BoundaryConditions& bc, const std::vector<int>& nodes, int component) {
  if (component < 0 || component > 2) {
    throw std::invalid_argument("fix_component: component must be 0, 1 or 2, got " + std::to_string(component));
  }
  for (int v : nodes) bc.fixed_dofs.push_back(3 * v + component);
}

void prescribe_displacement(BoundaryConditions& bc, const std::vector<int>& nodes, const Eigen::Vector3d& u) {
  for (int v : nodes) {
    for (int c = 0; c < 3; ++c) bc.prescribed.emplace_back(3 * v + c, u(c));
  }
}

void add_nodal_force(BoundaryConditions& bc, int num_nodes, const std::vector<int>& nodes, const Eigen::Vector3d& f) {
  if (bc.forces.size() == 0) bc.forces.setZero(3 * num_nodes);
  for (int v : nodes) {
    if (v < 0 || v >= num_nodes) throw std::invalid_argument("add_nodal_force: node " + std::to_string(v) + " out of range");
    bc.forces.segment<3>(3 * v) += f;
  }
}

namespace {
// Calls fn(N, X, dA vector) at the quadrature points of the reference face.
template <class Fn>
void integrate_face(const std::vector<Eigen::Vector3d>& vertices, const SurfaceFace& face, Fn&& fn) {
  for_each_face_point(face, [&](int v) { return vertices[v]; },
                      [&](const FacePoint& p, const Eigen::Vector3d& X, const Eigen::Vector3d& Xs,
                          const Eigen::Vector3d& Xt) { fn(p.N, X, Eigen::Vector3d(p.weight * Xs.cross(Xt))); });
}
}  // namespace

void add_surface_traction(BoundaryConditions& bc, const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<SurfaceFace>& faces,
                          const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& traction) {
  if (bc.forces.size() == 0) bc.forces.setZero(3 * static_cast<int>(vertices.size()));
  for (const auto& q : faces) {
    integrate_face(vertices, q, [&](const Eigen::Vector4d& N, const Eigen::Vector3d& X, const Eigen::Vector3d& dA) {
      const Eigen::Vector3d t = traction(X) * dA.norm();
      for (int a = 0; a < face_node_count(q); ++a) bc.forces.segment<3>(3 * q[a]) += N(a) * t;
    });
  }
}

void add_end_moment_traction(BoundaryConditions& bc, const std::vector<Eigen::Vector3d>& vertices,
                             const std::vector<SurfaceFace>& faces, const Eigen::Vector3d& axis, double moment) {
  if (faces.empty()) throw std::invalid_argument("add_end_moment_traction: no faces selected");
  // Area, centroid and the common normal.
  double area = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  for (const auto& q : faces) {
    integrate_face(vertices, q, [&](const Eigen::Vector4d&, const Eigen::Vector3d& X, const Eigen::Vector3d& dA) {
      area += dA.norm();
      c += dA.norm() * X;
      n += dA;
    });
  }
  c /= area;
  n.normalize();
  for (const auto& q : faces) {
    integrate_face(vertices, q, [&](const Eigen::Vector4d&, const Eigen::Vector3d&, const Eigen::Vector3d& dA) {
      if (dA.normalized().dot(n) < 1.0 - 1e-9) {
        throw std::invalid_argument("add_end_moment_traction: the end faces are not planar with one normal");
      }
    });
  }
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d w = n.cross(a);
  if (std::abs(a.dot(n)) > 1e-9) throw std::invalid_argument("add_end_moment_traction: axis must lie in the face");
  double I = 0.0;
  for (const auto& q : faces) {
    integrate_face(vertices, q, [&](const Eigen::Vector4d&, const Eigen::Vector3d& X, const Eigen::Vector3d& dA) {
      I += std::pow((X - c).dot(w), 2) * dA.norm();
    });
  }
  add_surface_traction(bc, vertices, faces, [&](const Eigen::Vector3d& X) -> Eigen::Vector3d {
    return (moment / I) * (X - c).dot(w) * n;
  });
}

void add_body_force(BoundaryConditions& bc, const Eigen::VectorXd& masses, double density,
                    const std::vector<int>& nodes, const Eigen::Vector3d& b) {
  if (!(density > 0.0)) throw std::invalid_argument("add_body_force: density must be > 0");
  const int n = static_cast<int>(masses.size());
  if (bc.forces.size() == 0) bc.forces.setZero(3 * n);
  for (int v : nodes) {
    if (v < 0 || v >= n) throw std::invalid_argument("add_body_force: node " + std::to_string(v) + " out of range");
    bc.forces.segment<3>(3 * v) += (masses(v) / density) * b;
  }
}

}  // namespace tetfsi::solid
