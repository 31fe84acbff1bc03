#pragma once
// swarm — the optimisers of the yarn-level calibration (SPEC §1 step 4, thesis 6.5.3), with
// no knowledge of fabrics:
//   * run_swarm / resume_swarm (particle_swarm.hpp): global search by a particle swarm,
//     parallel, reproducible, checkpointed after every iteration;
//   * run_cobyla (cobyla.hpp): local refinement of the swarm's best by NLopt's COBYLA,
//     returning the best point seen within bounds and budgets;
//   * run_implicit_filtering (implicit_filtering.hpp): local refinement of a least-squares
//     objective that is rough at small scales, by Gauss–Newton steps on stencil differences
//     whose scale shrinks as the search converges;
// over a ParameterSpace (parameter_space.hpp) of bounded, optionally log-space parameters.
// Failed evaluations are counted and penalised, never fatal (objective.hpp).

#include "swarm/cobyla.hpp"
#include "swarm/implicit_filtering.hpp"
#include "swarm/objective.hpp"
#include "swarm/parameter_space.hpp"
#include "swarm/particle_swarm.hpp"
