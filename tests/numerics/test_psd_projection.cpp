// Per-element PSD projection (numerics/psd_projection.hpp): an indefinite block becomes the
// nearest PSD one (negative eigenvalues clamped at 0, eigenvectors kept); a PSD block is kept.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "numerics/psd_projection.hpp"

namespace yarnfit::numerics {
namespace {

TEST(PsdProjection, ClampsNegativeEigenvaluesAndKeepsTheRest) {
  const Eigen::Matrix3d q = Eigen::Quaterniond(0.3, -0.5, 0.7, 0.2).normalized().toRotationMatrix();
  const Eigen::Vector3d lambda(-2.0, 0.5, 3.0);
  Eigen::Matrix3d h = q * lambda.asDiagonal() * q.transpose();
  project_psd<3>(h);
  const Eigen::Matrix3d expected = q * Eigen::Vector3d(0.0, 0.5, 3.0).asDiagonal() * q.transpose();
  EXPECT_LT((h - expected).lpNorm<Eigen::Infinity>(), 1e-14);
  Eigen::Matrix3d psd = q * Eigen::Vector3d(1.0, 0.5, 3.0).asDiagonal() * q.transpose();
  const Eigen::Matrix3d before = 0.5 * (psd + psd.transpose());
  project_psd<3>(psd);
  EXPECT_EQ(psd, before);
}

}  // namespace
}  // namespace yarnfit::numerics
