// `isotrace fit`: a variational implicit surface through a polygon model or
// an oriented point set, saved so scenes load it without solving again
// ({"type": "variational", "fitted": "FIELD.json"}).
#pragma once

#include <string>

namespace isotrace {

struct FitCommand {
    std::string input, output;
    double normalOffset = 0.0;  ///< 0: 0.01 of the bounding-box diagonal
    bool hermite = false;
    double margin = 0.0;        ///< 0: the default domain margin
    bool quiet = false;
};

/// Bad input (unreadable or malformed files, singular systems, too many
/// constraints) throws geometry::InputError; nothing is written then.
void runFit(const FitCommand& command);

}  // namespace isotrace
