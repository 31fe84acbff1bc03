// The yarn bending term (yarn_fit/energies/yarn_bending_term.hpp) over the real stockinette tile:
// its assembled gradient and Hessian in the tile's DOFs against finite differences, in-plane
// and curved, and its PSD projection.

#include <gtest/gtest.h>

#include "tests/yarn_fit/energies/term_check.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

TEST_F(StockinetteSystem, YarnBendingTermDerivativesMatchFiniteDifferences) {
  expect_yarn_term_derivatives(tile, params, "bending");
}

}  // namespace
}  // namespace yarnfit::yarn
