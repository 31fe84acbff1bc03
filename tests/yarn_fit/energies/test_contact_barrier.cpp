// Two-barrier Simpson contact (thesis 6.7; yarn_fit/energies/contact_barrier.cpp): the scalar
// barrier, the contact law, the segment-pair element's derivatives by finite differences, its
// cutoff, symmetry, +inf at coincidence, monotonicity and PSD projection.

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

#include "tests/yarn_fit/energies/element_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

TwoBarrierContact contact_model(double kc1_relative = 1.0) {
  return {.kc1 = kc1_relative * ks2 / yarn_radius,
          .r1 = yarn_radius,
          .kc2 = 1e3 * ks2 / yarn_radius,
          .r2 = 0.25 * yarn_radius};
}

auto contact_fn(const TwoBarrierContact& model, double la = edge_length, double lb = edge_length,
                bool project = false) {
  return [model, la, lb, project](const Vec<12>& x, Vec<12>* g, Mat<12>* h) {
    return contact_element(x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9), la,
                           lb, model, g, h, project);
  };
}

Vec<12> pack(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  Vec<12> x;
  x << a0, a1, b0, b1;
  return x;
}

// Segment pairs whose closest quadrature point pair is at distance d.
Vec<12> parallel_pair(double d, double shift) {
  const double l = edge_length;
  return pack(Vec3(0, 0, 0), Vec3(l, 0, 0), Vec3(shift, d, 0), Vec3(l + shift, d, 0));
}
Vec<12> crossing_pair(double d) {
  const double l = edge_length;
  return pack(Vec3(-l / 2, 0, 0), Vec3(l / 2, 0, 0), Vec3(0, -l / 2, d), Vec3(0, l / 2, d));
}
Vec<12> skew_pair(double d) {  // 60° apart, midpoints at distance d, b tilted out of plane
  const double l = edge_length;
  const Vec3 mid_b(0.0, 0.0, d);
  const Vec3 dir_b = Vec3(std::cos(pi / 3), std::sin(pi / 3), 0.0);
  return pack(Vec3(-l / 2, 0, 0), Vec3(l / 2, 0, 0), mid_b - 0.45 * l * dir_b + Vec3(0, 0, 0.1 * l),
              mid_b + 0.55 * l * dir_b + Vec3(0, 0, -0.1 * l));
}

TEST(Barrier, ScalarDerivativesAndLimits) {
  ErrorTally tally;
  for (const double x : {0.01, 0.1, 0.3, 0.5, 0.8, 0.95, 0.999}) {
    const auto f = [](const Vec<1>& y, Vec<1>* g, Mat<1>* h) {
      if (g != nullptr) (*g)(0) = Barrier::first(y(0));
      if (h != nullptr) (*h)(0, 0) = Barrier::second(y(0));
      return Barrier::value(y(0));
    };
    DerivativeCheckOptions options = element_options();
    options.length_scale = std::min(x, 1.0 - x);
    tally.add(expect_element_derivatives<1>(f, Vec<1>(x), "barrier x=" + std::to_string(x),
                                            options));
  }
  report("barrier f(x)^2", tally);
  // f(x) = −(x − 1)² log x.
  EXPECT_NEAR(Barrier::value(0.5), std::pow(0.25 * std::log(2.0), 2), 1e-15);
  EXPECT_EQ(Barrier::value(1.0), 0.0);
  EXPECT_EQ(Barrier::value(2.0), 0.0);
  EXPECT_EQ(Barrier::first(1.0), 0.0);
  EXPECT_EQ(Barrier::second(1.0), 0.0);
  EXPECT_EQ(Barrier::first(1.5), 0.0);
  EXPECT_EQ(Barrier::second(1.5), 0.0);
  for (const double x : {0.0, -0.5}) {
    EXPECT_TRUE(std::isinf(Barrier::value(x)) && Barrier::value(x) > 0.0);
    EXPECT_FALSE(std::isnan(Barrier::first(x)));
    EXPECT_FALSE(std::isnan(Barrier::second(x)));
  }
  EXPECT_GT(Barrier::value(1e-300), 1e5);
}

TEST(Barrier, C2OnsetAtOne) {
  // f ≈ h³ for x = 1 − h, so f² ≈ h⁶, (f²)' ≈ −6h⁵, (f²)'' ≈ 30h⁴: all three vanish at x = 1.
  for (const double h : {1e-2, 1e-3, 1e-4}) {
    const double x = 1.0 - h;
    EXPECT_NEAR(Barrier::value(x) / std::pow(h, 6), 1.0, 2.0 * h);
    EXPECT_NEAR(Barrier::first(x) / (-6.0 * std::pow(h, 5)), 1.0, 3.0 * h);
    EXPECT_NEAR(Barrier::second(x) / (30.0 * std::pow(h, 4)), 1.0, 4.0 * h);
  }
  EXPECT_LT(Barrier::second(1.0 - 1e-6), 1e-22);
  EXPECT_EQ(Barrier::second(1.0 + 1e-6), 0.0);
}

TEST(TwoBarrierContact, LawDerivativesMonotoneAndCutoff) {
  const TwoBarrierContact m = contact_model();
  EXPECT_DOUBLE_EQ(m.cutoff_distance(), 2.0 * yarn_radius);
  ErrorTally tally;
  for (const double d : {0.05e-3, 0.3e-3, 0.49e-3, 0.51e-3, 1e-3, 1.9e-3, 1.999e-3}) {
    const auto f = [&m](const Vec<1>& y, Vec<1>* g, Mat<1>* h) {
      if (g != nullptr) (*g)(0) = m.de(y(0));
      if (h != nullptr) (*h)(0, 0) = m.d2e(y(0));
      return m.e(y(0));
    };
    DerivativeCheckOptions options = element_options();
    options.length_scale = std::min({d, std::abs(d - 0.5e-3), 2e-3 - d});
    tally.add(expect_element_derivatives<1>(f, Vec<1>(d), "law D=" + std::to_string(d), options));
  }
  report("two-barrier law e(D)", tally);

  // Monotone decreasing on (0, cutoff), zero beyond; the stiff barrier adds below 2 R2.
  double previous = inf;
  for (int k = 1; k <= 2200; ++k) {
    const double d = 1e-6 * k;
    const double e = m.e(d);
    EXPECT_LE(m.de(d), 0.0) << d;
    if (d < m.cutoff_distance()) {
      EXPECT_LT(e, previous) << d;
    } else {
      EXPECT_EQ(e, 0.0) << d;
      EXPECT_EQ(m.de(d), 0.0) << d;
      EXPECT_EQ(m.d2e(d), 0.0) << d;
    }
    previous = e;
  }
  EXPECT_NEAR(m.e(1e-3), m.kc1 * Barrier::value(0.5), 1e-12 * m.e(1e-3));
  EXPECT_NEAR(m.e(0.25e-3), m.kc1 * Barrier::value(0.125) + m.kc2 * Barrier::value(0.5),
              1e-12 * m.e(0.25e-3));
  EXPECT_TRUE(std::isinf(m.e(0.0)) && m.e(0.0) > 0.0);
}

TEST(ContactElement, DerivativesNearOuterInnerAndBetween) {
  const TwoBarrierContact m = contact_model();
  const double outer = 2.0 * m.r1;
  const double inner = 2.0 * m.r2;
  struct Band {
    const char* name;
    std::vector<double> distances;
  };
  const Band bands[] = {
      {"outer", {0.9 * outer, 0.99 * outer, 0.999 * outer}},
      {"inner", {0.5 * inner, 0.9 * inner, 0.99 * inner, 0.999 * inner, 1.01 * inner}},
      {"between", {0.4 * outer, 0.6 * outer, 0.8 * outer}},
  };
  for (const Band& band : bands) {
    ErrorTally tally;
    for (const double d : band.distances) {
      const auto f = contact_fn(m, 1.1 * edge_length, 0.9 * edge_length);
      // Shifted along the yarn, but by less than the room left below the cutoff.
      const double shift = std::min(0.3 * edge_length, 0.5 * std::sqrt(outer * outer - d * d));
      const std::pair<std::string, Vec<12>> configurations[] = {
          {"parallel", parallel_pair(d, 0.0)},
          {"parallel shifted", parallel_pair(d, shift)},
          {"crossing", crossing_pair(d)},
          {"skew", skew_pair(d)},
      };
      for (const auto& [name, x] : configurations) {
        const std::string what = name + " D=" + std::to_string(d);
        EXPECT_GT(f(x, nullptr, nullptr), 0.0) << what << ": not in contact, check is vacuous";
        tally.add(expect_element_derivatives<12>(f, x, what, element_options()));
      }
    }
    report(std::string("contact, ") + band.name + " radius", tally);
  }
  // Random skew pairs in the contact range, with a softer and a stiffer soft barrier.
  std::mt19937 rng(31);
  ErrorTally tally;
  for (int trial = 0; trial < 30; ++trial) {
    const TwoBarrierContact mr = contact_model(std::pow(10.0, uniform(rng, -2.0, 2.0)));
    const Vec3 ca = 1e-3 * random_unit(rng);
    const Vec3 cb = ca + uniform(rng, 0.3, 2.0) * 1e-3 * random_unit(rng);
    const Vec3 ua = random_unit(rng), ub = random_unit(rng);
    const double la = uniform(rng, 0.5, 1.5) * edge_length;
    const double lb = uniform(rng, 0.5, 1.5) * edge_length;
    const Vec<12> x = pack(ca - 0.5 * la * ua, ca + 0.5 * la * ua, cb - 0.5 * lb * ub,
                           cb + 0.5 * lb * ub);
    Vec<12> g;
    if (contact_fn(mr, la, lb)(x, &g, nullptr) == 0.0) continue;  // nothing within reach
    tally.add(expect_element_derivatives<12>(contact_fn(mr, la, lb), x,
                                             "random pair " + std::to_string(trial), element_options()));
  }
  EXPECT_GE(tally.count, 10);
  report("contact, random pairs", tally);
}

TEST(ContactElement, ExactlyZeroBeyondCutoff) {
  const TwoBarrierContact m = contact_model();
  const auto check_zero = [&m](const Vec<12>& x, const char* what) {
    Vec<12> g = Vec<12>::Constant(7.0);
    Mat<12> h = Mat<12>::Constant(7.0);
    EXPECT_EQ(contact_fn(m)(x, &g, &h), 0.0) << what;
    EXPECT_TRUE((g.array() == 0.0).all()) << what;
    EXPECT_TRUE((h.array() == 0.0).all()) << what;
  };
  // Bounding boxes apart: the broad phase answers.
  check_zero(parallel_pair(1.0001 * m.cutoff_distance(), 0.0), "parallel beyond cutoff");
  check_zero(crossing_pair(2.5e-3), "crossing beyond cutoff");
  // Bounding boxes overlap but every quadrature pair is beyond the cutoff (2.83 mm apart).
  check_zero(pack(Vec3(0, 0, 0), Vec3(4e-3, 4e-3, 0), Vec3(3e-3, -1e-3, 0), Vec3(7e-3, 3e-3, 0)),
             "diagonal pair with overlapping boxes");
  // Just inside: not zero.
  EXPECT_GT(contact_fn(m)(parallel_pair(0.999 * m.cutoff_distance(), 0.0), nullptr, nullptr),
            0.0);
}

TEST(ContactElement, SymmetricUnderSwappingSegments) {
  const TwoBarrierContact m = contact_model();
  for (const Vec<12>& x : {skew_pair(0.7e-3), crossing_pair(0.4e-3), parallel_pair(1.5e-3, 2e-4)}) {
    Vec<12> swapped;
    swapped << x.tail<6>(), x.head<6>();
    Vec<12> g, gs;
    Mat<12> h, hs;
    const double w = contact_fn(m, 1.2e-3, 0.8e-3)(x, &g, &h);
    const double ws = contact_fn(m, 0.8e-3, 1.2e-3)(swapped, &gs, &hs);
    ASSERT_GT(w, 0.0);
    EXPECT_NEAR(ws, w, 1e-13 * w);
    Vec<12> gs_back;
    gs_back << gs.tail<6>(), gs.head<6>();
    EXPECT_LT((gs_back - g).lpNorm<Eigen::Infinity>(), 1e-12 * g.lpNorm<Eigen::Infinity>());
    Mat<12> hs_back;
    hs_back << hs.bottomRightCorner<6, 6>(), hs.bottomLeftCorner<6, 6>(),
        hs.topRightCorner<6, 6>(), hs.topLeftCorner<6, 6>();
    EXPECT_LT((hs_back - h).lpNorm<Eigen::Infinity>(), 1e-12 * h.lpNorm<Eigen::Infinity>());
    // Contact forces are internal: they sum to zero.
    EXPECT_LT(block_sum<12>(g).norm(), 1e-12 * g.norm());
  }
}

TEST(ContactElement, CoincidentQuadraturePointsGiveInfinity) {
  const TwoBarrierContact m = contact_model();
  const double l = edge_length;
  // The midpoint of a is b0; a crossing at distance 0; identical segments.
  for (const Vec<12>& x :
       {pack(Vec3(-l / 2, 0, 0), Vec3(l / 2, 0, 0), Vec3(0, 0, 0), Vec3(0, l, 0)),
        crossing_pair(0.0), parallel_pair(0.0, 0.0)}) {
    Vec<12> g;
    Mat<12> h;
    const double w = contact_fn(m)(x, &g, &h);
    EXPECT_TRUE(std::isinf(w) && w > 0.0) << w;
    EXPECT_TRUE(std::isinf(contact_fn(m)(x, nullptr, nullptr)));
  }
  // Close but apart: finite and large.
  const double w = contact_fn(m)(crossing_pair(1e-9), nullptr, nullptr);
  EXPECT_TRUE(std::isfinite(w));
  EXPECT_GT(w, 1e3 * contact_fn(m)(crossing_pair(0.25e-3), nullptr, nullptr));
}

TEST(ContactElement, EnergyDecreasesWithSeparation) {
  const TwoBarrierContact m = contact_model();
  double previous = inf;
  for (int k = 1; k <= 100; ++k) {
    const double d = 0.02e-3 * k;  // up to the cutoff
    const double w = contact_fn(m)(crossing_pair(d), nullptr, nullptr);
    if (d < m.cutoff_distance() * (1.0 - 1e-12)) {
      EXPECT_LT(w, previous) << d;
    }
    previous = w;
  }
  EXPECT_EQ(previous, 0.0);
}

TEST(ContactElement, AnalyticProjectionIsPsd) {
  const TwoBarrierContact m = contact_model();
  int indefinite = 0;
  for (const Vec<12>& x : {parallel_pair(0.3e-3, 0.0), parallel_pair(1.2e-3, 3e-4),
                           crossing_pair(0.2e-3), crossing_pair(1.0e-3), crossing_pair(1.98e-3),
                           skew_pair(0.45e-3), skew_pair(1.5e-3)}) {
    Mat<12> h, p;
    (void)contact_fn(m, edge_length, edge_length, false)(x, nullptr, &h);
    (void)contact_fn(m, edge_length, edge_length, true)(x, nullptr, &p);
    const double scale = h.lpNorm<Eigen::Infinity>();
    ASSERT_GT(scale, 0.0);
    if (min_eigenvalue<12>(h) < -1e-8 * scale) ++indefinite;
    EXPECT_GE(min_eigenvalue<12>(p), -1e-12 * scale);
    EXPECT_EQ((h - h.transpose()).lpNorm<Eigen::Infinity>(), 0.0);  // exactly symmetric
    EXPECT_EQ((p - p.transpose()).lpNorm<Eigen::Infinity>(), 0.0);
    // Clamping removes only curvature: h − p is negative semi-definite.
    EXPECT_GE(min_eigenvalue<12>(Mat<12>(p - h)), -1e-12 * scale);
  }
  EXPECT_GT(indefinite, 0) << "no indefinite contact Hessian seen: projection untested";
}

}  // namespace
}  // namespace yarnfit::yarn
