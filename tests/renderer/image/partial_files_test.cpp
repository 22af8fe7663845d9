#include "renderer/image/partial_files.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include "support/temporary_files.h"

using namespace isotrace;
using isotrace::testing::TemporaryFolder;

// A signal while a file is being written removes it, and the process still
// ends by that signal; a file whose write finished is left alone.
TEST(PartialFiles, SignalsRemoveFilesBeingWritten) {
    TemporaryFolder folder;
    const std::string partial = folder.file(".out.partial-1.exr"), done = folder.file("done.exr");
    std::ofstream(done) << "finished";
    for (int signal : {SIGINT, SIGTERM}) {
        std::ofstream(partial) << "half";
        EXPECT_EXIT(
            {
                removePartialFilesOnSignal();
                { const PartialFile finished(done); }
                const PartialFile guard(partial);
                std::raise(signal);
            },
            ::testing::KilledBySignal(signal), "");
        EXPECT_FALSE(std::filesystem::exists(partial)) << "signal " << signal;
        EXPECT_TRUE(std::filesystem::exists(done));
    }
}
