#pragma once
// What the pipeline's tests share: a plan of a record already read, run with nothing written,
// and the fields a list of problems names.
#include <string>
#include <vector>

#include "fabrics_db/records/fabric_reader.hpp"
#include "pipeline/plan.hpp"

namespace yarnfit::pipeline::plan_helpers {

// A plan of the stages on a record in memory (run_plan without an output folder writes nothing).
inline FitPlan in_memory(const db::Fabric& fabric, const PipelineOptions& options) {
  FitPlan plan;
  plan.fabric = fabric.folder;
  plan.options = options;
  plan.record = fabric;
  return plan;
}

inline PipelineResult run_in_memory(const db::Fabric& fabric, const PipelineOptions& options) {
  return run_plan(in_memory(fabric, options));
}

inline std::vector<std::string> fields(const db::Problems& problems) {
  std::vector<std::string> out;
  for (const auto& p : problems.items()) out.push_back(p.field);
  return out;
}

}  // namespace yarnfit::pipeline::plan_helpers
