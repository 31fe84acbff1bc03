// yarnfit serve DATA_DIR: the fitting service (service/http/fitting_service.hpp) until SIGINT or
// SIGTERM; yarnfit serve user add|token|revoke|list …: its accounts, kept in DATA_DIR/accounts.db
// by the service library (service/accounts/accounts.hpp). A token is printed once, when it is
// issued; only its hash is stored.
#include <pthread.h>
#include <signal.h>

#include <charconv>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "batch/batch.hpp"
#include "cli/commands.hpp"
#include "numerics/util/error.hpp"
#include "service/accounts/accounts.hpp"
#include "service/http/fitting_service.hpp"

namespace yarnfit::cli {

namespace fs = std::filesystem;

namespace {

struct UserArgs {
  std::string name;
  std::string data_dir;
  bool admin = false;
};

// The accounts of DATA_DIR (created with the folder when absent).
service::Accounts open_accounts(const std::string& data_dir) {
  fs::create_directories(data_dir);
  return service::Accounts(fs::path(data_dir) / "accounts.db");
}

void print_token(const service::IssuedToken& issued, const std::string& data_dir) {
  std::cout << "user " << issued.account.name << (issued.account.admin ? " (admin)" : "") << " in " << data_dir
            << "\ntoken: " << issued.token
            << "\nKeep it now: it is shown this once (only its hash is stored). Requests carry it as "
               "'Authorization: Bearer <token>'.\n";
}

// Runs one accounts action; a bad name, an unknown user or an unusable database is refused.
template <class Action>
int with_accounts(const std::string& data_dir, Action action) {
  try {
    service::Accounts accounts = open_accounts(data_dir);
    action(accounts);
    return k_exit_ok;
  } catch (const Error& e) {
    std::cerr << "serve user: " << e.what() << "\n";
  } catch (const fs::filesystem_error& e) {
    std::cerr << "serve user: " << e.what() << "\n";
  }
  return k_exit_invalid_input;
}

struct ServeArgs {
  std::string data_dir;
  std::string listen = "127.0.0.1:8080";
  service::FitJobsOptions jobs;
  bool mpi = false;
};

// Serves DATA_DIR until SIGINT or SIGTERM (taken by a thread that waits for them, then stops
// the server: no work in a signal handler).
int run_serve(const ServeArgs& a) {
  const auto colon = a.listen.rfind(':');
  service::ServiceOptions o;
  o.jobs = a.jobs;
  const std::string digits = colon == std::string::npos ? std::string() : a.listen.substr(colon + 1);
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), o.port);
  if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size()) {
    std::cerr << "serve: --listen " << a.listen << ": expected HOST:PORT\n";
    return k_exit_invalid_input;
  }
  o.host = a.listen.substr(0, colon);
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // inherited by the server's threads (and MPI's)
  try {
    std::optional<batch::MpiScope> mpi;
    if (a.mpi) {
      mpi.emplace();
      if (mpi->size() < 2)
        throw Error(ErrorCategory::input, "--mpi needs at least 2 ranks (rank 0 serves, the others fit): mpirun -np K");
      if (mpi->rank() != 0) {
        service::run_fit_worker(a.data_dir, o.jobs);
        return k_exit_ok;
      }
      o.jobs.mpi = true;
    }
    std::optional<service::FittingService> started;
    try {
      started.emplace(a.data_dir, o);
    } catch (const std::exception& e) {
      if (!mpi) throw;
      // The other ranks wait for work that will never come: end them with this one.
      std::cerr << "serve: " << e.what() << "\n";
      mpi->abort(k_exit_internal);
    }
    service::FittingService& server = *started;
    const int port = server.bind();
    std::cout << "yarnfit serve: " << a.data_dir << " on http://" << o.host << ":" << port
              << "/ (GET /healthz; the API under /api/v1 with 'Authorization: Bearer <token>'); fits on "
              << (a.mpi ? std::to_string(mpi->size() - 1) + " MPI ranks" : std::to_string(o.jobs.jobs) + " processes")
              << "; Ctrl-C stops\n"
              << std::flush;
    std::thread stopper([&server, &signals] {
      int received = 0;
      sigwait(&signals, &received);
      server.stop();
    });
    server.run();
    pthread_kill(stopper.native_handle(), SIGTERM);  // the server stopped first: release the waiter
    stopper.join();
  } catch (const Error& e) {
    std::cerr << "serve: " << e.what() << "\n";
    return exit_code_of(e);
  } catch (const std::exception& e) {
    std::cerr << "serve: " << e.what() << "\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

}  // namespace

void add_serve_commands(CLI::App& app, int& exit_code) {
  auto* serve = app.add_subcommand(
      "serve", "The fitting service: `serve DATA_DIR [--listen HOST:PORT] [--jobs N]` serves the API (docs/service.md); "
               "`serve user …` manages its accounts");
  auto serve_args = std::make_shared<ServeArgs>();
  serve->add_option("DATA_DIR", serve_args->data_dir, "The service's data folder (accounts, fabrics)");
  serve->add_option("--listen", serve_args->listen, "Address to listen on")->capture_default_str();
  serve->add_option("--jobs", serve_args->jobs.jobs, "Fits run at once, each in its own process")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  serve->add_option("--threads-per-job", serve_args->jobs.threads_per_job, "OpenMP threads of each fit")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  serve->add_option("--active-per-user", serve_args->jobs.active_per_user,
                    "A user's fits queued or running at once (429 past it)")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  serve->add_flag("--mpi", serve_args->mpi,
                  std::string("Under mpirun: rank 0 serves and keeps the ledger, the other ranks fit (docs/service.md)") +
                      (batch::mpi_available() ? "" : " (this build has no MPI)"));
  serve->add_option("--queue-length", serve_args->jobs.queue_length, "Fits queued or running for everyone (429 past it)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  serve->require_subcommand(0, 1);
  serve->final_callback([serve, serve_args, &exit_code] {
    if (!serve->get_subcommands().empty()) return;
    if (serve_args->data_dir.empty()) {
      std::cerr << "serve: DATA_DIR is required (or a subcommand: serve user …)\n";
      exit_code = k_exit_invalid_input;
      return;
    }
    exit_code = run_serve(*serve_args);
  });
  auto* user = serve->add_subcommand("user", "Users of the service and their API tokens (DATA_DIR/accounts.db)");
  user->require_subcommand(1);
  auto args = std::make_shared<UserArgs>();
  const auto name_and_dir = [&args](CLI::App* cmd) {
    cmd->add_option("NAME", args->name, "User name: a-z, 0-9, '.', '_', '-'")->required();
    cmd->add_option("DATA_DIR", args->data_dir, "The service's data folder")->required();
  };
  auto* add = user->add_subcommand("add", "Add a user and print their token (once)");
  name_and_dir(add);
  add->add_flag("--admin", args->admin, "The user sees every user's fabrics and jobs");
  add->callback([args, &exit_code] {
    exit_code = with_accounts(args->data_dir, [&](service::Accounts& a) {
      print_token(a.add_user(args->name, args->admin), args->data_dir);
    });
  });
  auto* token = user->add_subcommand("token", "Give a user a new token (the old one stops working) and print it");
  name_and_dir(token);
  token->callback([args, &exit_code] {
    exit_code = with_accounts(args->data_dir, [&](service::Accounts& a) { print_token(a.new_token(args->name), args->data_dir); });
  });
  auto* revoke = user->add_subcommand("revoke", "Revoke a user's token: their requests are refused from now on");
  name_and_dir(revoke);
  revoke->callback([args, &exit_code] {
    exit_code = with_accounts(args->data_dir, [&](service::Accounts& a) {
      a.revoke(args->name);
      std::cout << "user " << args->name << ": token revoked\n";
    });
  });
  auto* list = user->add_subcommand("list", "List the users (never their tokens)");
  list->add_option("DATA_DIR", args->data_dir, "The service's data folder")->required();
  list->callback([args, &exit_code] {
    exit_code = with_accounts(args->data_dir, [&](service::Accounts& a) {
      for (const auto& u : a.list())
        std::cout << u.name << (u.admin ? "  admin" : "") << (u.revoked ? "  revoked" : "") << "\n";
    });
  });
}

}  // namespace yarnfit::cli
