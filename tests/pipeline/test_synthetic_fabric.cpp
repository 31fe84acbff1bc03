// A record from a known yarn model (issue 48, `synth fabric`; pipeline/synthetic_fabric.hpp) and
// the check of a yarn model against a record's measurements (pipeline/measured_check.hpp): the
// record is valid, carries the truth, and its tests are reproduced by the law it was made with;
// the yarn model's own samples are homogenised to a law whose misfit is reported.
#include <gtest/gtest.h>

#include <cmath>

#include "fabrics_db/records/fabric_reader.hpp"
#include "pipeline/measured_check.hpp"
#include "pipeline/synthetic_fabric.hpp"
#include "shell_fit/fit/record_errors.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::pipeline {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;

const fs::path k_tile = fs::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo/tile.pyp";

yarn::YarnParams toe_truth(const db::PeriodicTile& tile) {
  const yarn::ParameterScales scales = yarn::scales_of(tile, 120.0);
  yarn::YarnParams p = yarn::default_params(scales);
  p.ks1 = 0.05 * p.ks2;
  p.eps_s = 0.005;
  p.kb = 0.2 * scales.kb_base();
  p.r1 = 0.9 * scales.r_est;
  p.kc1 = 2.0 * scales.kc_base();
  return p;
}

TEST(SyntheticFabric, AYarnModelsRecordIsValidCarriesItsTruthAndIsItsLaws) {
  ScratchDir dir("synth_fabric");
  db::Problems problems;
  const auto tile = db::read_pyp(k_tile, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  const yarn::YarnParams truth = toe_truth(*tile);
  SyntheticFabricOptions o;
  o.id = "syn";
  o.test_points = 7;
  o.bending_directions = {db::Direction::weft};
  o.curvature_points = 3;
  const SyntheticFabricResult r = write_synthetic_fabric(*tile, truth, o, dir / "syn");
  ASSERT_TRUE(r.law.ok) << r.law.message;
  // The law's misfit to the yarn model's own samples is reported (and finite).
  std::cout << "[ law     ] misfit: stress " << r.law.stress_misfit_pct << " %, compression " << r.law.compression_misfit_pct
            << " %, bending " << r.law.bending_misfit_pct << " %\n";
  EXPECT_TRUE(std::isfinite(r.law.stress_misfit_pct) && std::isfinite(r.law.compression_misfit_pct));
  EXPECT_LT(r.law.bending_misfit_pct, 5.0);
  const db::FabricLoad load = db::load_fabric(dir / "syn");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  const db::Fabric& f = *load.fabric;
  EXPECT_EQ(f.stretch_tests.size(), 3u);
  EXPECT_EQ(f.bending_tests.size(), 1u);
  EXPECT_DOUBLE_EQ(*f.stiffest_yarn_stiffness(), 120.0);
  ASSERT_TRUE(f.pattern && f.pattern->has_tile());
  EXPECT_NEAR(f.ground_truth.at("ks1").get<double>(), truth.ks1, 1e-9 * truth.ks1);
  EXPECT_NEAR(f.ground_truth.at("R1").get<double>(), truth.r1, 1e-9 * truth.r1);
  EXPECT_NEAR(f.ground_truth.at("kxx").get<double>(), r.law.params.inplane.kxx, 1e-9 * std::abs(r.law.params.inplane.kxx));
  // The record's tests are its law's (to the difference between the writer's refined meshes
  // and the check's default ones).
  const shell::RecordErrors own = shell::simulate_record_errors(f, r.law.params);
  ASSERT_TRUE(own.ok) << own.message;
  EXPECT_LT(own.errors.stretch_force_pct, 3.0);
  EXPECT_LT(own.errors.bending_pct, 3.0);
  // Refused: an existing record without overwrite.
  EXPECT_THROW((void)write_synthetic_fabric(*tile, truth, o, dir / "syn"), std::runtime_error);
}

// The yarn model's samples as uniform targets: σ_s from the objective's S (σ_s = S (1 + s)),
// and the bending check's Δσ_κ.
TEST(MeasuredCheck, TheYarnModelsSamplesAreItsFirstPiolaKirchhoffStressAndBending) {
  yarn::YarnFitResult fit;
  fit.ok = true;
  yarn::DirectionError d;
  d.scale.direction = db::Direction::warp;
  d.stretch = {0.0, 0.1, 0.2};
  d.stress_sim = {0.0, 10.0, 30.0};
  d.compression_sim = {0.0, 0.02, 0.05};
  fit.final.directions.push_back(d);
  yarn::BendingDirectionError b;
  b.direction = db::Direction::warp;
  b.curvature = {0.0, 50.0};
  b.stress_sim = {0.0, 1e-3};
  fit.bending.directions.push_back(b);
  const auto samples = yarn_model_samples(fit);
  ASSERT_EQ(samples.size(), 1u);
  ASSERT_EQ(samples[0].stretch.size(), 3u);
  EXPECT_DOUBLE_EQ(samples[0].stretch[2].stress, 30.0 * 1.2);
  EXPECT_DOUBLE_EQ(samples[0].stretch[1].compression, 0.02);
  ASSERT_EQ(samples[0].bending.size(), 2u);
  EXPECT_DOUBLE_EQ(samples[0].bending[1].stress, 1e-3);
  // A failed fit is not checked.
  yarn::YarnFitResult failed;
  const results::MeasuredCheckRecord none = check_against_measurements(db::Fabric{}, failed, shell::InplaneModel::thesis, std::nullopt);
  EXPECT_FALSE(none.ok);
  EXPECT_NE(none.message.find("failed"), std::string::npos);
}

}  // namespace
}  // namespace yarnfit::pipeline
