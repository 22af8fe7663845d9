// `isotrace compare`: image differences with thresholds, for regression
// tests and people. Exit 0 within thresholds, 1 over the fail threshold (or
// NaN and infinite pixels), 2 for bad input.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace isotrace {

struct CompareCommand {
    std::string test, reference;
    std::string metric = "rmse";
    double fail = -1.0;          ///< < 0: the metric's default
    double warn = -1.0;          ///< < 0: none
    double failPercent = -1.0;   ///< < 0: none
    double pixelThreshold = 0.1;
    double pixelsPerDegree = 0.0;  ///< FLIP viewing condition; 0: the papers' default
    std::string noise;           ///< a second render of `test` with another seed
    std::string diff;            ///< difference image (.exr: |a - b|; other: a colour map)
    bool json = false;
};

void addCompareCommand(CLI::App& app, CompareCommand& command);
int runCompare(const CompareCommand& command);

}  // namespace isotrace
