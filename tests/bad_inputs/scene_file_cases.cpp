#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {

std::vector<BadInputCase> sceneFileCases() { return {}; }

}  // namespace isotrace::testing
