// `isotrace fit --report`: what a user sees of a fit, measured against the
// input: a torus model fitted by both methods comes back closed, in one
// piece of genus 1, within a small fraction of its diagonal both ways.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <sstream>

#include "support/run_command.h"
#include "support/temporary_files.h"

using isotrace::testing::runIsotrace;
using isotrace::testing::TemporaryFolder;

namespace {

// A torus (radii 1 and 0.4) as an OFF model of 32 x 16 quads, split.
std::string torusOff() {
    const int n = 32, m = 16;
    std::ostringstream off;
    off << "OFF\n" << n * m << " " << 2 * n * m << " 0\n";
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
            off << (1 + 0.4 * std::cos(v)) * std::cos(u) << " " << 0.4 * std::sin(v) << " "
                << (1 + 0.4 * std::cos(v)) * std::sin(u) << "\n";
        }
    auto at = [&](int i, int j) { return ((i + n) % n) * m + (j + m) % m; };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < m; ++j) {
            off << "3 " << at(i, j) << " " << at(i, j + 1) << " " << at(i + 1, j + 1) << "\n";
            off << "3 " << at(i, j) << " " << at(i + 1, j + 1) << " " << at(i + 1, j) << "\n";
        }
    return off.str();
}

nlohmann::json fitReport(TemporaryFolder& folder, const std::string& method) {
    const std::string input = folder.write("torus.off", torusOff());
    const auto r = runIsotrace("fit " + input + " -o " + folder.file(method + ".json") + " --method " + method +
                               " -q --report --report-resolution 64");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return nlohmann::json::parse(r.output);
}

}  // namespace

TEST(FitReport, TorusFitsAreClosedOfGenusOneAndCloseToTheModel) {
    TemporaryFolder folder;
    for (const std::string method : {"mpu", "variational"}) {
        const nlohmann::json report = fitReport(folder, method);
        EXPECT_EQ(report["input"]["genus"], nlohmann::json::array({1})) << method << report.dump(2);
        EXPECT_TRUE(report["input"]["closed"].get<bool>()) << method;
        EXPECT_TRUE(report["fit"]["closed"].get<bool>()) << method << report.dump(2);
        EXPECT_EQ(report["fit"]["components"].get<int>(), 1) << method << report.dump(2);
        EXPECT_EQ(report["fit"]["genus"], nlohmann::json::array({1})) << method << report.dump(2);
        // The model's flat facets lie within 0.4 (1 - cos(pi / 16)) = 0.008
        // of the round torus the fits follow: about 0.3% of the diagonal.
        EXPECT_LT(report["distance"]["mean"].get<double>(), 0.003) << method << report.dump(2);
        EXPECT_LT(report["distance"]["max"].get<double>(), 0.01) << method << report.dump(2);
        EXPECT_GT(report["distance"]["max"].get<double>(), 0.0) << method;
        EXPECT_NEAR(report["diagonal"].get<double>(), std::sqrt(2.8 * 2.8 * 2 + 0.8 * 0.8), 0.05) << method;
    }
}
