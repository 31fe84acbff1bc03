// The yarn fit's checkpoint (read on resume, by `fit`, `batch` and the service after a
// restart): read_fit_checkpoint throws std::runtime_error naming the file and the field.
#include <stdexcept>

#include "yarn_fit/fit/fit_checkpoint.hpp"
#include "fuzz/fuzz_support.hpp"

YARNFIT_FUZZ_TARGET(fit_checkpoint) {
  using namespace yarnfit;
  const auto file = fuzz::input_file(fuzz::as_text(data, size), "fit_checkpoint.json");
  try {
    (void)yarn::read_fit_checkpoint(file);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
