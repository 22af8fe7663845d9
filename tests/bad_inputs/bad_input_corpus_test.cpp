// The bad-input corpus: every case run as a user would, in a folder of its
// own, under a time limit. ISOTRACE_CORPUS_EXECUTABLE runs it against
// another build (tests/sanitize.sh points it at the sanitizer build).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "bad_inputs/bad_input_case.h"
#include "support/run_command.h"

namespace isotrace::testing {
namespace {

namespace fs = std::filesystem;

std::string executable() {
    const char* other = std::getenv("ISOTRACE_CORPUS_EXECUTABLE");
    return other && *other ? other : ISOTRACE_EXECUTABLE;
}

/// Runs a shell command in `folder`; `timeout` turns a hang into 124.
CommandResult run(const fs::path& folder, const std::string& command) {
    return runShell("cd '" + folder.string() + "' && timeout -k 5 120 " + command + " </dev/null");
}

std::string isotraceCommand(const std::string& arguments) { return "'" + executable() + "' " + arguments; }

/// Every file below `folder` with its bytes (symbolic links by target).
std::map<std::string, std::string> snapshot(const fs::path& folder) {
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(folder)) {
        const std::string name = fs::relative(entry.path(), folder).string();
        if (entry.is_symlink()) files[name] = "-> " + fs::read_symlink(entry.path()).string();
        else if (entry.is_directory()) files[name + "/"] = "";
        else if (entry.is_regular_file()) {
            std::ifstream in(entry.path(), std::ios::binary);
            files[name] = std::string(std::istreambuf_iterator<char>(in), {});
        } else files[name] = "(special file)";
    }
    return files;
}

class BadInput : public ::testing::TestWithParam<BadInputCase> {};

TEST_P(BadInput, IsRefusedCleanly) {
    const BadInputCase& c = GetParam();
    const fs::path root = fs::temp_directory_path() / ("isotrace-corpus-" + c.name + "-" + std::to_string(::getpid()));
    const fs::path folder = root / "case";
    fs::remove_all(root);
    fs::create_directories(folder);
    auto files = fixtureFiles();
    for (const auto& [name, content] : c.files) files[name] = content;
    for (const auto& [name, content] : files) std::ofstream(folder / name, std::ios::binary) << content;
    // Fits are cached outside the folder, so the folder shows only outputs.
    ::setenv("ISOTRACE_CACHE_DIR", (root / "cache").c_str(), 1);
    for (const std::string& step : c.setup) {
        const bool ownCommand = step.rfind("isotrace ", 0) == 0;
        const CommandResult prepared = run(folder, ownCommand ? isotraceCommand(step.substr(9)) : step);
        ASSERT_EQ(prepared.exitCode, 0) << "setup failed: " << step << "\n" << prepared.output;
    }
    const auto before = snapshot(folder);

    const CommandResult outcome = run(folder, isotraceCommand(c.arguments));
    const std::string context = "isotrace " + c.arguments + "\n" + outcome.output;
    EXPECT_NE(outcome.exitCode, 124) << "hang: " << context;
    EXPECT_EQ(outcome.exitCode, 2) << context;
    EXPECT_NE(outcome.output.find("error"), std::string::npos) << context;
    for (const std::string& mention : c.mentions)
        EXPECT_NE(outcome.output.find(mention), std::string::npos) << "does not name \"" << mention << "\": " << context;
    for (const char* report : {"AddressSanitizer", "LeakSanitizer", "runtime error:", "terminate called"})
        EXPECT_EQ(outcome.output.find(report), std::string::npos) << context;

    const auto after = snapshot(folder);
    for (const auto& [name, content] : after) {
        const auto was = before.find(name);
        if (was == before.end()) ADD_FAILURE() << "left behind: " << name << "\n" << context;
        else if (was->second != content) ADD_FAILURE() << "changed: " << name << "\n" << context;
    }
    for (const auto& [name, content] : before)
        if (!after.count(name)) ADD_FAILURE() << "removed: " << name << "\n" << context;
    fs::remove_all(root);
}

std::vector<BadInputCase> allCases() {
    std::vector<BadInputCase> cases;
    for (auto part : {sceneMutationCases, sceneFileCases, commandLineCases, inputFileCases, vdbFileCases})
        for (auto& c : part()) cases.push_back(std::move(c));
    return cases;
}

std::string caseName(const ::testing::TestParamInfo<BadInputCase>& info) {
    std::string name = info.param.name;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput, ::testing::ValuesIn(allCases()), caseName);

// The fixtures themselves are valid: each case breaks exactly one thing.
TEST(BadInputFixtures, AreValid) {
    const fs::path folder = fs::temp_directory_path() / ("isotrace-corpus-fixtures-" + std::to_string(::getpid()));
    fs::remove_all(folder);
    fs::create_directories(folder);
    for (const auto& [name, content] : fixtureFiles()) std::ofstream(folder / name, std::ios::binary) << content;
    ::setenv("ISOTRACE_CACHE_DIR", (folder / "cache").c_str(), 1);
    for (const char* scene : {"scene.json", "other.json", "small.json"}) {
        const CommandResult outcome = run(folder, isotraceCommand(std::string("render ") + scene + " -o out.exr --quiet"));
        EXPECT_EQ(outcome.exitCode, 0) << scene << ": " << outcome.output;
        EXPECT_EQ(outcome.output.find("warning"), std::string::npos) << scene << ": " << outcome.output;
    }
    fs::remove_all(folder);
}

}  // namespace
}  // namespace isotrace::testing
