#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {

std::vector<BadInputCase> inputFileCases() { return {}; }

}  // namespace isotrace::testing
