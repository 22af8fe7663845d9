// The faces around each vertex of a mesh being simplified, one cache line
// per vertex: the simplifier reads the fans of both ends of every candidate
// collapse, so a fan costs one memory access, and building them costs no
// allocation per vertex.
//
// Marching cubes gives a vertex 4 to 8 faces and a collapse merges two fans,
// so nearly all fit in a record's slots; a fan that outgrows them moves to a
// list of its own. Each vertex's fan is written only by the thread that owns
// the vertex (the simplifier's blocks), so vertices need no locks.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace isotrace::geometry {

class VertexFans {
public:
    /// Every vertex's fan must be assigned before it is read: the records
    /// start uninitialised, so that the caller fills them in parallel.
    explicit VertexFans(size_t vertices) : records_(new Record[vertices]), large_(vertices) {}

    std::span<const uint32_t> operator[](uint32_t v) const {
        const Record& r = records_[v];
        return {r.count <= kSlots ? r.slots : large_[v].data(), r.count};
    }
    bool empty(uint32_t v) const { return records_[v].count == 0; }

    void assign(uint32_t v, std::span<const uint32_t> faces) {
        Record& r = records_[v];
        r.count = uint32_t(faces.size());
        if (faces.size() <= kSlots) {
            std::copy(faces.begin(), faces.end(), r.slots);
            std::vector<uint32_t>().swap(large_[v]);
        } else {
            large_[v].assign(faces.begin(), faces.end());
        }
    }
    void clear(uint32_t v) { assign(v, {}); }

    void pushBack(uint32_t v, uint32_t face) {
        Record& r = records_[v];
        if (r.count < kSlots) {
            r.slots[r.count++] = face;
            return;
        }
        if (r.count == kSlots) large_[v].assign(r.slots, r.slots + kSlots);
        large_[v].push_back(face);
        ++r.count;
    }

    /// Removes the faces for which `drop` is true, keeping the others' order.
    template <class Drop>
    void eraseIf(uint32_t v, Drop drop) {
        Record& r = records_[v];
        uint32_t* data = r.count <= kSlots ? r.slots : large_[v].data();
        const uint32_t* end = std::remove_if(data, data + r.count, drop);
        const uint32_t count = uint32_t(end - data);
        if (r.count > kSlots && count <= kSlots) {
            std::copy(data, data + count, r.slots);  // before the list goes
            std::vector<uint32_t>().swap(large_[v]);
        } else if (r.count > kSlots) {
            large_[v].resize(count);
        }
        r.count = count;
    }

private:
    static constexpr uint32_t kSlots = 15;
    struct alignas(64) Record {
        uint32_t count;
        uint32_t slots[kSlots];
    };
    std::unique_ptr<Record[]> records_;
    std::vector<std::vector<uint32_t>> large_;  ///< fans of more than kSlots faces
};

}  // namespace isotrace::geometry
