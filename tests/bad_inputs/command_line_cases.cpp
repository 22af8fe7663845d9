#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {

std::vector<BadInputCase> commandLineCases() { return {}; }

}  // namespace isotrace::testing
