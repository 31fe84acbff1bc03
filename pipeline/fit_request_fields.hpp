#pragma once
// The fields of a fit request a user sets by name, each listed once for every front end that
// asks for it:
// - `fit`, `shell fit`, `yarn fit` and `batch` register their options from it, with its help
//   (cli/fit_args.cpp);
// - the service reads a request's JSON from it, writes it back, and checks the sizes a stranger
//   may ask for (service/jobs/fit_request_json.cpp);
// - the command line names a problem the library found by the option that set the field
//   (cli/option_names.cpp).
// So a field is added, renamed or bounded in one place, and the command line, the service and
// their error messages cannot disagree about it. The library checks the values themselves
// (pipeline_options, then PipelineOptions::problems).
//
//   for_each_request_field(request, [](const pipeline::RequestField& f, auto& member) {
//     if (f.served) std::cout << f.name << "\n";
//   });

#include <optional>
#include <string>
#include <vector>

#include "pipeline/fit_request.hpp"

namespace yarnfit::pipeline {

// The commands that share a field register it together, with the others of its group.
enum class RequestGroup {
  search,       // the yarn fit's settings: `fit`, `yarn fit`, `batch`
  shell,        // the shell stage's mesh, law and held-out tests: `fit`, `shell fit`, `batch`
  shell_solve,  // the shell fit's own mesh refinement, iterations and range: `shell fit`
  outputs,      // the export formats: `fit`, `batch`
  stages,       // which stages run: `batch` (the other commands each run their own)
};

struct RequestField {
  const char* name;    // a service request's key, and the field a problem of the request names
  const char* option;  // the command line's names, CLI11's way: "--local,--local-method"
  std::string help;
  RequestGroup group;
  bool served = true;     // a service request may set it
  int served_most = 0;    // a size of the search: a service request asks 1 to this (0: no bound)
  std::vector<const char*> settings_names{};  // the library's names of what it sets, in problems
};

// The kinds of member a field binds that the front ends treat apart: an optional size (absent
// unless given) and a list of names.
template <class T>
inline constexpr bool is_optional = false;
template <class T>
inline constexpr bool is_optional<std::optional<T>> = true;
template <class T>
inline constexpr bool is_list = false;
template <class T>
inline constexpr bool is_list<std::vector<T>> = true;

// The settings of a request that gives no numbers of its own (the default budget's), which the
// help of the optional sizes states.
[[nodiscard]] const yarn::YarnFitSettings& default_request_settings();

namespace detail {

// The yarn fit's search: its budget, its steps and their sizes, its seed.
template <class Request, class Visit>
void visit_search_fields(Request& r, Visit& visit) {
  using G = RequestGroup;
  const yarn::YarnFitSettings& d = default_request_settings();
  const auto default_is = [](int n) { return " (default " + std::to_string(n) + ")"; };
  visit(RequestField{"budget", "--budget",
                     "Named search settings: quick, default or thorough (the options below override them; "
                     "bench_calibration and the report's 'What accuracy costs' show what each costs and reaches)",
                     G::search},
        r.budget);
  visit(RequestField{"global_method", "--global",
                     "Global step: staged (R1 and kc1 first on few samples, then every parameter near that R1, the "
                     "best distinct candidates rescored on the local samples) or swarm (the thesis's: --particles x "
                     "--iterations on --samples)",
                     G::search},
        r.global_method);
  visit(RequestField{"particles", "--particles", "Swarm particles of --global swarm" + default_is(d.particles),
                     G::search, true, 256},
        r.particles);
  visit(RequestField{"iterations", "--iterations", "Swarm iterations of --global swarm" + default_is(d.iterations),
                     G::search, true, 40},
        r.iterations);
  visit(RequestField{"samples", "--samples",
                     "Stretch samples per direction in --global swarm" + default_is(d.swarm_samples), G::search,
                     true, 50, {"swarm_samples"}},
        r.samples);
  visit(RequestField{"local_samples", "--local-samples",
                     "Stretch samples per direction in the local step, the rescore and the final evaluation" +
                         default_is(d.local_samples),
                     G::search, true, 50},
        r.local_samples);
  visit(RequestField{"starts", "--starts",
                     "Local runs of --global staged, from its best distinct candidates" + default_is(d.staged.starts),
                     G::search, true, 16, {"staged.starts"}},
        r.starts);
  visit(RequestField{"local_evaluations", "--local-evaluations",
                     "Budget of objective evaluations of --local implicit-filtering or cobyla, and of the "
                     "Gauss-Newton step's fallback" + default_is(d.local_evaluations),
                     G::search, true, 1500},
        r.local_evaluations);
  visit(RequestField{"local_method", "--local,--local-method",
                     "Local step: gauss-newton (the rest state held within rounds, Gauss-Newton on exact Jacobians, "
                     "relaxed again between rounds), implicit-filtering (Gauss-Newton on stencil differences) or "
                     "cobyla (the thesis's choice)",
                     G::search},
        r.local_method);
  visit(RequestField{"seed", "--seed", "Swarm seed (same seed, same result whatever --threads)", G::search}, r.seed);
}

// What the yarn fit's objective and model leave out or add (ablations, Figs. 6.11-6.17).
template <class Request, class Visit>
void visit_model_fields(Request& r, Visit& visit) {
  using G = RequestGroup;
  visit(RequestField{"compression_nodes", "--compression-nodes",
                     "Where the zero-orthogonal-stress compression is solved: 0 at every stretch sample; N >= 2 at N "
                     "samples with linear interpolation between them (2: the thesis's both ends)",
                     G::search, false, 0, {"swarm_compression_nodes", "local_compression_nodes"}},
        r.compression_nodes);
  visit(RequestField{"compression_weight", "--compression-weight",
                     "Weight of the compression errors beside the stress errors in the yarn objective (1: the "
                     "thesis's eq. 6.11; 0: the stresses alone)",
                     G::search, false, 0, {"objective.compression_weight"}},
        r.compression_weight);
  visit(RequestField{"no_swarm", "--no-swarm", "The local step alone from the middle of the bounds (ablation, Fig. 6.11)",
                     G::search},
        r.no_swarm);
  visit(RequestField{"linear_stretch", "--linear-stretch", "ks1 = ks2, eps_s = 0: no biphasic stretch (ablation, Fig. 6.16)",
                     G::search},
        r.linear_stretch);
  visit(RequestField{"no_rest_shape", "--no-rest-shape", "Keep the tile's own rest shape (ablation, Fig. 6.17)", G::search},
        r.no_rest_shape);
  visit(RequestField{"relax_period", "--relax-period",
                     "Relax the tile period per candidate until its coarse stress at rest vanishes (the rest-period "
                     "relaxation, after the rest shape, whose own few period chord steps leave about a tenth of that "
                     "stress). Off by default: on the acrylic records with generated tiles it removed the "
                     "stockinette's 7.7 N/m at zero stretch but raised g on every knit tried, at 1.3-1.8x the time",
                     G::search, false},
        r.relax_period);
  visit(RequestField{"no_shape", "--no-shape",
                     "Keep a generated tile at its prior loop shape instead of fitting its course/wale aspect "
                     "(records whose pattern is a knit without a knitting_gauge)",
                     G::search, false},
        r.no_shape);
  visit(RequestField{"no_profile", "--no-profile",
                     "Skip the identifiability profile (each fitted parameter moved 10 % both ways, 2 local-step "
                     "evaluations per parameter)",
                     G::search},
        r.no_profile);
}

// The shell stage's mesh, law, held-out tests and solve; the stages and the exports.
template <class Request, class Visit>
void visit_plan_fields(Request& r, Visit& visit) {
  using G = RequestGroup;
  visit(RequestField{"stages", "--stages", "shell (the shell fit and its uniform targets) or all (the whole pipeline)",
                     G::stages},
        r.stages);
  visit(RequestField{"mesh", "--mesh", "Shell stage: mesh cell size [mm]", G::shell, false}, r.mesh_mm);
  visit(RequestField{"shell_model", "--shell-model",
                     "In-plane shell law: stiffening (eq. 6.1 plus exponential lock-up per material direction with "
                     "lateral shares, fitted from the thesis model's fit) or thesis (eq. 6.1 alone)",
                     G::shell},
        r.shell_model);
  visit(RequestField{"fab_held_out", "--fab-held-out",
                     "A FAB record's tests held out of the shell fit and predicted: exactly one of S1 and S2, and any "
                     "of the bends U1, D1, D2 but not all three; comma-separated (docs/fab.md)",
                     G::shell},
        r.fab_held_out);
  visit(RequestField{"refinements", "--refine", "Midpoint subdivisions of the mesh (0-4)", G::shell_solve, false},
        r.refinements);
  visit(RequestField{"max_iterations", "--max-iterations",
                     "Ceres iterations of the in-plane fit after its multi-start (1-1000)", G::shell_solve, true, 10000},
        r.max_iterations);
  visit(RequestField{"full_range", "--full-range",
                     "Fit every measured point, not only up to the power range (83.3 N/m line force)", G::shell_solve},
        r.full_range);
  visit(RequestField{"export", "--export",
                     "Also export the fitted fabric, into DIR/exports/: u3m (<id>.u3ma, U3M 1.1), arcsim "
                     "(<id>_arcsim.json, ARCSim's material data), table (table/, CSV and JSON); comma-separated "
                     "(docs/exports.md)",
                     G::outputs},
        r.exports);
}

}  // namespace detail

// Calls visit(field, member) for each field; within a group, in the order the commands' help
// lists them. `Request` is FitRequest or const FitRequest.
template <class Request, class Visit>
void for_each_request_field(Request& r, Visit&& visit) {
  detail::visit_search_fields(r, visit);
  detail::visit_model_fields(r, visit);
  detail::visit_plan_fields(r, visit);
}

}  // namespace yarnfit::pipeline
