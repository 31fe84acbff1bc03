// A swarm stage's checkpoint (<checkpoint>.<stage>), read against the yarn fit's own
// five-parameter space: read_checkpoint throws yarnfit::Error (numerics/util/error.hpp) naming the file and field.

#include "fuzz/fuzz_support.hpp"
#include "numerics/util/error.hpp"
#include "swarm/swarm_state.hpp"

YARNFIT_FUZZ_TARGET(swarm_checkpoint) {
  using namespace yarnfit;
  static const swarm::ParameterSpace space({{"ks1", 0.4, 400.0, true},
                                            {"eps_s", 1e-4, 0.15, true},
                                            {"kb", 1e-9, 1e-5, true},
                                            {"R1", 1e-4, 3e-4, false},
                                            {"kc1", 1e3, 1e7, true}});
  const auto file = fuzz::input_file(fuzz::as_text(data, size), "fit_checkpoint.json.all");
  try {
    (void)swarm::detail::read_checkpoint(file, space);
  } catch (const Error&) {
  }
  return 0;
}
