// The yarn fit's checkpoint (read on resume, by `fit`, `batch` and the service after a
// restart): read_fit_checkpoint throws yarnfit::Error (numerics/util/error.hpp) naming the file and the field.

#include "yarn_fit/fit/fit_checkpoint.hpp"
#include "fuzz/fuzz_support.hpp"
#include "numerics/util/error.hpp"

YARNFIT_FUZZ_TARGET(fit_checkpoint) {
  using namespace yarnfit;
  const auto file = fuzz::input_file(fuzz::as_text(data, size), "fit_checkpoint.json");
  try {
    (void)yarn::read_fit_checkpoint(file);
  } catch (const Error&) {
  }
  return 0;
}
