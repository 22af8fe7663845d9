#include "renderer/commands/command.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "geometry/errors.h"

using namespace isotrace;

// Bad input and a failing environment are the user's to fix (exit 2); a
// broken invariant is ours (its own exit status and an "internal error").
TEST(Command, ExitStatusTellsBadInputFromInternalErrors) {
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(runReportingErrors([]() -> int { throw geometry::InputError("s.json", "/film/width", "must be positive"); }),
              kExitBadInput);
    EXPECT_EQ(runReportingErrors([]() -> int { throw geometry::IoError("out.exr", "cannot write image"); }), kExitBadInput);
    EXPECT_EQ(runReportingErrors([]() -> int { throw std::runtime_error("in.obj: a library's own complaint"); }),
              kExitBadInput);
    EXPECT_EQ(runReportingErrors([]() -> int { throw std::bad_alloc(); }), kExitBadInput);
    EXPECT_EQ(runReportingErrors([]() -> int { throw geometry::InternalError("Embree error 2 while building"); }),
              kExitInternalError);
    EXPECT_EQ(runReportingErrors([]() -> int { throw std::logic_error("object placed with no such shape"); }),
              kExitInternalError);
    EXPECT_EQ(runReportingErrors([]() -> int { throw 42; }), kExitInternalError);
    EXPECT_EQ(runReportingErrors([] { return int(kExitComparisonFailed); }), kExitComparisonFailed);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("error: s.json: /film/width: must be positive"), std::string::npos) << err;
    EXPECT_NE(err.find("internal error: object placed with no such shape"), std::string::npos) << err;
    EXPECT_NE(err.find("error: out.exr: cannot write image"), std::string::npos) << err;
    EXPECT_NE(err.find("internal error: Embree error 2 while building"), std::string::npos) << err;
    EXPECT_NE(kExitInternalError, kExitBadInput);
    EXPECT_NE(kExitInternalError, kExitComparisonFailed);
}

TEST(Command, EverySubcommandIsWired) {
    for (const char* name : {"render", "polygonize", "merge", "compare", "fit", "preview", "sample", "voxelize"}) {
        const char* argv[] = {"isotrace", name, "--help"};
        ::testing::internal::CaptureStdout();
        EXPECT_EQ(runIsotrace(3, argv), 0) << name;
        const std::string help = ::testing::internal::GetCapturedStdout();
        EXPECT_NE(help.find(name), std::string::npos) << help;
    }
    const char* unknown[] = {"isotrace", "rendr"};
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(runIsotrace(2, unknown), kExitBadInput);
    ::testing::internal::GetCapturedStderr();
}
