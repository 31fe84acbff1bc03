// The batch on MPI ranks (SPEC §5a): rank 0 plans, owns the ledger and DIR's lock, and hands
// one fabric at a time to each worker rank; a worker runs the job in-process (the same
// run_fabric_job as the local batch's children), writes into DIR on the shared filesystem and
// reports its stage and its outcome. Messages are the JSON lines of fabric_job.hpp.
//
//   worker → 0   k_tag_hello    {"host", "pid"}             once, then it waits for work
//   0 → worker   k_tag_job      a JobSpec
//   worker → 0   k_tag_stage    {"fabric_id", "stage"}      while the job runs
//   worker → 0   k_tag_outcome  {"fabric_id", "outcome"}    when it ends; the worker is free
//   0 → worker   k_tag_stop     ""                          no more work
//
// A rank that dies makes mpirun end the whole job; the ledger then shows the running
// fabrics with dead processes, and the rerun takes them over from their checkpoints.
#include "batch/batch.hpp"

#include <cstdlib>

#ifdef YARNFIT_HAVE_MPI

#include <mpi.h>
#include <unistd.h>

#include <chrono>
#include <deque>
#include <map>
#include <set>
#include <thread>

#include <nlohmann/json.hpp>

#include "batch/batch_run.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::batch {

namespace {

using nlohmann::json;

constexpr int k_tag_hello = 1;
constexpr int k_tag_job = 2;
constexpr int k_tag_stage = 3;
constexpr int k_tag_outcome = 4;
constexpr int k_tag_stop = 5;

void send(const std::string& text, int to, int tag) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

// Receives the message `status` announced (from MPI_Probe or MPI_Iprobe).
std::string receive(const MPI_Status& status) {
  int count = 0;
  MPI_Get_count(&status, MPI_CHAR, &count);
  std::string text(static_cast<std::size_t>(count), '\0');
  MPI_Recv(text.data(), count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return text;
}

void stop_workers(int size) {
  for (int r = 1; r < size; ++r) send("", r, k_tag_stop);
}

void worker(const BatchOptions& options) {
  send(json{{"host", host_name()}, {"pid", static_cast<long>(::getpid())}}.dump(), 0, k_tag_hello);
  const std::thread::id main_thread = std::this_thread::get_id();
  for (;;) {
    MPI_Status status;
    MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
    const std::string message = receive(status);
    if (status.MPI_TAG == k_tag_stop) return;
    const JobSpec spec = job_spec_from_message(message);
    StageThrottle throttle;
    // Stages from the main thread only (MPI is initialised with MPI_THREAD_FUNNELED).
    const StageFn stage = [&](const std::string& s) {
      if (std::this_thread::get_id() == main_thread && throttle.pass(s))
        send(json{{"fabric_id", spec.fabric_id}, {"stage", s}}.dump(), 0, k_tag_stage);
    };
    const JobOutcome outcome = run_fabric_job(spec, options, stage);
    send(json{{"fabric_id", spec.fabric_id}, {"outcome", to_message(outcome)}}.dump(), 0, k_tag_outcome);
  }
}

struct WorkerState {
  std::string host;
  long pid = 0;
  std::string fabric_id;  // empty: idle
};

BatchSummary coordinator(const BatchOptions& options, int size) {
  std::optional<BatchRun> run_holder;
  try {
    run_holder.emplace(options);
  } catch (...) {
    stop_workers(size);
    throw;
  }
  BatchRun& run = *run_holder;
  std::map<int, WorkerState> workers;  // the ranks that said hello
  const BatchFeed& feed = options.feed;
  auto last_look = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  bool stopped = false;
  // Cancelled while a rank fits them: a rank's fit cannot be stopped from here, so the job stays
  // running (not to be started twice) and ends cancelled when the rank reports.
  std::set<std::string> cancel_when_done;
  run.tick(true);
  for (;;) {
    if (feed && std::chrono::steady_clock::now() - last_look > std::chrono::milliseconds(250)) {
      last_look = std::chrono::steady_clock::now();
      if ((stopped = feed.stop && feed.stop())) break;
      for (const BatchFabric& f : feed.take()) run.add(f);
      if (feed.cancelled)
        for (const std::string& key : feed.cancelled()) {
          if (run.is_running(key)) cancel_when_done.insert(key);
          else run.cancel(key, k_cancelled_by_owner);
        }
    }
    for (auto& [rank, w] : workers) {
      if (!w.fabric_id.empty() || !run.has_queued()) continue;
      const JobSpec spec = run.next();
      send(to_message(spec), rank, k_tag_job);
      w.fabric_id = spec.fabric_id;
      run.started(spec, w.host, w.pid);
    }
    if (!feed && !run.has_queued() && run.running_count() == 0) break;
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (!flag) {
      run.tick();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    const json j = json::parse(receive(status), nullptr, false);
    if (j.is_discarded()) continue;
    WorkerState& w = workers[status.MPI_SOURCE];
    if (status.MPI_TAG == k_tag_hello) {
      w.host = j.value("host", "");
      w.pid = j.value("pid", 0L);
    } else if (status.MPI_TAG == k_tag_stage) {
      run.stage(j.value("fabric_id", ""), j.value("stage", ""));
    } else if (status.MPI_TAG == k_tag_outcome) {
      const std::string id = j.value("fabric_id", "");
      if (cancel_when_done.erase(id)) run.finished(id, {false, k_cancelled_by_owner});
      else run.finished(id, job_outcome_from_message(j.value("outcome", "{}")));
      w.fabric_id.clear();
    }
    run.tick();
  }
  const std::vector<std::string> busy = run.running_ids();
  for (const std::string& id : busy) run.interrupted(id);  // stopped: queued for the next start
  // A rank inside a fit would read the stop only when the fit ends (hours): end them all now;
  // their jobs are queued and resume from their checkpoints at the next start.
  if (!busy.empty()) MPI_Abort(MPI_COMM_WORLD, 1);
  stop_workers(size);
  run.tick(true);
  return run.summary(stopped);
}

}  // namespace

bool mpi_available() { return true; }

MpiScope::MpiScope() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
  if (provided < MPI_THREAD_SERIALIZED)
    throw Error(ErrorCategory::system, "this MPI cannot be called from a thread other than main");
  MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &m_size);
}

MpiScope::~MpiScope() { MPI_Finalize(); }

void MpiScope::abort(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // MPI_Abort does not return; its declaration does not say so
}

// MPI_Init_thread … MPI_Finalize around the run, unless the caller initialised MPI itself.
class MpiSession {
 public:
  MpiSession() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (initialised) return;
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    m_owner = true;
  }
  ~MpiSession() {
    if (m_owner) MPI_Finalize();
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

 private:
  bool m_owner = false;
};

BatchSummary run_batch_mpi(const BatchOptions& options) {
  const MpiSession session;
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size < 2) throw Error(ErrorCategory::input, "--mpi needs at least 2 ranks (rank 0 coordinates, the others fit): mpirun -np K");
  if (rank != 0) {
    worker(options);
    BatchSummary none;
    none.coordinator = false;
    return none;
  }
  return coordinator(options, size);
}

}  // namespace yarnfit::batch

#else

namespace yarnfit::batch {

bool mpi_available() { return false; }

BatchSummary run_batch_mpi(const BatchOptions&) {
  throw Error(ErrorCategory::system, "--mpi: this yarnfit was built without MPI (install libopenmpi-dev and rebuild)");
}

MpiScope::MpiScope() { throw Error(ErrorCategory::system, "--mpi: this yarnfit was built without MPI (install libopenmpi-dev and rebuild)"); }
MpiScope::~MpiScope() = default;
void MpiScope::abort(int) { std::abort(); }

}  // namespace yarnfit::batch

#endif
