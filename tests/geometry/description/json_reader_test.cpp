#include "geometry/description/json_reader.h"

#include <gtest/gtest.h>

using namespace isotrace::geometry;

// Text nested past the parser's recursion is refused at its line and
// column before parsing; strings holding brackets do not count.
TEST(JsonReader, DeepNestingIsAnErrorNotACrash) {
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    try {
        parseJsonText(deep, "deep.json");
        FAIL() << "accepted 100,000 levels";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("deep.json: line 1, column 4001: JSON nested deeper than 4000 levels"),
                  std::string::npos)
            << e.what();
    }
    const std::string fine = std::string(3000, '[') + "\"[[[{{{\"" + std::string(3000, ']');
    EXPECT_NO_THROW(parseJsonText(fine, "fine.json"));
}
