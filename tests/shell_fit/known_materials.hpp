#pragma once
// The in-plane laws the shell tests simulate, written once.
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell::known {

// An anisotropic knit (N/m): soft weft, stiff warp, some coupling.
inline const InplaneParams k_knit{120.0, 35.0, 400.0, 30.0, 5.0, 8.0};
// A stiff, nearly inextensible sheet, for scenes where only bending should matter.
inline const InplaneParams k_stiff{2e4, 0.0, 2e4, 1e4, 0.0, 0.0};

}  // namespace yarnfit::shell::known
