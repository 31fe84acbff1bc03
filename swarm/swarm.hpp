#pragma once
// swarm — a generic particle swarm optimiser (SPEC §1 step 4): bounds, log-space
// parameters, inertia decaying 0.9 → 0.1, repulsion between particles, particles evaluated
// in parallel. It knows nothing of fabrics. No code yet.
namespace yarnfit::swarm {}
