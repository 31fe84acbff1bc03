// Exact sensitivities (yarn_fit/homogenise/sensitivity.hpp) against central differences on the
// real stockinette tile: the assembled parameter and F-derivatives at a fixed state, the
// homogenised tangent and the stresses' parameter derivatives at an equilibrium (re-solved at
// every difference step), and the first-order root correction of the free compression with
// dc*/dθ against the exact roots.

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/parameter_check.hpp"
#include "tests/yarn_fit/yarn_fixtures.hpp"
#include "yarn_fit/homogenise/sensitivity.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;
using testing::sweep_parameter;

Eigen::Vector4d vec(const Eigen::Matrix2d& m) { return {m(0, 0), m(1, 0), m(0, 1), m(1, 1)}; }

YarnParams toe_params(const db::PeriodicTile& tile) {
  YarnParams p = params_for(tile);
  p.ks1 = 0.05 * p.ks2;
  p.eps_s = 0.005;
  p.kc1 *= 2.0;
  p.r1 *= 0.9;
  return p;
}

// Each term on its own (a system of that term alone), at an equilibrium of the whole tile where
// every contact is engaged: the terms' derivatives differ by orders of magnitude, and a sum
// would hide the small ones in the round-off of the large.
TEST_F(StockinetteSystem, AssembledParameterAndDeformationDerivativesMatchDifferences) {
  const YarnParams p = toe_params(tile);
  // 35 % along the weft, held narrow: some edges in the stiff phase, some pressed into compression.
  const CoarseDeformation chi{0.35, 0.15, 0.0, weft_angle()};
  YarnSystem whole(make_yarn_tile(tile), p);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(whole.dof_count());
  ASSERT_TRUE(simulate_sample(whole, chi, g).ok);
  const std::vector<YarnParam> all(kAllYarnParams.begin(), kAllYarnParams.end());
  for (const YarnTermKind kind : all_yarn_terms()) {
    YarnSystem sys(make_yarn_tile(tile), p, {kind});
    sys.set_deformation(chi);
    sys.rebuild_contacts(g);
    const std::string term = sys.terms().front()->name();
    const ParameterDerivatives pd = sys.parameter_derivatives(g, all);
    int checked = 0;
    for (std::size_t k = 0; k < all.size(); ++k) {
      const auto column = static_cast<Eigen::Index>(k);
      if (pd.gradient.col(column).isZero() && pd.energy[column] == 0.0) continue;  // not this term's
      ++checked;
      const auto at = [&](double theta) {
        YarnSystem copy = sys;
        YarnParams q = p;
        set(q, all[k], theta);
        copy.set_params(q);
        copy.rebuild_contacts(g);
        return copy;
      };
      const auto energy_and_gradient = [&](double theta) {
        const YarnSystem copy = at(theta);
        Eigen::VectorXd grad;
        const double e = copy.energy_gradient(g, grad);
        return std::pair<double, Eigen::VectorXd>{e, grad};
      };
      const auto stress = [&](double theta) {
        const YarnSystem copy = at(theta);
        return std::pair<double, Eigen::VectorXd>{0.0, Eigen::VectorXd(vec(copy.coarse_stress(g)) * copy.area())};
      };
      const double theta = get(p, all[k]);
      const auto r = sweep_parameter(energy_and_gradient, theta, pd.energy[column], pd.gradient.col(column), 1e-300,
                                     1e-300);
      const std::string what = term + " term, " + to_string(all[k]);
      EXPECT_LT(r.value_error, 1e-6) << what << ": dE/dθ analytic " << pd.energy[column] << ", FD " << r.value_fd;
      EXPECT_LT(r.vector_error, 1e-6) << what << ": d(grad E)/dθ, worst entry " << r.worst;
      const auto s = sweep_parameter(stress, theta, 0.0, pd.affine.col(column), 1.0, 1e-300);
      EXPECT_LT(s.vector_error, 1e-6) << what << ": d(A P)/dθ, worst entry " << s.worst;
    }
    std::cout << "[ FD      ] " << term << " term: " << checked << " parameters it depends on at this state\n";
    EXPECT_GE(checked, kind == YarnTermKind::stretch ? 2 : kind == YarnTermKind::bending ? 1 : 2) << term;

    // F-derivatives along s and c, for a pull along the weft and one turned off the axes.
    for (const double angle : {weft_angle(), bias_angle() + 0.3}) {
      CoarseDeformation turned = chi;
      turned.angle = angle;
      sys.set_deformation(turned);
      sys.rebuild_contacts(g);
      const AffineDerivatives ad = sys.affine_derivatives(g);
      const Eigen::Vector4d ws = stretch_weights(turned), wc = compression_weights(turned);
      const Eigen::Vector4d area_stress = vec(sys.coarse_stress(g)) * sys.area();
      for (const bool along_s : {true, false}) {
        const Eigen::Vector4d w = along_s ? ws : wc;
        const auto eval = [&](double q) {
          YarnSystem copy = sys;
          CoarseDeformation x = turned;
          (along_s ? x.stretch : x.compression) = q;
          copy.set_deformation(x);
          copy.rebuild_contacts(g);
          Eigen::VectorXd grad;
          const double e = copy.energy_gradient(g, grad);
          const Eigen::Vector4d ap = vec(copy.coarse_stress(g)) * copy.area();
          Eigen::VectorXd out(grad.size() + 2);
          out << grad, ws.dot(ap), wc.dot(ap);
          return std::pair<double, Eigen::VectorXd>{e, out};
        };
        Eigen::VectorXd analytic(ad.gradient.rows() + 2);
        analytic << ad.gradient * w, ws.dot(ad.hessian * w), wc.dot(ad.hessian * w);
        const double q = along_s ? turned.stretch : turned.compression;
        const auto r = sweep_parameter(eval, q, w.dot(area_stress), analytic, 1e-300, 1e-300);
        const std::string what = term + " term, d/d" + (along_s ? "s" : "c") + " at angle " + std::to_string(angle);
        EXPECT_LT(r.value_error, 1e-6) << what;
        EXPECT_LT(r.vector_error, 1e-6) << what << " of (grad E, A P), worst entry " << r.worst;
      }
    }
  }
}

// Solves to a force tolerance far below the default so that differences of equilibria resolve
// the derivatives (warm-started from the centre's state each time).
EquilibriumOptions tight() {
  EquilibriumOptions o;
  o.force_tolerance = 1e-13 * 400.0;
  o.stress_tolerance = 0.0;
  o.max_iterations = 500;
  return o;
}

TEST_F(StockinetteSystem, EquilibriumTangentAndStressSensitivitiesMatchResolvedDifferences) {
  const YarnParams p = toe_params(tile);
  YarnSystem sys(make_yarn_tile(tile), p);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
  const CoarseDeformation chi{0.12, 0.04, 0.0, weft_angle()};
  const Sample centre = simulate_sample(sys, chi, g, tight());
  ASSERT_TRUE(centre.ok) << centre.message;
  const std::vector<YarnParam> fitted{YarnParam::ks1, YarnParam::eps_s, YarnParam::kb, YarnParam::r1, YarnParam::kc1};
  const EquilibriumSensitivity sens = equilibrium_sensitivity(sys, g, fitted);
  ASSERT_TRUE(sens.ok) << sens.message;
  const auto stress_at = [&](const YarnParams& q, const CoarseDeformation& x) {
    YarnSystem copy = sys;
    copy.set_params(q);
    Eigen::VectorXd state = g;
    const Sample s = simulate_sample(copy, x, state, tight());
    EXPECT_TRUE(s.ok) << s.message;
    return std::pair<double, Eigen::VectorXd>{s.energy_density, Eigen::VectorXd(vec(s.coarse_stress))};
  };
  for (std::size_t k = 0; k < fitted.size(); ++k) {
    const auto eval = [&](double theta) {
      YarnParams q = p;
      set(q, fitted[k], theta);
      return stress_at(q, chi);
    };
    const Eigen::VectorXd analytic = sens.stress_params.col(static_cast<Eigen::Index>(k));
    const auto r = sweep_parameter(eval, get(p, fitted[k]), 0.0, analytic, 1.0, 1e-300, {1e-3, 3e-4, 1e-4, 3e-5});
    std::cout << "[ FD      ] dP/d" << to_string(fitted[k]) << ": best relative error " << r.vector_error << " at step "
              << r.vector_step << "\n";
    EXPECT_LT(r.vector_error, 1e-4) << to_string(fitted[k]) << ": worst entry " << r.worst << " analytic "
                                    << analytic[r.worst] << ", FD " << r.worst_fd;
  }
  for (const bool along_s : {true, false}) {
    const Eigen::Vector4d w = along_s ? stretch_weights(chi) : compression_weights(chi);
    const auto eval = [&](double q) {
      CoarseDeformation x = chi;
      (along_s ? x.stretch : x.compression) = q;
      return stress_at(p, x);
    };
    const Eigen::VectorXd analytic = sens.tangent * w;
    const auto r = sweep_parameter(eval, along_s ? chi.stretch : chi.compression, 0.0, analytic, 1.0, 1e-300,
                                   {1e-2, 3e-3, 1e-3, 3e-4});
    std::cout << "[ FD      ] tangent along " << (along_s ? "s" : "c") << ": best relative error " << r.vector_error
              << "\n";
    EXPECT_LT(r.vector_error, 1e-4) << (along_s ? "s" : "c") << ": worst entry " << r.worst;
  }
}

TEST_F(StockinetteSystem, FreeCompressionRootCorrectionAndItsDerivativeMatchExactRoots) {
  const YarnParams p = toe_params(tile);
  YarnSystem sys(make_yarn_tile(tile), p);
  const CoarseDeformation chi{0.15, 0.0, 0.0, weft_angle()};
  Eigen::VectorXd g_exact = Eigen::VectorXd::Zero(sys.dof_count());
  CompressionOptions exact_search;
  exact_search.tolerance = 1e-11;
  exact_search.initial_guess = 0.03;
  exact_search.initial_step = 0.002;
  const Sample exact = solve_free_compression(sys, chi, g_exact, exact_search, tight());
  ASSERT_TRUE(exact.ok) << exact.message;
  const std::vector<YarnParam> fitted{YarnParam::ks1, YarnParam::eps_s, YarnParam::kb, YarnParam::r1, YarnParam::kc1};

  // The band the fit accepts, from a guess off the root: the correction lands on the root.
  {
    Eigen::VectorXd g = g_exact;
    CompressionOptions band;
    band.stress_tolerance = 3e-2 * exact.stress_s;
    band.initial_guess = exact.chi.compression + 0.004;
    const Sample accepted = solve_free_compression(sys, chi, g, band, tight());
    ASSERT_TRUE(accepted.ok) << accepted.message;
    const EquilibriumSensitivity sens = equilibrium_sensitivity(sys, g, fitted);
    ASSERT_TRUE(sens.ok) << sens.message;
    BandOptions root;  // τ = 0: the root itself
    const SensitiveReadout r = free_compression_readout(accepted, sens, root);
    ASSERT_FALSE(r.held);
    const double before = std::abs(accepted.chi.compression - exact.chi.compression);
    const double after = std::abs(r.compression - exact.chi.compression);
    std::cout << "[ root    ] c accepted " << accepted.chi.compression << ", corrected " << r.compression << ", exact "
              << exact.chi.compression << "; sigma accepted " << accepted.stress_s << ", corrected " << r.stress_s
              << ", exact " << exact.stress_s << "\n";
    EXPECT_GT(before, 1e-4) << "the band should leave the accepted c off the root";
    EXPECT_LT(after, 0.05 * before);
    EXPECT_LT(std::abs(r.stress_s - exact.stress_s), 0.05 * std::abs(accepted.stress_s - exact.stress_s));
    // With the band the search used: a reference inside it is the read-out (derivative 0), one
    // beyond it gives the band's edge (derivative that of the root).
    BandOptions with_band;
    with_band.tolerance = band.stress_tolerance;
    with_band.reference = r.root + 0.5 * band.stress_tolerance / r.stress_cc;
    const SensitiveReadout inside = free_compression_readout(accepted, sens, with_band);
    EXPECT_TRUE(inside.in_band);
    EXPECT_DOUBLE_EQ(inside.compression, with_band.reference);
    EXPECT_TRUE(inside.d_compression.isZero());
    with_band.reference = r.root + 3.0 * band.stress_tolerance / r.stress_cc;
    const SensitiveReadout edge = free_compression_readout(accepted, sens, with_band);
    EXPECT_FALSE(edge.in_band);
    EXPECT_NEAR(edge.compression, r.root + edge.half_width, 1e-15);
    EXPECT_LT((edge.d_compression - r.d_compression).norm(), 1e-12 * r.d_compression.norm());
  }

  // dc*/dθ and dσ_s/dθ along the root against differences of exact roots.
  g_exact = g_exact.eval();
  Eigen::VectorXd g = g_exact;
  sys.set_deformation(exact.chi);
  const EquilibriumSensitivity sens = equilibrium_sensitivity(sys, g, fitted);
  ASSERT_TRUE(sens.ok) << sens.message;
  const SensitiveReadout at_root = free_compression_readout(exact, sens, BandOptions{});
  for (std::size_t k = 0; k < fitted.size(); ++k) {
    const double theta = get(p, fitted[k]);
    const auto eval = [&](double value) {
      YarnSystem copy = sys;
      YarnParams q = p;
      set(q, fitted[k], value);
      copy.set_params(q);
      Eigen::VectorXd state = g_exact;
      CompressionOptions co = exact_search;
      co.initial_guess = exact.chi.compression;
      co.initial_step = 1e-5;
      const Sample s = solve_free_compression(copy, chi, state, co, tight());
      EXPECT_TRUE(s.ok) << s.message;
      Eigen::VectorXd v(1);
      v << s.stress_s;
      return std::pair<double, Eigen::VectorXd>{s.chi.compression, v};
    };
    const auto column = static_cast<Eigen::Index>(k);
    Eigen::VectorXd d_stress(1);
    d_stress << at_root.d_stress[column];
    // Scales: c* moves by about 1e-4 and σ by about 1 % over a relative change of θ.
    const auto fd = sweep_parameter(eval, theta, at_root.d_compression[column], d_stress, 1e-4 / theta,
                                    1e-2 * exact.stress_s / theta, {1e-3, 3e-4, 1e-4});
    std::cout << "[ FD      ] dc*/d" << to_string(fitted[k]) << " " << fd.value_error << ", dsigma/d"
              << to_string(fitted[k]) << " " << fd.vector_error << "\n";
    EXPECT_LT(fd.value_error, 1e-3) << "dc*/d" << to_string(fitted[k]) << ": analytic " << at_root.d_compression[column]
                                    << ", FD " << fd.value_fd;
    EXPECT_LT(fd.vector_error, 1e-3) << "dsigma/d" << to_string(fitted[k]);
  }
}

}  // namespace
}  // namespace yarnfit::yarn
