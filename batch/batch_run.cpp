#include "batch/batch_run.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <numeric>
#include <set>
#include <thread>

#include "fabrics_db/records/fabric_hash.hpp"
#include "fabrics_db/records/database.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "pipeline/plan.hpp"

namespace yarnfit::batch {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_between(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

const BatchOptions& checked(const BatchOptions& options) {
  const db::Problems problems = options.problems();
  if (!problems.empty()) throw Error(ErrorCategory::input, problems.to_string());
  std::error_code ec;
  fs::create_directories(options.out, ec);
  if (ec) throw Error(ErrorCategory::io, options.out.string() + ": cannot create the output folder: " + ec.message());
  return options;
}

// The ledger's key of each fabric: its id, or its folder's name when the id is missing or
// shared by several records (those are invalid, and must not overwrite each other's rows).
std::vector<std::string> fabric_keys(const db::DatabaseLoad& database) {
  std::map<std::string, int> uses;
  for (const auto& f : database.fabrics) ++uses[f.id];
  std::vector<std::string> keys;
  for (const auto& f : database.fabrics)
    keys.push_back(f.id.empty() || uses[f.id] > 1 ? f.folder.filename().string() : f.id);
  return keys;
}

std::string problems_text(const db::Problems& problems) {
  std::string text = problems.to_string();
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

void wait_for_exit(long pid, double seconds) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (process_alive(pid) && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

}  // namespace

bool process_alive(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

DirectoryLock::DirectoryLock(const fs::path& out) {
  const fs::path file = out / "batch.lock";
  m_fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (m_fd < 0) throw Error(ErrorCategory::io, file.string() + ": cannot open: " + std::strerror(errno));
  if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0) {
    std::string holder, why;
    db::read_text_file(file, holder, why);
    ::close(m_fd);
    m_fd = -1;
    throw Error(ErrorCategory::conflict, out.string() + ": another batch is running in this folder (" +
                     std::string(db::trim(holder)) + "); wait for it or stop it first");
  }
  const std::string me = "pid " + std::to_string(::getpid()) + " on " + host_name() + "\n";
  if (::ftruncate(m_fd, 0) != 0 || ::pwrite(m_fd, me.data(), me.size(), 0) != static_cast<ssize_t>(me.size())) {
    // The lock holds regardless; the file only names the holder for the message above.
  }
}

DirectoryLock::~DirectoryLock() {
  if (m_fd >= 0) ::close(m_fd);
}

BatchRun::BatchRun(const BatchOptions& options)
    : m_options(checked(options)),
      m_lock(std::make_unique<DirectoryLock>(m_options.out)),
      m_ledger(ledger_file(m_options.out)),
      m_start(Clock::now()),
      m_last_heartbeat(m_start),
      m_last_progress(m_start) {
  plan();
}

void BatchRun::plan() {
  if (m_options.database.empty()) return;  // a feed brings the fabrics
  const db::DatabaseLoad database = db::load_database(m_options.database);
  const std::vector<std::string> keys = fabric_keys(database);
  const std::set<std::string> only(m_options.only.begin(), m_options.only.end());
  std::set<std::string> found;
  db::Problems argument_problems;
  std::vector<std::size_t> selected;
  for (std::size_t i = 0; i < database.fabrics.size(); ++i) {
    const auto& f = database.fabrics[i];
    if (!m_options.family.empty() && f.family != m_options.family) continue;
    if (!only.empty() && !only.count(keys[i])) continue;
    found.insert(keys[i]);
    selected.push_back(i);
  }
  for (const auto& id : only)
    if (!found.count(id)) argument_problems.add("", 0, "only", id + ": no such fabric in " + m_options.database.string());
  if (selected.empty() && argument_problems.empty())
    argument_problems.add("", 0, "database",
                          m_options.database.string() + ": no fabric" +
                              (m_options.family.empty() ? std::string() : " of family " + m_options.family) +
                              (database.problems.empty() ? std::string() : " (" + problems_text(database.problems) + ")"));
  if (!argument_problems.empty()) throw Error(ErrorCategory::input, argument_problems.to_string());
  for (const std::size_t i : selected) plan_fabric(keys[i], database.fabrics[i], m_options.fit, false, false);
}

void BatchRun::add(const BatchFabric& fabric) {
  if (m_running.count(fabric.key)) return;  // asked again while it runs: this run goes on
  m_queue.erase(std::remove_if(m_queue.begin(), m_queue.end(), [&](const JobSpec& q) { return q.fabric_id == fabric.key; }),
                m_queue.end());
  plan_fabric(fabric.key, db::load_fabric(fabric.folder), fabric.fit, fabric.report, true);
  tick(true);
}

void BatchRun::plan_fabric(const std::string& key, const db::FabricLoad& load, const pipeline::PipelineOptions& fit,
                           bool report, bool own_options) {
  const nlohmann::json options_json = fit_options_json(fit);
  // Checked as the jobs will run them: with the batch's folder for generated tiles.
  pipeline::PipelineOptions job_options = fit;
  job_options.tile_cache = generated_tiles_folder(m_options.out);
  const double now = unix_now();
  if (std::find(m_selected.begin(), m_selected.end(), key) == m_selected.end()) {
    m_selected.push_back(key);
    ++m_summary.selected;
  }
  db::Problems problems = load.problems;
  if (load.ok()) {
    // The plan the job will run (fabric_job.cpp), on the record just hashed, into the fabric's
    // folder, which the batch replaces.
    pipeline::FitPlan plan;
    plan.fabric = load.folder;
    plan.out = fabric_output_folder(m_options.out, key);
    plan.options = job_options;
    plan.report = report;
    plan.overwrite = true;
    plan.record = *load.fabric;
    problems.append(pipeline::check_plan(plan));
  }
  JobRow row;
  row.fabric_id = key;
  row.family = load.family;
  row.folder = load.folder.string();
  row.hash = db::fabric_hash(load, options_json);
  row.options = options_json.dump();
  const std::optional<JobRow> old = m_ledger.job(key);
  if (old) row.attempts = old->attempts;
  JobSpec spec{key, load.family, load.folder, true, std::nullopt, report};
  if (own_options) spec.fit = fit;

  if (!problems.empty()) {
    ++m_summary.invalid;
    row.status = "failed";
    row.error = problems_text(problems);
    row.ended = now;
    if (!(old && old->status == "failed" && old->hash == row.hash && old->error == row.error))
      m_ledger.put_job(row, "invalid", row.error, now);
    return;
  }
  if (old && old->hash == row.hash) {
    if (old->status == "done") {
      ++m_summary.skipped_done;
      return;
    }
    if (old->status == "failed" && !m_options.retry_failed && !own_options) {
      ++m_summary.skipped_failed;
      return;
    }
    if (old->status == "running") {
      const double age = now - old->heartbeat;
      // On this host the lock we hold says that the batch which ran the job is gone: its
      // process is dead, or a child about to die with it (PR_SET_PDEATHSIG), which is given
      // a moment so that it does not write beside the job's new run.
      const bool here_too = old->host == host_name();
      if (here_too) wait_for_exit(old->pid, 5.0);
      // A fed batch (the service) holds DIR's lock for the whole folder: a job it finds running
      // belongs to a run of it that is gone, wherever its rank ran.
      const bool stale = here_too || own_options || age > m_options.stale_after;
      if (!stale) {
        m_summary.running_elsewhere.push_back(key + " (pid " + std::to_string(old->pid) + " on " + old->host +
                                              ", heartbeat " + db::format_g(age, 3) + " s ago)");
        return;
      }
      ++m_summary.taken_over;
      row.status = "queued";
      m_ledger.put_job(row, "taken_over",
                       "from pid " + std::to_string(old->pid) + " on " + old->host + " (heartbeat " +
                           db::format_g(age, 3) + " s ago, stage " + old->stage + ")",
                       now);
    } else if (old->status == "failed") {
      row.status = "queued";
      m_ledger.put_job(row, "retry", old->error, now);
    }
    m_queue.push_back(spec);  // queued: resumed from its checkpoint if it has one
    return;
  }
  // New, or changed since its last run: a fresh start, without the old files.
  std::error_code ec;
  fs::remove_all(fabric_output_folder(m_options.out, key), ec);
  row.status = "queued";
  m_ledger.put_job(row, old ? "changed" : "queued", old ? "hash " + old->hash + " -> " + row.hash : row.hash, now);
  spec.resume = false;
  m_queue.push_back(spec);
}

void BatchRun::cancel(const std::string& key, const std::string& why) {
  const auto queued = std::find_if(m_queue.begin(), m_queue.end(), [&](const JobSpec& q) { return q.fabric_id == key; });
  if (queued != m_queue.end()) {
    m_queue.erase(queued);
    if (std::optional<JobRow> row = m_ledger.job(key)) {
      row->status = "failed";
      row->error = why;
      row->ended = unix_now();
      m_ledger.put_job(*row, "cancelled", why, row->ended);
    }
  } else if (m_running.count(key)) {
    finished(key, {false, why});
  }
  tick(true);
}

std::vector<std::string> BatchRun::running_ids() const {
  std::vector<std::string> ids;
  for (const auto& [id, r] : m_running) ids.push_back(id);
  return ids;
}

JobSpec BatchRun::next() {
  JobSpec spec = m_queue.front();
  m_queue.pop_front();
  return spec;
}

void BatchRun::started(const JobSpec& spec, const std::string& host, long pid) {
  m_ledger.start_job(spec.fabric_id, host, pid, unix_now());
  m_running[spec.fabric_id] = {spec, "starting", Clock::now()};
  ++m_summary.ran;
  tick(true);
}

void BatchRun::stage(const std::string& fabric_id, const std::string& stage) {
  const auto it = m_running.find(fabric_id);
  if (it == m_running.end() || it->second.stage == stage) return;
  // The ledger keeps the stage's name ("swarm", "local"), not every step of it.
  const std::string name = stage.substr(0, stage.find_first_of(" 0123456789"));
  const std::string old_name = it->second.stage.substr(0, it->second.stage.find_first_of(" 0123456789"));
  it->second.stage = stage;
  if (name != old_name) m_ledger.set_stage(fabric_id, name, unix_now());
  tick();
}

void BatchRun::finished(const std::string& fabric_id, const JobOutcome& outcome) {
  const auto it = m_running.find(fabric_id);
  if (it == m_running.end()) return;
  const JobSpec spec = it->second.spec;
  m_job_seconds.push_back(seconds_between(it->second.start, Clock::now()));
  m_running.erase(it);
  m_ledger.finish_job(fabric_id, outcome.ok, outcome.error,
                      read_result_rows(fabric_output_folder(m_options.out, fabric_id), fabric_id, spec.family), unix_now());
  tick(true);
}

void BatchRun::interrupted(const std::string& fabric_id) {
  m_running.erase(fabric_id);
  m_ledger.requeue(fabric_id, "the batch was stopped", unix_now());
}

void BatchRun::tick(bool force) {
  const auto now = Clock::now();
  if (seconds_between(m_last_heartbeat, now) >= m_options.heartbeat_interval) {
    m_ledger.heartbeat(running_ids(), unix_now());
    m_last_heartbeat = now;
  }
  if (!m_options.progress || (!force && seconds_between(m_last_progress, now) < 1.0)) return;
  m_last_progress = now;
  BatchProgress p;
  p.selected = m_summary.selected;
  const std::set<std::string> selected(m_selected.begin(), m_selected.end());
  for (const auto& job : m_ledger.jobs()) {
    if (!selected.count(job.fabric_id)) continue;
    if (job.status == "done") ++p.done;
    else if (job.status == "failed") ++p.failed;
  }
  p.queued = static_cast<int>(m_queue.size());
  for (const auto& [id, r] : m_running) p.running.push_back({id, r.stage, seconds_between(r.start, now)});
  p.seconds = seconds_between(m_start, now);
  if (!m_job_seconds.empty()) {
    // Jobs left × the mean job time so far, spread over the jobs that run at once.
    const double mean = std::accumulate(m_job_seconds.begin(), m_job_seconds.end(), 0.0) / m_job_seconds.size();
    const double slots = std::max<double>(1.0, static_cast<double>(std::max<std::size_t>(m_running.size(), 1)));
    double left = mean * static_cast<double>(m_queue.size());
    for (const auto& r : p.running) left += std::max(0.0, mean - r.seconds);
    p.seconds_left = left / slots;
  }
  m_options.progress(p);
}

BatchSummary BatchRun::summary(bool was_interrupted) {
  BatchSummary s = m_summary;
  s.interrupted = was_interrupted;
  s.seconds = seconds_between(m_start, Clock::now());
  const std::set<std::string> selected(m_selected.begin(), m_selected.end());
  s.done = 0;
  s.failed = 0;
  for (const auto& job : m_ledger.jobs()) {
    if (!selected.count(job.fabric_id)) continue;
    if (job.status == "done") ++s.done;
    if (job.status == "failed") {
      ++s.failed;
      s.failures.push_back({job.fabric_id, job.error});
    }
  }
  return s;
}

}  // namespace yarnfit::batch
