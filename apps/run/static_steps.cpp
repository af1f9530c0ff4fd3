#include "apps/run/static_steps.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>

#include "apps/run/errors.hpp"

namespace tetfsi::run {

StaticSteps solve_in_steps(const std::string& name, const solid::ElasticModel& model,
                           const solid::BoundaryConditions& bc, const solid::StaticOptions& options,
                           spdlog::logger& log) {
  StaticSteps s;
  s.load_factors = {0.0};
  s.states = {Eigen::VectorXd::Zero(3 * model.num_nodes())};
  auto on_step = [&](const solid::StepLog& l, const Eigen::VectorXd& u) {
    std::string ratios;
    for (std::size_t k = 1; k < l.residuals.size(); ++k)
      ratios += fmt::format(" {:.3g}", l.residuals[k - 1] > 0 ? l.residuals[k] / l.residuals[k - 1] : 0.0);
    log.info("solid '{}': load factor {:.6g}: {} Newton solves ({} with the projected tangent), {} cuts, "
             "residuals [{}], ratios [{} ]", name, l.load_factor, l.iterations, l.modified_tangent_solves, l.cuts,
             fmt::join(l.residuals, ", "), ratios);
    s.load_factors.push_back(l.load_factor);
    s.states.push_back(u);
    s.logs.push_back(l);
    double m = 0;
    if (!bc.rotating_faces.empty()) {
      Eigen::Vector3d f, mom;
      solid::face_reaction(model, bc.rotating_faces[0], u, f, mom);
      m = mom.dot(bc.rotating_faces[0].axis.normalized());
    }
    s.moments.push_back(m);
  };
  try {
    const auto result = solid::solve_static(model, bc, options, 1.0, on_step);
    s.assembly_seconds = result.assembly_seconds;
    s.solve_seconds = result.solve_seconds;
  } catch (const solid::NonConvergence& e) {
    throw RunError(fmt::format("solid '{}': static solve failed: {}", name, e.what()));
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("solid '{}': {}", name, e.what()));
  }
  return s;
}

const Eigen::VectorXd& state_at(const StaticSteps& steps, double lambda) {
  if (lambda < 0) return steps.states.back();
  std::size_t k = 0;
  while (k + 1 < steps.load_factors.size() && steps.load_factors[k + 1] <= lambda + 1e-12) ++k;
  return steps.states[k];
}

void write_load_steps(Output& out, const std::string& name, const StaticSteps& steps) {
  std::ofstream csv(out.dir() / fmt::format("{}_load_steps.csv", name));
  csv << "load_factor,iterations,cuts,final_residual_ratio,reaction_moment,projected_tangent_solves\n";
  for (std::size_t k = 0; k < steps.logs.size(); ++k) {
    const auto& l = steps.logs[k];
    csv << csv_row({l.load_factor, double(l.iterations), double(l.cuts),
                    l.residuals.empty() ? 0.0 : l.residuals.back(), steps.moments[k],
                    double(l.modified_tangent_solves)});
  }
}

std::vector<double> static_totals(const std::vector<const StaticSteps*>& solids) {
  double steps = 0, its = 0, max_its = 0, cuts = 0;
  for (const auto* s : solids)
    for (const auto& l : s->logs) {
      steps += 1;
      its += l.iterations;
      max_its = std::max(max_its, double(l.iterations));
      cuts += l.cuts;
    }
  return {steps, its, max_its, cuts};
}

}  // namespace tetfsi::run
