#include "service/jobs/fit_jobs.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <future>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "batch/batch.hpp"
#include "batch/batch_report.hpp"
#include "exports/export_fit.hpp"
#include "numerics/util/error.hpp"
#include "numerics/util/whole_file.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "reports/report.hpp"

namespace yarnfit::service {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Writes `text` to `file` whole or not at all (numerics/util/whole_file.hpp), its folder made.
void write_whole(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  numerics::write_file_whole(file, text);
}

// "local 1 40/150" → (40, 150); (0, 0) when the text ends without a step.
std::pair<int, int> step_of(const std::string& text) {
  const auto slash = text.rfind('/');
  const auto space = text.rfind(' ');
  if (slash == std::string::npos || space == std::string::npos || space > slash) return {0, 0};
  try {
    return {std::stoi(text.substr(space + 1, slash - space - 1)), std::stoi(text.substr(slash + 1))};
  } catch (const std::exception&) {
    return {0, 0};
  }
}

// A rough share of the fit done, from the step the fit reports: for the whole pipeline the
// shell stage is taken as the first 15 %, the global search up to 60 %, the local step up to
// 97 %, the report the rest; a shell-only fit as its own steps. An estimate for a progress
// bar, not a promise: the stages' real shares vary with the record and the budget.
double progress_of(const std::string& stages, const std::string& step) {
  const auto [i, n] = step_of(step);
  const double within = n > 0 ? std::clamp(static_cast<double>(i) / n, 0.0, 1.0) : 0.0;
  const auto band = [&](double from, double to) { return from + (to - from) * within; };
  const std::string name = step.substr(0, step.find(' '));
  if (stages == "shell") return name == "report" ? 0.97 : band(0.0, 0.95);
  if (name == "shell" || name == "starting") return band(0.0, 0.15);
  if (name == "local") return band(0.6, 0.97);
  if (name == "report") return 0.97;
  return band(0.15, 0.6);  // the global search: swarm, or the staged search's contact/all/swarm
}

std::string job_key(const std::string& owner, const std::string& fabric_id) { return owner + "/" + fabric_id; }

fs::path request_file_of(const fs::path& runs, const std::string& key) { return runs / "requests" / (key + ".json"); }

ServiceFitRequest read_request(const fs::path& file, db::Problems& problems) {
  std::ifstream in(file);
  return fit_request_from_json(json::parse(in, nullptr, false), problems);
}

// The fabric the engine runs for `request` (its problems when it cannot).
batch::BatchFabric fabric_of_request(const fs::path& runs, const std::string& key, const fs::path& record,
                                     const ServiceFitRequest& request, db::Problems& problems) {
  batch::BatchFabric f{key, record, pipeline::pipeline_options(request.request, problems), request.report};
  problems.append(f.fit.problems());
  f.fit.tile_cache = batch::generated_tiles_folder(runs);
  const db::FabricLoad load = db::load_fabric(record);
  problems.append(load.problems);
  if (load.ok()) {
    // The plan the batch will run, checked on the record just read; its output folder is the
    // batch's to choose and replace, so none is checked here.
    pipeline::FitPlan plan;
    plan.fabric = record;
    plan.options = f.fit;
    plan.report = f.report;
    plan.record = *load.fabric;
    problems.append(pipeline::check_plan(plan));
  }
  f.fit.tile_cache.clear();  // the batch sets it for each job
  return f;
}

// The fabric of job `key` as its kept request says (what an MPI worker runs).
std::optional<batch::BatchFabric> requested_fabric(const fs::path& data, const std::string& key) {
  const fs::path runs = data / "runs";
  if (!fs::exists(request_file_of(runs, key))) return std::nullopt;
  db::Problems problems;
  const ServiceFitRequest request = read_request(request_file_of(runs, key), problems);
  return fabric_of_request(runs, key, data / "fabrics" / key, request, problems);
}

}  // namespace

void run_fit_worker(const fs::path& data_dir, const FitJobsOptions& options) {
  batch::BatchOptions o;
  o.out = data_dir / "runs";
  o.threads_per_job = options.threads_per_job;
  o.fabric_of = [data_dir](const std::string& key) { return requested_fabric(data_dir, key); };
  batch::run_batch_mpi(o);
}

std::vector<std::pair<std::string, fs::path>> downloadable_files(const std::string& id) {
  std::vector<std::pair<std::string, fs::path>> files;
  for (const char* f : {"shell_fit.json", "uniform_targets.csv", "shell_curves.csv", "yarn_fit.json", "yarn_curves.csv",
                        "summary.txt"})
    files.emplace_back(f, f);
  for (const auto format : {exports::ExportFormat::u3m, exports::ExportFormat::arcsim}) {
    const fs::path p = exports::export_path(format, id);
    files.emplace_back(p.filename().string(), p);
  }
  for (const char* f : {"table.json", "stress.csv", "uniaxial.csv", "bending.csv"})
    files.emplace_back(f, exports::export_path(exports::ExportFormat::table, id) / f);
  return files;
}

struct FitJobs::Impl {
  fs::path data, runs;
  FitJobsOptions options;

  mutable std::mutex mutex;  // guards everything below
  std::vector<batch::BatchFabric> pending;   // asked for, not yet taken by the engine
  std::set<std::string> pending_keys;        // asked for, not yet in the ledger as asked
  std::set<std::string> taken_keys;          // taken by the engine's last look
  std::vector<std::string> cancels;
  std::map<std::string, batch::RunningFabric> live;  // the running fits' steps
  std::map<std::string, std::string> stages_of;      // key → "shell" or "all"
  // The furthest progress shown of each running job, by attempt: the estimate from the step
  // can fall back (a stage's steps count towards a budget it rarely uses up), a bar should not.
  mutable std::map<std::string, std::pair<int, double>> furthest;
  std::string engine_error;  // why the engine stopped on its own (empty while it runs)
  std::mutex start_mutex;    // serialises FitJobs::start (taken before `mutex`, never inside it)
  std::atomic<bool> stopping{false};
  std::thread engine;

  fs::path request_file(const std::string& key) const { return request_file_of(runs, key); }
  batch::BatchFabric fabric_for(const std::string& key, const fs::path& record, const ServiceFitRequest& request,
                                db::Problems& problems) const {
    return fabric_of_request(runs, key, record, request, problems);
  }

  // Feeds the jobs a previous service left queued or running (their requests kept).
  void feed_unfinished() {
    if (!fs::is_directory(runs / "requests")) return;
    const batch::Ledger ledger(batch::ledger_file(runs));
    for (const auto& owner : fs::directory_iterator(runs / "requests"))
      for (const auto& file : fs::directory_iterator(owner.path())) {
        if (file.path().extension() != ".json") continue;
        const std::string key = owner.path().filename().string() + "/" + file.path().stem().string();
        const auto row = ledger.job(key);
        if (row && row->status != "queued" && row->status != "running") continue;
        db::Problems problems;
        const ServiceFitRequest request = read_request(file.path(), problems);
        stages_of[key] = request.request.stages;
        // A record with problems now is recorded as failed by the batch.
        pending.push_back(fabric_for(key, data / "fabrics" / key, request, problems));
        pending_keys.insert(key);
      }
  }

  batch::BatchOptions engine_options() {
    batch::BatchOptions o;
    o.out = runs;
    o.jobs = options.jobs;
    o.threads_per_job = options.threads_per_job;
    o.fabric_of = [data = data](const std::string& key) { return requested_fabric(data, key); };
    o.feed.take = [this] {
      const std::lock_guard lock(mutex);
      // What was taken last time is in the ledger now (the batch planned it since).
      for (const auto& k : taken_keys) pending_keys.erase(k);
      taken_keys.clear();
      for (const auto& f : pending) taken_keys.insert(f.key);
      return std::exchange(pending, {});
    };
    o.feed.cancelled = [this] {
      const std::lock_guard lock(mutex);
      return std::exchange(cancels, {});
    };
    o.feed.stop = [this] { return stopping.load(); };
    return o;
  }

  void start_engine() {
    std::promise<void> started;
    std::future<void> ready = started.get_future();
    batch::BatchOptions o = engine_options();
    auto once = std::make_shared<std::once_flag>();
    o.progress = [this, once, &started](const batch::BatchProgress& p) {
      {
        const std::lock_guard lock(mutex);
        live.clear();
        for (const auto& r : p.running) live[r.fabric_id] = r;
      }
      std::call_once(*once, [&started] { started.set_value(); });
    };
    engine = std::thread([this, o, once, &started] {
      try {
        if (options.mpi) batch::run_batch_mpi(o);
        else batch::run_batch(o);
      } catch (const std::exception& e) {
        {
          const std::lock_guard lock(mutex);
          engine_error = e.what();
        }
        std::call_once(*once, [&started] { started.set_exception(std::current_exception()); });
      }
      if (!stopping) {
        const std::lock_guard lock(mutex);
        if (engine_error.empty()) engine_error = "the fit engine stopped";
      }
    });
    try {
      ready.get();
    } catch (...) {
      engine.join();
      throw;
    }
  }

  // The state a client sees: queued until the engine has planned it.
  json describe(const std::string& key, const std::optional<batch::JobRow>& row) const {
    const auto slash = key.find('/');
    json j{{"id", key.substr(slash + 1)}, {"owner", key.substr(0, slash)}};
    std::string state = row ? row->status : "queued";
    std::string step;
    double seconds = 0;
    {
      const std::lock_guard lock(mutex);
      if (pending_keys.count(key)) state = "queued";
      if (const auto l = live.find(key); l != live.end() && state == "running") {
        step = l->second.stage;
        seconds = l->second.seconds;
      }
    }
    if (state == "failed" && row && row->error == batch::k_cancelled_by_owner) state = "cancelled";
    const std::string stages = [&] {
      const std::lock_guard lock(mutex);
      const auto s = stages_of.find(key);
      return s == stages_of.end() ? std::string("all") : s->second;
    }();
    double progress = state == "done" ? 1.0 : state == "running" ? progress_of(stages, step) : 0.0;
    if (state == "running" && row) {
      const std::lock_guard lock(mutex);
      auto& [attempt, most] = furthest[key];
      if (attempt != row->attempts) attempt = row->attempts, most = 0.0;
      progress = most = std::max(most, progress);
    }
    j["state"] = state;
    j["stage"] = state == "running" && row ? row->stage : "";
    j["step"] = step;
    j["progress"] = progress;
    if (state != "queued" && row && row->started > 0)
      seconds = state == "running" ? std::max(seconds, batch::unix_now() - row->started) : row->ended - row->started;
    j["seconds"] = seconds;
    j["seconds_left"] = state == "running" && progress > 0.02 ? json(seconds * (1 - progress) / progress) : json();
    j["attempts"] = row ? row->attempts : 0;
    j["error"] = state == "failed" && row ? row->error : "";
    json files = json::array();
    const fs::path folder = batch::fabric_output_folder(runs, key);
    if (state != "queued")
      for (const auto& [name, path] : downloadable_files(fs::path(key).filename().string()))
        if (fs::exists(folder / path)) files.push_back(name);
    j["files"] = files;
    j["report"] = state != "queued" && fs::exists(folder / "report" / "index.html");
    return j;
  }

  [[nodiscard]] batch::Ledger ledger() const { return batch::Ledger::open_read_only(batch::ledger_file(runs)); }

  std::optional<json> find(const std::string& key) const {
    const auto row = ledger().job(key);
    bool asked = false;
    {
      const std::lock_guard lock(mutex);
      asked = pending_keys.count(key) > 0;
    }
    if (!row && !asked) return std::nullopt;
    return describe(key, row);
  }

  // Jobs queued or running: of `owner`, and of everyone.
  std::pair<int, int> active(const std::string& owner) const {
    std::set<std::string> keys;
    for (const auto& row : ledger().jobs())
      if (row.status == "queued" || row.status == "running") keys.insert(row.fabric_id);
    {
      const std::lock_guard lock(mutex);
      keys.insert(pending_keys.begin(), pending_keys.end());
    }
    const int mine = static_cast<int>(std::count_if(keys.begin(), keys.end(), [&](const std::string& k) {
      return k.compare(0, owner.size() + 1, owner + "/") == 0;
    }));
    return {mine, static_cast<int>(keys.size())};
  }
};

FitJobs::FitJobs(fs::path data_dir, FitJobsOptions options) : m_impl(std::make_unique<Impl>()) {
  m_impl->data = std::move(data_dir);
  m_impl->runs = m_impl->data / "runs";
  m_impl->options = options;
  fs::create_directories(m_impl->runs);
  {
    const std::lock_guard lock(m_impl->mutex);
    m_impl->feed_unfinished();
  }
  m_impl->start_engine();
}

FitJobs::~FitJobs() {
  m_impl->stopping = true;
  if (m_impl->engine.joinable()) m_impl->engine.join();
}

JobAnswer FitJobs::start(const std::string& owner, const std::string& fabric_id, const fs::path& record,
                         const json& body) {
  const std::string key = job_key(owner, fabric_id);
  if (const std::string why = engine_problem(); !why.empty())
    return {503, {{"error", "fits cannot run now: " + why}, {"problems", json::array()}}};
  db::Problems problems;
  const ServiceFitRequest request = fit_request_from_json(body, problems);
  batch::BatchFabric fabric = m_impl->fabric_for(key, record, request, problems);
  if (!problems.empty()) {
    json list = json::array();
    for (const auto& p : problems.items()) list.push_back(p.to_string());
    return {422, {{"error", "the fit cannot run as asked"}, {"problems", list}}};
  }
  // From the check to the request kept and queued, one start at a time: two requests for one
  // fabric, or past the limits together, would both pass the checks.
  const std::lock_guard one_at_a_time(m_impl->start_mutex);
  if (const auto now = m_impl->find(key); now && ((*now)["state"] == "queued" || (*now)["state"] == "running"))
    return {409, {{"error", "a fit of '" + fabric_id + "' is " + (*now)["state"].get<std::string>()}, {"problems", json::array()}}};
  const auto [mine, all] = m_impl->active(owner);
  if (mine >= m_impl->options.active_per_user)
    return {429, {{"error", "you have " + std::to_string(mine) + " fits queued or running (at most " +
                                std::to_string(m_impl->options.active_per_user) + "); wait for one to end"},
                  {"problems", json::array()}}};
  if (all >= m_impl->options.queue_length)
    return {429, {{"error", "the queue is full (" + std::to_string(all) + " fits); try again later"}, {"problems", json::array()}}};
  write_whole(m_impl->request_file(key), to_json(request).dump(2) + "\n");
  {
    const std::lock_guard lock(m_impl->mutex);
    m_impl->stages_of[key] = request.request.stages;
    m_impl->pending.push_back(std::move(fabric));
    m_impl->pending_keys.insert(key);
  }
  return {202, *m_impl->find(key)};
}

JobAnswer FitJobs::cancel(const std::string& owner, const std::string& fabric_id) {
  const std::string key = job_key(owner, fabric_id);
  const auto now = m_impl->find(key);
  if (!now) return {404, {{"error", "no fit of '" + fabric_id + "'"}, {"problems", json::array()}}};
  if ((*now)["state"] != "queued" && (*now)["state"] != "running")
    return {409, {{"error", "the fit of '" + fabric_id + "' has ended (" + (*now)["state"].get<std::string>() + ")"},
                  {"problems", json::array()}}};
  {
    const std::lock_guard lock(m_impl->mutex);
    m_impl->cancels.push_back(key);
  }
  // The engine looks at its feed four times a second; the answer waits for it.
  for (int i = 0; i < 100; ++i) {
    const auto after = m_impl->find(key);
    if (after && (*after)["state"] == "cancelled") return {200, *after};
    if (after && (*after)["state"] != "queued" && (*after)["state"] != "running")
      return {409, {{"error", "the fit of '" + fabric_id + "' ended (" + (*after)["state"].get<std::string>() + ") first"},
                    {"problems", json::array()}}};
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (const std::string why = engine_problem(); !why.empty())
    return {503, {{"error", "fits cannot run now: " + why}, {"problems", json::array()}}};
  return {202, *m_impl->find(key)};  // under MPI a rank's fit ends cancelled when the rank reports
}

JobAnswer FitJobs::delete_fabric(const std::string& owner, const std::string& fabric_id, const fs::path& record) {
  const std::string key = job_key(owner, fabric_id);
  const std::lock_guard one_at_a_time(m_impl->start_mutex);  // no fit of it starts meanwhile
  const auto busy = [&](const std::string& state) {
    return JobAnswer{409, {{"error", "a fit of '" + fabric_id + "' is " + state + "; cancel it first"}, {"problems", json::array()}}};
  };
  if (const auto now = m_impl->find(key); now && ((*now)["state"] == "queued" || (*now)["state"] == "running"))
    return busy((*now)["state"].get<std::string>());
  {
    batch::Ledger ledger(batch::ledger_file(m_impl->runs));
    if (ledger.job(key) && !ledger.forget_job(key, "deleted by its owner", batch::unix_now())) return busy("running");
  }
  std::error_code ec;
  fs::remove(m_impl->request_file(key), ec);
  fs::remove_all(batch::fabric_output_folder(m_impl->runs, key), ec);
  {
    const std::lock_guard lock(m_impl->mutex);
    m_impl->stages_of.erase(key);
    m_impl->furthest.erase(key);
  }
  // Out of the user's folder in one rename, then removed: a reader sees the record whole or not at all.
  const fs::path gone = m_impl->data / "uploads" / (".deleted-" + std::to_string(::getpid()) + "-" +
                                                    std::to_string(std::hash<std::string>{}(key + std::to_string(batch::unix_now()))));
  if (std::rename(record.c_str(), gone.c_str()) != 0)
    return {500, {{"error", "the record of '" + fabric_id + "' could not be removed"}, {"problems", json::array()}}};
  fs::remove_all(gone, ec);
  return {200, {{"id", fabric_id}, {"owner", owner}, {"deleted", true}}};
}

std::string FitJobs::engine_problem() const {
  const std::lock_guard lock(m_impl->mutex);
  return m_impl->engine_error;
}

std::optional<json> FitJobs::job(const std::string& owner, const std::string& fabric_id) const {
  return m_impl->find(job_key(owner, fabric_id));
}

std::vector<json> FitJobs::jobs(const std::string& owner) const {
  std::map<std::string, std::optional<batch::JobRow>> keys;
  for (const auto& row : m_impl->ledger().jobs()) keys[row.fabric_id] = row;
  {
    const std::lock_guard lock(m_impl->mutex);
    for (const auto& k : m_impl->pending_keys) keys.try_emplace(k);
  }
  std::vector<json> out;
  for (const auto& [key, row] : keys)
    if (owner.empty() || key.compare(0, owner.size() + 1, owner + "/") == 0) out.push_back(m_impl->describe(key, row));
  return out;
}

std::vector<std::pair<std::string, int>> FitJobs::counts() const {
  std::map<std::string, int> n{{"queued", 0}, {"running", 0}, {"done", 0}, {"failed", 0}, {"cancelled", 0}};
  for (const auto& j : jobs("")) ++n[j["state"].get<std::string>()];
  return {n.begin(), n.end()};
}

fs::path FitJobs::output_folder(const std::string& owner, const std::string& fabric_id) const {
  return batch::fabric_output_folder(m_impl->runs, job_key(owner, fabric_id));
}

fs::path FitJobs::family_report(const std::string& owner) const {
  reports::RunOutputs run = batch::read_batch_outputs(m_impl->runs);
  std::vector<reports::FabricOutputs> mine;
  for (auto& f : run.fabrics)
    if (owner.empty() || f.id.compare(0, owner.size() + 1, owner + "/") == 0) {
      if (!owner.empty()) f.id = f.id.substr(owner.size() + 1);  // the user's own names
      mine.push_back(std::move(f));
    }
  run.fabrics = std::move(mine);
  run.label = owner.empty() ? "all users" : owner;
  run.source = run.label;  // not the server's folder: where it keeps runs is none of a user's business
  std::vector<reports::RunOutputs> runs;
  runs.push_back(std::move(run));
  const fs::path folder = owner.empty() ? m_impl->data / "reports" / "everyone" : m_impl->data / "reports" / "users" / owner;
  return reports::write_report(reports::make_report_data(std::move(runs)), folder);
}

}  // namespace yarnfit::service
