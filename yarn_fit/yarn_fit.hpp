#pragma once
// yarn_fit — periodic yarn-level simulation and fit of yarn parameters.
//
// Planned contents (SPEC §1 step 3, §3 "Yarn", "Parameters"; thesis 3.2, A.1–A.2, 6.4–6.5):
//   energies/   biphasic stretch (6.5), bending with rest curvature (6.6), twist (optional),
//               two-barrier contact with Simpson quadrature (6.7)
//   periodic/   ghost copies, co-rotated periodic conditions, fractional counting
//   solver/     constrained Newton (3.32) with the A.2.3 regulariser and step limit
//   homogenise/ energy density (6.8), stretch stress (6.10), zero-orthogonal-stress compression
//   rest_shape/ alternating rest-length / rest-curvature heuristic (6.5.2)
//   fit/        swarm global step + COBYLA refinement on p = {ks1, ε̄s, kb, R1, kc1} (6.5.3)
// This module has no code yet; the target exists so the dependency graph is fixed.
namespace yarnfit::yarn {}
