// Name -> factory tables for the renderer's plugin kinds (materials, lights,
// integrators), as Mitsuba's plugin registry: the scene file's "type" picks
// the factory, and an unknown type fails at its JSON path, listing the
// valid names and suggesting the nearest. Each kind lists its types in one
// place (materials/material_types.cpp and the like): adding a type is its
// file plus one line there.
#pragma once

#include <string>
#include <vector>

#include "geometry/description/json_reader.h"

namespace isotrace {

template <class Factory>
class Registry {
public:
    struct Entry {
        std::string name;
        Factory make;
    };
    explicit Registry(std::vector<Entry> entries) : entries_(std::move(entries)) {}

    /// In registration order (the order error messages list them in).
    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const Entry& e : entries_) out.push_back(e.name);
        return out;
    }
    /// The factory named by `r`'s "type" key (`fallback` when absent; empty:
    /// the key is required).
    const Factory& factoryFor(geometry::JsonObjectReader& r, const std::string& fallback = "") const {
        const std::string type = r.choice("type", names(), fallback);
        for (const Entry& e : entries_)
            if (e.name == type) return e.make;
        r.fail("type", "unregistered type");  // unreachable: choice() checked the name
    }

private:
    std::vector<Entry> entries_;
};

}  // namespace isotrace
