// The three solvers of eq. (7) of Chentanez et al. 2006 agree with a dense LU of the same system to their tolerance,
// report honestly, and never fall back silently.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <vector>

#include "coupling/solvers/coupled_solver.hpp"
#include "support/binary_stream.hpp"

using namespace tetfsi::coupling;

namespace {

// A system with the structure of eq. (7) at a realistic scale: a chain of solid nodes
// (A = M/h + (h/2)K, mass 0.1 kg per node, springs 1e4 N/m, h = 1/60 s) whose last 6 dofs touch
// a 2D grid of pressure nodes through H (areas ~1e-2 m²), and P = (h/ρ) L with L a 5-point
// Laplacian (ρ = 1000 kg/m³) with one Dirichlet node, so P is positive definite.
CoupledSystem make_system(int solid_nodes, int grid) {
  const double h = 1.0 / 60, mass = 0.1, k = 1e4, rho = 1000, cell = 0.05;
  const int n = solid_nodes, m = grid * grid;
  std::vector<Eigen::Triplet<double>> ta, tc, th;
  for (int i = 0; i < n; ++i) {
    ta.emplace_back(i, i, mass / h + (h / 2) * 2 * k);
    if (i + 1 < n) {
      ta.emplace_back(i, i + 1, -(h / 2) * k);
      ta.emplace_back(i + 1, i, -(h / 2) * k);
    }
  }
  auto id = [grid](int x, int y) { return x + grid * y; };
  for (int y = 0; y < grid; ++y)
    for (int x = 0; x < grid; ++x) {
      double diag = (x == 0 && y == 0) ? 1.0 : 0.0;  // Dirichlet-like anchor at node 0
      const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[0] >= grid || q[1] >= grid) continue;
        tc.emplace_back(id(x, y), id(q[0], q[1]), -(h / rho) * cell);
        diag += 1.0;
      }
      tc.emplace_back(id(x, y), id(x, y), (h / rho) * cell * diag);
    }
  for (int j = 0; j < 6 && j < n; ++j) {
    const int a = n - 1 - j;
    th.emplace_back(m - 1 - j, a, cell * cell * 4);
    th.emplace_back(m - 2 - j, a, cell * cell * 2);
  }
  CoupledSystem s;
  s.A.resize(n, n);
  s.A.setFromTriplets(ta.begin(), ta.end());
  s.P.resize(m, m);
  s.P.setFromTriplets(tc.begin(), tc.end());
  s.H.resize(m, n);
  s.H.setFromTriplets(th.begin(), th.end());
  s.b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);      // forces [N]
  s.r = 1e-3 * Eigen::VectorXd::LinSpaced(m, 1.0, -1.0);  // fluxes [m³/s]
  return s;
}

constexpr double kMildDrift = 5.0;

Eigen::VectorXd dense_reference(const CoupledSystem& s) {
  const Eigen::MatrixXd K(paper_form_matrix(s));
  Eigen::VectorXd rhs(s.b.size() + s.r.size());
  rhs << s.b, s.r;
  return K.partialPivLu().solve(rhs);
}

}  // namespace

class CoupledSolvers : public ::testing::TestWithParam<CoupledSolverKind> {};

TEST_P(CoupledSolvers, AgreeWithDenseLU) {
  const CoupledSystem s = make_system(30, 12);
  const Eigen::VectorXd ref = dense_reference(s);
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  auto solver = make_coupled_solver(GetParam(), options);
  Eigen::VectorXd u, p;
  const CoupledSolveReport report = solver->solve(s, u, p);
  EXPECT_LE(report.residual.max(), 1e-10) << report.solver;
  const double err_u = (u - ref.head(u.size())).norm() / ref.head(u.size()).norm();
  const double err_p = (p - ref.tail(p.size())).norm() / ref.tail(p.size()).norm();
  // The system's condition number here is ~1e4, so 1e-10 residuals give ~1e-6 errors at most.
  EXPECT_LT(err_u, 1e-6) << report.solver;
  EXPECT_LT(err_p, 1e-6) << report.solver;
  EXPECT_FALSE(report.solver.empty());
}

TEST_P(CoupledSolvers, RejectsMismatchedBlocks) {
  CoupledSystem s = make_system(10, 4);
  s.r.resize(3);
  Eigen::VectorXd u, p;
  EXPECT_THROW(make_coupled_solver(GetParam())->solve(s, u, p), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, CoupledSolvers,
                         ::testing::Values(CoupledSolverKind::Umfpack, CoupledSolverKind::BiCGSTAB,
                                           CoupledSolverKind::SchurCG),
                         [](const auto& info) { return to_string(info.param); });

TEST(CoupledSolversReport, IterativeSolverThatStopsEarlyThrowsInsteadOfFallingBack) {
  const CoupledSystem s = make_system(30, 12);
  CoupledSolverOptions options;
  options.max_iterations = 1;
  for (auto kind : {CoupledSolverKind::BiCGSTAB, CoupledSolverKind::SchurCG}) {
    Eigen::VectorXd u, p;
    EXPECT_THROW(make_coupled_solver(kind, options)->solve(s, u, p), CoupledSolveError) << to_string(kind);
  }
}

TEST(CoupledSolversReport, SchurCGReusesItsFactorAnalysisOnlyWhileThePatternHolds) {
  // One solver object over a sequence of systems, as in a run: same pattern with new values
  // (CHOLMOD's analysis is kept), then a larger system (re-analysed), then a smaller one again.
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  auto solver = make_coupled_solver(CoupledSolverKind::SchurCG, options);
  CoupledSystem stiffer = make_system(30, 12);
  stiffer.A = 3.0 * stiffer.A;
  for (const CoupledSystem& s : {make_system(30, 12), stiffer, make_system(45, 12), make_system(30, 12)}) {
    const Eigen::VectorXd ref = dense_reference(s);
    Eigen::VectorXd u, p;
    solver->solve(s, u, p);
    EXPECT_LT((u - ref.head(u.size())).norm(), 1e-6 * ref.head(u.size()).norm()) << s.A.rows();
    EXPECT_LT((p - ref.tail(p.size())).norm(), 1e-6 * ref.tail(p.size()).norm()) << s.A.rows();
  }
}

TEST(CoupledSolversReport, SchurCGLagsItsBlocksThenRebuildsThemWhenTheyDrift) {
  // A run-like sequence on one solver: a fresh solve (Schur CG), a lagged one on new values
  // (GMRES with the earlier factor, as many iterations as the fresh solve), then a solid block whose
  // diagonal grows up to 300x along the chain (the lagged blocks are too far off: GMRES misses its
  // cap and the step is solved fresh), then the same system again, lagged on the new factor. Every
  // answer matches the dense LU. (The rebuild rule itself: SchurCGRebuildsOnceTheLaggedSolvesCostTwoFreshOnes.)
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  auto solver = make_coupled_solver(CoupledSolverKind::SchurCG, options);
  CoupledSystem first = make_system(30, 12), second = first, drifted = first;
  second.A = 1.02 * first.A;
  second.b *= -0.5;
  for (int i = 0; i < drifted.A.rows(); ++i) drifted.A.coeffRef(i, i) *= 1.0 + 300.0 * i * i / 900.0;
  std::vector<CoupledSolveReport> reports;
  for (const CoupledSystem* s : {&first, &second, &drifted, &drifted}) {
    const Eigen::VectorXd ref = dense_reference(*s);
    Eigen::VectorXd u, p;
    reports.push_back(solver->solve(*s, u, p));
    EXPECT_LE(reports.back().residual.max(), 1e-10) << reports.size();
    EXPECT_LT((u - ref.head(u.size())).norm(), 1e-6 * ref.head(u.size()).norm()) << reports.size();
    EXPECT_LT((p - ref.tail(p.size())).norm(), 1e-6 * ref.tail(p.size()).norm()) << reports.size();
  }
  EXPECT_EQ(reports[0].solver, "schur_cg+ic");
  EXPECT_EQ(reports[0].factor_age, 0);
  EXPECT_EQ(reports[1].solver, "block_gmres+ic");
  EXPECT_EQ(reports[1].factor_age, 1);
  EXPECT_LE(reports[1].iterations, reports[0].iterations + 3);
  // The drifted system: GMRES with the old blocks misses its cap (3x the fresh iterations + 20),
  // so the step is solved fresh, its report counting the lagged attempt's iterations too.
  EXPECT_EQ(reports[2].factor_age, 0) << reports[2].solver;
  EXPECT_GT(reports[2].iterations, 3 * reports[0].iterations + 20);
  EXPECT_LE(reports[3].factor_age, 1);
  EXPECT_LE(reports[3].iterations, reports[0].iterations + 3);
}

TEST(CoupledSolversReport, SchurCGGoesOnWithGmresWhenTheSolidBlockLosesDefiniteness) {
  // A with one negative diagonal entry (an uncoupled dof at the far end of the chain): no
  // Cholesky exists and CG on the Schur complement is not defined, but GMRES preconditioned with
  // the factor of the earlier SPD A solves the system. A solver that never saw an SPD A must
  // refuse, naming the cause.
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  const CoupledSystem first = make_system(30, 12);
  CoupledSystem indefinite = first;
  indefinite.A.coeffRef(0, 0) *= -0.1;
  const Eigen::VectorXd ref = dense_reference(indefinite);
  auto solver = make_coupled_solver(CoupledSolverKind::SchurCG, options);
  Eigen::VectorXd u, p;
  solver->solve(first, u, p);
  for (int k = 1; k <= 2; ++k) {
    const CoupledSolveReport report = solver->solve(indefinite, u, p);
    EXPECT_EQ(report.solver, "block_gmres+ic");
    EXPECT_EQ(report.factor_age, k);
    EXPECT_LT((u - ref.head(u.size())).norm(), 1e-6 * ref.head(u.size()).norm());
    EXPECT_LT((p - ref.tail(p.size())).norm(), 1e-6 * ref.tail(p.size()).norm());
  }
  try {
    make_coupled_solver(CoupledSolverKind::SchurCG, options)->solve(indefinite, u, p);
    ADD_FAILURE() << "an indefinite A with no earlier factor must throw";
  } catch (const CoupledSolveError& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
  }
}

/// A copy of `s` whose solid block's diagonal grows along the chain by up to `factor` - 1: a drift
/// that the lagged factor of `s` handles with more iterations.
CoupledSystem drift(const CoupledSystem& s, double factor) {
  CoupledSystem d = s;
  const double n = static_cast<double>(d.A.rows());
  for (int i = 0; i < d.A.rows(); ++i) d.A.coeffRef(i, i) *= 1.0 + (factor - 1.0) * (i / n) * (i / n);
  return d;
}

/// The same drift of the fluid block P (the pressure Schur complement's preconditioner lags it;
/// refactorizing A does not help).
CoupledSystem drift_fluid(const CoupledSystem& s, double factor) {
  CoupledSystem d = s;
  const double m = static_cast<double>(d.P.rows());
  for (int i = 0; i < d.P.rows(); ++i) d.P.coeffRef(i, i) *= 1.0 + (factor - 1.0) * (i / m) * (i / m);
  return d;
}

/// Lagged solves of `s` (no warm start, so each does the same work) until their iterations beyond
/// `fresh` add up to `budget` (at most 20 solves); each must be lagged and cost extra iterations.
struct LaggedSolves {
  int extra = 0;                  ///< iterations beyond `fresh`, summed
  std::vector<int> ages;          ///< factor_age of each solve
  int last_iterations = 0;
};
LaggedSolves lag_until(CoupledSolver& solver, const CoupledSystem& s, int fresh, int budget) {
  LaggedSolves run;
  for (int k = 1; k <= 20 && run.extra < budget; ++k) {
    Eigen::VectorXd u, p;
    const CoupledSolveReport r = solver.solve(s, u, p);
    EXPECT_EQ(r.solver, "block_gmres+ic") << "solve " << k << " should be lagged and converge within the cap";
    EXPECT_GT(r.iterations, fresh) << "the drift must cost extra iterations";
    run.extra += r.iterations - fresh;
    run.ages.push_back(r.factor_age);
    run.last_iterations = r.iterations;
  }
  return run;
}

TEST(CoupledSolversReport, SchurCGRefactorizesTheSolidBlockOnceItsDriftCostsHalfAFreshSolve) {
  // The solid block drifts: the lagged solves cost extra iterations; once these add up to half the
  // fresh solve's, the next solve refactorizes A alone (still GMRES with Ŝ's lagged preconditioner,
  // factor age 0) and needs fewer iterations than the lagged solve before it. An indefinite A
  // arriving then cannot be factorized: the earlier SPD factor must stay and solve it.
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  const CoupledSystem first = make_system(30, 12);
  const CoupledSystem mild = drift(first, kMildDrift);
  for (bool indefinite : {false, true}) {
    auto solver = make_coupled_solver(CoupledSolverKind::SchurCG, options);
    Eigen::VectorXd u, p;
    const int fresh = solver->solve(first, u, p).iterations;
    const LaggedSolves lagged = lag_until(*solver, mild, fresh, fresh / 2);
    ASSERT_GE(lagged.extra, fresh / 2);
    const int k = static_cast<int>(lagged.ages.size());
    for (int i = 0; i < k; ++i) ASSERT_EQ(lagged.ages[i], i + 1);
    CoupledSystem next = mild;
    if (indefinite) next.A.coeffRef(0, 0) *= -0.1;
    const Eigen::VectorXd ref = dense_reference(next);
    u.resize(0), p.resize(0);
    const CoupledSolveReport r = solver->solve(next, u, p);
    EXPECT_EQ(r.solver, "block_gmres+ic");
    if (indefinite) {
      EXPECT_EQ(r.factor_age, k + 1);  // the kept factor
    } else {
      EXPECT_EQ(r.factor_age, 0);  // A refactorized for this solve
      EXPECT_LT(r.iterations, lagged.last_iterations);
    }
    EXPECT_LT((u - ref.head(u.size())).norm(), 1e-6 * ref.head(u.size()).norm());
    EXPECT_LT((p - ref.tail(p.size())).norm(), 1e-6 * ref.tail(p.size()).norm());
  }
}

TEST(CoupledSolversReport, SchurCGRebuildsOnceTheLaggedSolvesCostTwoFreshOnes) {
  // The rent-or-buy rule for both blocks (GMRES converging every time): lagged solves of a system
  // whose fluid block drifted cost extra iterations that refactorizing A does not remove; once
  // their sum reaches twice the fresh solve's, the next solve must be fresh. Then an indefinite A
  // arrives while a rebuild is due: the refactorization fails, the earlier SPD factor must still be
  // intact and solve it.
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  const CoupledSystem first = make_system(30, 12);
  const CoupledSystem mild = drift_fluid(first, kMildDrift);
  for (bool indefinite_at_rebuild : {false, true}) {
    auto solver = make_coupled_solver(CoupledSolverKind::SchurCG, options);
    Eigen::VectorXd u, p;
    const int fresh = solver->solve(first, u, p).iterations;
    const LaggedSolves lagged = lag_until(*solver, mild, fresh, 2 * fresh);
    ASSERT_GE(lagged.extra, 2 * fresh);
    const int age = lagged.ages.back();
    CoupledSystem next = first;
    if (indefinite_at_rebuild) next.A.coeffRef(0, 0) *= -0.1;
    const Eigen::VectorXd ref = dense_reference(next);
    u.resize(0), p.resize(0);
    const CoupledSolveReport r = solver->solve(next, u, p);
    if (indefinite_at_rebuild) {
      EXPECT_EQ(r.solver, "block_gmres+ic");  // the kept factor, with Ŝ's preconditioner rebuilt
      EXPECT_EQ(r.factor_age, age + 1);
    } else {
      EXPECT_EQ(r.solver, "schur_cg+ic");  // rebuilt
      EXPECT_EQ(r.factor_age, 0);
    }
    EXPECT_LT((u - ref.head(u.size())).norm(), 1e-6 * ref.head(u.size()).norm());
    EXPECT_LT((p - ref.tail(p.size())).norm(), 1e-6 * ref.tail(p.size()).norm());
  }
}

TEST(CoupledSolversReport, SchurCGWithoutCheckpointStateSolvesTheSameAndRefusesToWriteIt) {
  // keep_checkpoint_state = false frees Ŝ once its preconditioner is set up: the fresh and the
  // lagged solves must give the same bits as with Ŝ kept, and write_state must refuse.
  CoupledSolverOptions keep, drop;
  keep.tolerance = drop.tolerance = 1e-10;
  drop.keep_checkpoint_state = false;
  const CoupledSystem first = make_system(30, 12);
  const CoupledSystem mild = drift(first, kMildDrift);
  auto kept = make_coupled_solver(CoupledSolverKind::SchurCG, keep);
  auto dropped = make_coupled_solver(CoupledSolverKind::SchurCG, drop);
  for (const CoupledSystem* s : {&first, &mild, &mild}) {
    Eigen::VectorXd u_kept, p_kept, u_dropped, p_dropped;
    const CoupledSolveReport a = kept->solve(*s, u_kept, p_kept);
    const CoupledSolveReport b = dropped->solve(*s, u_dropped, p_dropped);
    EXPECT_EQ(a.solver, b.solver);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(u_kept, u_dropped);
    EXPECT_EQ(p_kept, p_dropped);
  }
  tetfsi::BinaryWriter out;
  EXPECT_NO_THROW(kept->write_state(out));
  EXPECT_THROW(dropped->write_state(out), std::logic_error);
}

TEST(CoupledSolversReport, SchurCGWithoutReuseFactorizesEverySolve) {
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  options.reuse_factorization = false;
  auto solver = make_coupled_solver(CoupledSolverKind::SchurCG, options);
  const CoupledSystem s = make_system(30, 12);
  const Eigen::VectorXd ref = dense_reference(s);
  for (int k = 0; k < 2; ++k) {
    Eigen::VectorXd u, p;
    const CoupledSolveReport report = solver->solve(s, u, p);
    EXPECT_EQ(report.solver, "schur_cg+ic");
    EXPECT_EQ(report.factor_age, 0);
    EXPECT_LT((u - ref.head(u.size())).norm(), 1e-6 * ref.head(u.size()).norm());
    EXPECT_LT((p - ref.tail(p.size())).norm(), 1e-6 * ref.tail(p.size()).norm());
  }
}

TEST(CoupledSolversReport, SchurCGDecouplesTheBlocksOnlyWhereTheSolidHardlyAnswersThePressure) {
  // A solid 1e4 times heavier (mass 1 t per node against kg fluxes): its velocity answer to the
  // pressure forces, H zᵤ, is a tiny part of the fluid block's right-hand side, so from the second
  // lagged solve on the preconditioner is the block diagonal (its two blocks side by side), with
  // no more iterations than the block triangle. The system as made (share above 0.05) keeps the
  // block triangle. Every answer matches the dense LU.
  CoupledSolverOptions options;
  options.tolerance = 1e-10;
  CoupledSystem heavy = make_system(30, 12);
  heavy.A *= 1e4;
  for (const bool weak : {true, false}) {
    const CoupledSystem s = weak ? heavy : make_system(30, 12);
    const Eigen::VectorXd ref = dense_reference(s);
    auto solver = make_coupled_solver(CoupledSolverKind::SchurCG, options);
    std::vector<CoupledSolveReport> reports;
    for (int k = 0; k < 4; ++k) {
      Eigen::VectorXd u, p;
      reports.push_back(solver->solve(s, u, p));
      EXPECT_LT((u - ref.head(u.size())).norm(), 1e-6 * ref.head(u.size()).norm()) << weak << " " << k;
      EXPECT_LT((p - ref.tail(p.size())).norm(), 1e-6 * ref.tail(p.size()).norm()) << weak << " " << k;
    }
    EXPECT_EQ(reports[0].solver, "schur_cg+ic");
    EXPECT_EQ(reports[1].solver, "block_gmres+ic") << weak;  // measures the coupling first
    for (int k = 2; k < 4; ++k) {
      EXPECT_EQ(reports[k].solver, weak ? "block_diagonal_gmres+ic" : "block_gmres+ic") << k;
      if (weak) EXPECT_LE(reports[k].iterations, reports[1].iterations + 1) << k;
    }
    if (!weak) continue;
    // A solid block that drifted far (its diagonal up to 300x): the lagged block diagonal misses
    // its cap and the step is solved fresh; the next lagged solve goes back to the block triangle.
    CoupledSystem drifted = heavy;
    for (int i = 0; i < drifted.A.rows(); ++i) drifted.A.coeffRef(i, i) *= 1.0 + 300.0 * i * i / 900.0;
    const Eigen::VectorXd drifted_ref = dense_reference(drifted);
    for (int k = 0; k < 2; ++k) {
      Eigen::VectorXd u, p;
      const CoupledSolveReport r = solver->solve(drifted, u, p);
      EXPECT_EQ(r.factor_age, k) << r.solver;
      if (k == 1) EXPECT_EQ(r.solver, "block_gmres+ic");
      EXPECT_LT((u - drifted_ref.head(u.size())).norm(), 1e-6 * drifted_ref.head(u.size()).norm()) << k;
      EXPECT_LT((p - drifted_ref.tail(p.size())).norm(), 1e-6 * drifted_ref.tail(p.size()).norm()) << k;
    }
  }
}

TEST(CoupledSolversReport, PressureOnlySystemIsAPlainProjection) {
  // No solid: eq. (7) reduces to the fluid projection P p = r.
  CoupledSystem s = make_system(30, 8);
  s.A.resize(0, 0);
  s.H.resize(s.P.rows(), 0);
  s.b.resize(0);
  const Eigen::VectorXd ref = Eigen::MatrixXd(s.P).llt().solve(s.r);
  for (auto kind : {CoupledSolverKind::Umfpack, CoupledSolverKind::SchurCG}) {
    Eigen::VectorXd u, p;
    make_coupled_solver(kind)->solve(s, u, p);
    EXPECT_LT((p - ref).norm() / ref.norm(), 1e-8) << to_string(kind);
  }
}

TEST(CoupledSolversReport, ParsesNames) {
  EXPECT_EQ(parse_coupled_solver_kind("schur_cg"), CoupledSolverKind::SchurCG);
  EXPECT_THROW(parse_coupled_solver_kind("cholesky"), std::invalid_argument);
}
