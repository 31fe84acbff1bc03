// Implementation pending (see yarn_elements.hpp).
#include "yarn_fit/energies/yarn_elements.hpp"
