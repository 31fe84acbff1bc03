#pragma once
// The tile at rest for one parameter set (thesis 6.5.2): the rest-shape heuristic run from the
// tile as read (rest lengths and curvatures reset towards a relaxed state, the period
// stretched to relax its normal rest stress), then, with ObjectiveOptions::rest_period, the
// period relaxed to the tile's own stress-free rest.
//
// Every swarm candidate gets its own (its parameters set the tile's rest geometry: a contact
// radius 10 % off changes every stress). The fit's local step holds one while it moves the
// parameters, and relaxes it again between local runs: the alternation of 6.5.2/6.5.3, which
// also lets the residual Jacobian leave the rest shape's own dependence on θ out honestly.
// Always from the tile as read, never from another parameter set's rest state, so that a rest
// state is a function of its parameters alone (the swarm's cutoff, its resume and the
// alternation's fixed point rely on it).

#include <Eigen/Core>
#include <optional>
#include <string>

#include "yarn_fit/homogenise/rest_period.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

struct RestStateOptions {
  bool rest_shape = true;    // run the heuristic (off: the tile as read, an ablation)
  yarn::RestShapeOptions rest;
  bool rest_period = false;  // then relax the period to zero coarse normal stress
  yarn::RestPeriodOptions period;
};

struct RestState {
  bool ok = false;
  std::string message;        // why not (a solve of the heuristic or the period did not converge)
  yarn::YarnParams params;    // what it was relaxed with
  // The tile with the rest lengths, rest curvatures and period of the relaxation, at χ = 0,
  // with its contact list as the relaxation left it (each direction's sweep starts from a copy).
  std::optional<yarn::YarnSystem> system;
  Eigen::VectorXd g;          // the relaxed state at χ = 0
  yarn::RestShapeResult rest;
  yarn::RestPeriodResult period;
  int newton_iterations = 0;
  double seconds = 0.0;
};

// Never throws for numerical trouble (ok = false with the reason).
RestState relax_rest_state(const yarn::YarnTile& tile, const yarn::YarnParams& params, const RestStateOptions& options);

}  // namespace yarnfit::yarn
