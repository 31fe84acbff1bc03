#include <cmath>

#include "batch/batch.hpp"

namespace yarnfit::batch {

namespace {

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

nlohmann::json text_or_null(const std::string& s) { return s.empty() ? nlohmann::json() : nlohmann::json(s); }

}  // namespace

nlohmann::json batch_status_json(const Ledger& ledger) {
  nlohmann::json counts = {{"queued", 0}, {"running", 0}, {"done", 0}, {"failed", 0}};
  nlohmann::json jobs = nlohmann::json::array();
  for (const auto& j : ledger.jobs()) {
    counts[j.status] = counts.value(j.status, 0) + 1;
    jobs.push_back({{"fabric_id", j.fabric_id},
                    {"family", j.family},
                    {"folder", j.folder},
                    {"status", j.status},
                    {"stage", text_or_null(j.stage)},
                    {"attempts", j.attempts},
                    {"host", text_or_null(j.host)},
                    {"pid", j.pid},
                    {"heartbeat", number_or_null(j.heartbeat)},
                    {"started", number_or_null(j.started)},
                    {"ended", number_or_null(j.ended)},
                    {"hash", j.hash},
                    {"error", text_or_null(j.error)}});
  }
  nlohmann::json results = nlohmann::json::array();
  for (const auto& r : ledger.results()) {
    nlohmann::json row = {{"fabric_id", r.fabric_id}, {"stage", r.stage}, {"family", r.family}};
    for (std::size_t i = 0; i < result_columns().size() && i < r.values.size(); ++i)
      row[result_columns()[i]] = number_or_null(r.values[i]);
    row["params"] = nlohmann::json::parse(r.params.empty() ? "{}" : r.params, nullptr, false);
    results.push_back(row);
  }
  return {{"ledger", ledger.file().string()}, {"counts", counts}, {"jobs", jobs}, {"results", results}};
}

}  // namespace yarnfit::batch
