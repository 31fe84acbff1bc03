#pragma once
// One fabric's job, wherever it runs (a child process of the local batch, an MPI worker): the
// library pipeline on the record, its files written atomically into DIR/fabrics/<id>/, the
// swarm checkpointed there after every iteration so that a killed job resumes inside its
// swarm; and the rows of the results table read back from those files.

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "batch/batch_options.hpp"
#include "batch/ledger.hpp"

namespace yarnfit::batch {

struct JobSpec {
  std::string fabric_id;
  std::string family;
  std::filesystem::path folder;  // the record
  bool resume = false;           // continue from the fabric's swarm checkpoint if there is one
  // A fabric's own options (BatchFabric); the batch's when empty. Not part of the message: an
  // MPI worker runs with the batch's options.
  std::optional<pipeline::PipelineOptions> fit;
  bool report = false;
};

struct JobOutcome {
  bool ok = false;
  std::string error;  // why not ok: the record's problems, the fit's failure, an exception
};

// Called with a short description of what the job does now ("shell in-plane (weft) start
// 1/3", "swarm 3/10", "local 12/150"), from the thread that runs the stage.
using StageFn = std::function<void(const std::string& stage)>;

// Which stage reports are worth sending on (a pipe, an MPI message): a new stage at once,
// steps of the same stage at most every 0.5 s. Not thread-safe: callers serialise.
class StageThrottle {
 public:
  [[nodiscard]] bool pass(const std::string& stage);

 private:
  std::string m_last;
  std::chrono::steady_clock::time_point m_last_time{};
};

// Runs the job. Never throws: every failure is the outcome's.
JobOutcome run_fabric_job(const JobSpec& spec, const BatchOptions& options, const StageFn& stage);

// The results rows of the files in `fabric_output_folder` (shell_fit.json, yarn_fit.json;
// a file that is missing or unreadable gives no row).
std::vector<ResultRow> read_result_rows(const std::filesystem::path& fabric_output_folder,
                                        const std::string& fabric_id, const std::string& family);

// JobSpec and JobOutcome as one line of JSON and back (the messages of the local batch's
// pipes and of MPI); parse failures throw an Error.
std::string to_message(const JobSpec& spec);
JobSpec job_spec_from_message(const std::string& message);
std::string to_message(const JobOutcome& outcome);
JobOutcome job_outcome_from_message(const std::string& message);

}  // namespace yarnfit::batch
