// Scene mutations: from two valid scenes that use every key the format has,
// each value replaced by one of a type it can never have, each array
// emptied and each object given a key isotrace does not know. The message
// must name the scene file and the JSON path of the change.
#include <nlohmann/json.hpp>

#include <set>

#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {
namespace {

using Json = nlohmann::ordered_json;

std::string testName(const std::string& text) {
    std::string name;
    for (char c : text) {
        const bool word = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
        if (word) name += c;
        else if (!name.empty() && name.back() != '_') name += '_';
    }
    while (!name.empty() && name.back() == '_') name.pop_back();
    return name;
}

/// Arrays of plain values of one kind (vectors, lists of names, rows of
/// numbers) are read by one loop: their first element stands for all.
bool isUniformList(const Json& value) {
    if (!value.is_array() || value.empty() || value[0].is_object()) return false;
    for (const auto& element : value)
        if (element.type() != value[0].type() || (element.is_number() != value[0].is_number())) return false;
    return true;
}

/// Lists that may validly be empty: a scene lit only by emissive objects,
/// a variational field without one kind of constraint.
bool mayBeEmpty(const Json::json_pointer& at) {
    static const std::set<std::string> keys{"lights", "boundary", "interior", "exterior", "values", "normals", "gradients"};
    return keys.count(at.back()) > 0;
}

class MutationWriter {
public:
    MutationWriter(const char* sceneText, std::string file, std::vector<BadInputCase>& cases)
        : root_(Json::parse(sceneText)), file_(std::move(file)), cases_(cases) {}

    void visit(const Json& node, const Json::json_pointer& at, bool elementOfVector) {
        const std::string place = at.to_string();
        if (!at.empty()) {
            // A vector's elements may be reported at the vector.
            const std::string mentioned = elementOfVector ? at.parent_pointer().to_string() : place;
            add("wrong_type", at, node.is_boolean() ? Json("yes") : Json(true), mentioned);
            if (node.is_array() && !node.empty() && !mayBeEmpty(at)) add("empty", at, Json::array(), place);
        }
        if (node.is_object()) {
            Json withUnknownKey = node;
            withUnknownKey["bogus_key"] = 1;
            add("unknown_key", at, withUnknownKey, place + "/bogus_key");
            for (const auto& [key, value] : node.items()) visit(value, at / key, false);
        } else if (node.is_array()) {
            const bool uniform = isUniformList(node);
            const size_t visited = uniform ? 1 : node.size();
            for (size_t i = 0; i < visited; ++i) visit(node[i], at / i, uniform && node[0].is_number());
        }
    }
    const Json& root() const { return root_; }

private:
    void add(const std::string& kind, const Json::json_pointer& at, const Json& replacement,
             const std::string& mentioned) {
        Json mutated = root_;
        if (at.empty()) mutated = replacement;
        else mutated[at] = replacement;
        BadInputCase c;
        c.name = testName(file_ + "_" + kind + "_" + at.to_string()) + "_" + std::to_string(cases_.size());
        c.files[file_] = mutated.dump(1);
        c.arguments = "render " + file_ + " -o out.exr --quiet";
        c.mentions = {file_, mentioned};
        cases_.push_back(std::move(c));
    }

    Json root_;
    std::string file_;
    std::vector<BadInputCase>& cases_;
};

}  // namespace

std::vector<BadInputCase> sceneMutationCases() {
    std::vector<BadInputCase> cases;
    for (const auto& [text, file] : {std::pair{completeScene(), "scene.json"}, std::pair{alternativeScene(), "other.json"}}) {
        MutationWriter writer(text, file, cases);
        writer.visit(writer.root(), Json::json_pointer(), false);
    }
    return cases;
}

}  // namespace isotrace::testing
