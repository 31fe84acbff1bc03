#pragma once
// What a plan does once its stages ran (plan.hpp): the writer (the stages' files), the exports
// (`--export`, into out/exports/) and the one-fabric report (out/report/, which links the
// exports), as objects of one kind: each checks with the plan, before any work, the files it
// would replace, and runs in that order on the plan's result.

#include <memory>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric_reader.hpp"
#include "pipeline/plan.hpp"

namespace yarnfit::pipeline {

class OutputStage {
 public:
  virtual ~OutputStage() = default;
  // Every problem that would refuse it (its files in the way unless the plan overwrites).
  virtual void check(const FitPlan& plan, const db::FabricLoad& load, db::Problems& problems) const = 0;
  // Writes its files into plan.out from `result`, adding them and their text to result.outputs;
  // throws for a file that cannot be written.
  virtual void run(const FitPlan& plan, const std::string& fabric_id, PipelineResult& result,
                   const PlanObserver& observer) const = 0;
};

// The writer, then the exports and the report when the plan asks for them.
[[nodiscard]] std::vector<std::unique_ptr<OutputStage>> output_stages(const FitPlan& plan);

}  // namespace yarnfit::pipeline
