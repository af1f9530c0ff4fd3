#pragma once
/// @file preflight_models.hpp
/// Preflight's checks of the solids and models one scene combines (preflight.cpp).
#include <string>
#include <vector>

#include "apps/run/simulation.hpp"
#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// Combinations the chosen runner cannot simulate as written (kinematic beside deforming solids
/// outside the coupled and mpm runners, hex8 beside tet or with a fluid, volume meshes outside
/// their runner, mixed static and dynamic analyses, loads or static analysis outside the solid
/// runner, self-contact on a solid that cannot fold), each with its JSON pointer.
/// @param runner        the name of the runner the scene goes to (choose_runner)
/// @param meshes_fluid  the scene has a fluid on a tet mesh
std::vector<scene::Issue> model_mix_issues(const scene::Json& js, const std::string& runner, bool meshes_fluid);

/// export.checkpoint_every > 0 with a runner that does not write checkpoints for this scene
/// (RunnerEntry::checkpoints; checkpoint.hpp): the issue naming the key, or none.
std::vector<scene::Issue> checkpoint_issues(const scene::Scene& scene, const RunnerEntry& runner);

/// More than one MPI process (`mpirun -n N`): only the fluid and coupled runners distribute
/// anything (their pressure and coupled solves, on PETSc: parallel/mpi_session.hpp); any other
/// set-up would run N copies of the same serial run. The issues naming the key to change, or none.
std::vector<scene::Issue> process_issues(const scene::Json& js, const std::string& runner, int processes);

}  // namespace tetfsi::run
