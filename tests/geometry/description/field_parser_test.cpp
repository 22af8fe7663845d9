#include "geometry/description/field_parser.h"

#include <gtest/gtest.h>

using namespace isotrace::geometry;

namespace {

// Compiles `name` from a "fields" object and returns the error text ("" if none).
std::string compileError(const std::string& fieldsJson, const std::string& name) {
    try {
        FieldLibrary library(Json::parse(fieldsJson), "/fields", "scene.json");
        library.compile(name);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(FieldParser, UnknownTypeNamesThePathAndSuggests) {
    const std::string e = compileError(R"({"a": {"type": "spere", "radius": 1}})", "a");
    EXPECT_NE(e.find("scene.json: /fields/a/type"), std::string::npos) << e;
    EXPECT_NE(e.find("did you mean \"sphere\""), std::string::npos) << e;
}

TEST(FieldParser, UnknownKeyIsRejectedWithSuggestion) {
    const std::string e = compileError(R"({"a": {"type": "sphere", "radius": 1, "centre": [0, 0, 0]}})", "a");
    EXPECT_NE(e.find("/fields/a/centre"), std::string::npos) << e;
    EXPECT_NE(e.find("did you mean \"center\""), std::string::npos) << e;
}

TEST(FieldParser, UnknownFieldNameInOperands) {
    const std::string e = compileError(R"({"a": {"type": "sphere", "radius": 1},
                                            "cut": {"type": "difference", "of": ["a", "ringg"]}})", "cut");
    EXPECT_NE(e.find("/fields/cut/of/1"), std::string::npos) << e;
    EXPECT_NE(e.find("unknown field \"ringg\""), std::string::npos) << e;
}

TEST(FieldParser, CycleInFieldGraphIsReported) {
    const std::string e = compileError(R"({"a": {"type": "union", "of": ["b"]},
                                            "b": {"type": "offset", "distance": 0.1, "of": "a"}})", "a");
    EXPECT_NE(e.find("cycle in the field graph: a -> b -> a"), std::string::npos) << e;
    EXPECT_NE(e.find("/fields/b/of"), std::string::npos) << e;
}

TEST(FieldParser, SelfReferenceIsACycle) {
    const std::string e = compileError(R"({"a": {"type": "complement", "of": "a"}})", "a");
    EXPECT_NE(e.find("cycle"), std::string::npos) << e;
}

// The graph must have no cycles even among fields no object uses: the
// library refuses them when it is made, naming the reference that closes
// the cycle. The check walks with its own stack: a chain of 20,000 named
// fields is fine.
TEST(FieldParser, CyclesAmongUnusedFieldsAreRefused) {
    try {
        FieldLibrary library(Json::parse(R"({"used": {"type": "sphere", "radius": 1},
            "x": {"type": "union", "of": ["used", {"type": "offset", "distance": 0.1, "of": "y"}]},
            "y": {"type": "variational", "blend": ["z", "x"]},
            "z": {"type": "sphere", "radius": 1}})"),
                             "/fields", "scene.json");
        FAIL() << "a cycle was accepted";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("cycle in the field graph: x -> y -> x"), std::string::npos) << what;
        EXPECT_NE(what.find("/fields/y/blend/1"), std::string::npos) << what;
    }
    Json chain = Json::object();
    chain["f0"] = {{"type", "sphere"}, {"radius", 1}};
    for (int i = 1; i < 20000; ++i) chain["f" + std::to_string(i)] = {{"type", "offset"}, {"distance", 0.0}, {"of", "f" + std::to_string(i - 1)}};
    EXPECT_NO_THROW(FieldLibrary(chain, "/fields", "scene.json"));
    chain["f0"] = {{"type", "offset"}, {"distance", 0.0}, {"of", "f19999"}};
    EXPECT_THROW(FieldLibrary(chain, "/fields", "scene.json"), InputError);
}

TEST(FieldParser, InvalidParametersNameTheirPath) {
    EXPECT_NE(compileError(R"({"a": {"type": "sphere", "radius": -1}})", "a").find("/fields/a/radius"), std::string::npos);
    EXPECT_NE(compileError(R"({"a": {"type": "sphere", "radius": "big"}})", "a").find("expected a number"), std::string::npos);
    EXPECT_NE(compileError(R"({"a": {"type": "sphere", "center": [0, 0], "radius": 1}})", "a").find("/fields/a/center"),
              std::string::npos);
    EXPECT_NE(compileError(R"({"a": {"type": "box", "size": [1, 0, 1]}})", "a").find("/fields/a/size"), std::string::npos);
    EXPECT_NE(compileError(R"({"a": {"type": "union", "of": []}})", "a").find("at least 1 operand"), std::string::npos);
    EXPECT_NE(compileError(R"({"a": {"type": "difference", "of": [{"type": "sphere", "radius": 1}]}})", "a").find("at least 2"),
              std::string::npos);
    EXPECT_NE(compileError(R"({"a": {"type": "transform", "scale": [1, 0, 1], "of": {"type": "sphere", "radius": 1}}})", "a")
                  .find("/fields/a/scale"),
              std::string::npos);
    EXPECT_NE(compileError(R"({"a": {"type": "polynomial", "terms": [[1, 2, 0, 0], [-1, 0, 0, 0.5]], "domain": [[-1,-1,-1],[1,1,1]]}})", "a")
                  .find("/fields/a/terms/1/3"),
              std::string::npos);
}

TEST(FieldParser, PolynomialNeedsADomain) {
    const std::string e = compileError(R"({"q": {"type": "quadric", "coefficients": [1,1,1,0,0,0,0,0,0,-1]}})", "q");
    EXPECT_NE(e.find("needs a \"domain\""), std::string::npos) << e;
}

TEST(FieldParser, DeclaredLipschitzBoundIsCheckedWithTheMeasuredValue) {
    // Goursat's tangle has gradients far above 1 inside its domain.
    const std::string bad = compileError(R"({"t": {"type": "polynomial", "preset": "tangle", "lipschitz": 1}})", "t");
    EXPECT_NE(bad.find("/fields/t/lipschitz"), std::string::npos) << bad;
    EXPECT_NE(bad.find("the gradient's length is"), std::string::npos) << bad;
    EXPECT_EQ(compileError(R"({"s": {"type": "sphere", "radius": 1, "lipschitz": 1.0}})", "s"), "");
}

TEST(FieldParser, NamedFieldsAreSharedAndNested) {
    FieldLibrary library(Json::parse(R"({
        "ball": {"type": "sphere", "radius": 1},
        "moved": {"type": "transform", "translate": [2, 0, 0], "of": "ball"},
        "both": {"type": "union", "of": ["ball", "moved"]}})"),
                         "/fields", "scene.json");
    const FieldProgram f = library.compile("both");
    EXPECT_NEAR(f.value(Vec3(2, 0, 0)), -1.0, 1e-12);
    EXPECT_NEAR(f.value(Vec3(0, 0, 0)), -1.0, 1e-12);
    EXPECT_NEAR(f.value(Vec3(1, 0, 0)), 0.0, 1e-12);
    EXPECT_NEAR(f.bounds().upper.x(), 3.0, 1e-12);
}

TEST(FieldParser, UniformScaleKeepsDistances) {
    FieldLibrary library(Json::parse(R"({"s": {"type": "transform", "scale": 2, "of": {"type": "sphere", "radius": 1}}})"),
                         "/fields", "scene.json");
    const FieldProgram f = library.compile("s");
    EXPECT_NEAR(f.value(Vec3(3, 0, 0)), 1.0, 1e-12);
}

namespace {
std::string nested(int levels) {
    std::string text;
    for (int i = 0; i < levels; ++i) text += R"({"type": "union", "of": [)";
    text += R"({"type": "sphere", "radius": 1})";
    for (int i = 0; i < levels; ++i) text += "]}";
    return text;
}
}  // namespace

// The compiler recurses per level of operands and names: 900 levels
// compile, deeper graphs (inline or through a chain of 5,000 names) are an
// error at the JSON path where the limit is crossed, not a stack overflow.
TEST(FieldParser, DeepFieldGraphsAreErrorsAtTheirPlace) {
    EXPECT_NO_THROW(FieldLibrary(Json::parse(R"({"deep": )" + nested(900) + "}"), "/fields", "s.json").compile("deep"));
    try {
        FieldLibrary(Json::parse(R"({"deep": )" + nested(1500) + "}"), "/fields", "s.json").compile("deep");
        FAIL() << "1,500 levels compiled";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("nests deeper than 1000 levels"), std::string::npos);
    }
    Json chain = {{"f0", {{"type", "sphere"}, {"radius", 1}}}};
    for (int i = 1; i <= 5000; ++i)
        chain["f" + std::to_string(i)] = {{"type", "offset"}, {"distance", 0.001}, {"of", "f" + std::to_string(i - 1)}};
    try {
        FieldLibrary(chain, "/fields", "s.json").compile("f5000");
        FAIL() << "a chain of 5,000 names compiled";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("s.json: /fields/f4000: the field graph nests deeper than 1000"),
                  std::string::npos)
            << e.what();
    }
}
