#pragma once
// The stages of a fit as objects of one kind (SPEC §1, §5): each checks, before any stage runs,
// everything that would refuse it (reading the files it needs), and each runs on what the
// stages before it left in the plan's state. run_plan (plan.hpp) runs a
// StagePlan, so there is one order of stages and one place where each stage's work is called.
//
//   PlanState state = new_plan_state(fabric, options);
//   const StagePlan stages(options.stages);
//   stages.check(state, problems);
//   if (problems.empty()) result = stages.run(std::move(state));

#include <memory>
#include <optional>
#include <vector>

#include "numerics/util/clock.hpp"
#include "pipeline/pipeline.hpp"

namespace yarnfit::pipeline {

// What the stages of one plan hand on while it runs.
struct PlanState {
  PipelineOptions options;
  db::Fabric fabric;
  numerics::Clock::time_point start;  // when the plan began (the stages' seconds count from it)
  std::optional<std::vector<db::DirectionTargets>> file_targets;  // Stage::yarn: the targets file's
  // What the stages made; its yarn problem is made by the yarn stage's check, or by the tile
  // stage once the tile exists.
  PipelineResult result;
};

[[nodiscard]] PlanState new_plan_state(const db::Fabric& fabric, const PipelineOptions& options);

// The options' problems as the shell and the yarn stage check them: "shell.<field>" and
// "yarn.<field>" (a start file skips the swarm, so its settings are not checked then).
[[nodiscard]] db::Problems shell_option_problems(const PipelineOptions& options);
[[nodiscard]] db::Problems yarn_option_problems(const PipelineOptions& options);
// The exports' ("export"): they need the shell stage, whose law they sample.
[[nodiscard]] db::Problems export_option_problems(const PipelineOptions& options);

// `result` refused for `problems`: nothing (more) was run.
void refuse(PipelineResult& result, db::Problems problems);

// One stage. check: every problem that would refuse it, without any work; run: the stage on
// `state` (false when the plan ends after it: a failed fit, or a tile that cannot be used).
class PlanStage {
 public:
  virtual ~PlanStage() = default;
  virtual void check(PlanState& state, db::Problems& problems) const = 0;
  virtual bool run(PlanState& state) const = 0;
};

// The stages `stages` names, in their order: tile (a knit's tile generated, only when the yarn
// fit runs), shell, targets (the shell's in memory, or the file's with Stage::yarn), yarn.
class StagePlan {
 public:
  explicit StagePlan(Stage stages);
  // Every stage's check, problems appended in stage order.
  void check(PlanState& state, db::Problems& problems) const;
  // The stages in order on a checked state, until one ends the plan; never throws for bad
  // input or a failed fit (the result's status says).
  [[nodiscard]] PipelineResult run(PlanState state) const;

 private:
  std::vector<std::unique_ptr<PlanStage>> m_stages;
};

}  // namespace yarnfit::pipeline
