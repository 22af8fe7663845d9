// The solids a path is inside. A path starts inside the solids around the
// camera, is inside a solid after it refracts into it, and outside after
// it refracts out; a reflection leaves its side unchanged. What the path
// meets next must agree. Where it does not, the tracer has seen a surface
// where the ray crosses none: at a concave edge of a CSG solid or a mesh,
// a ray leaving one face starts on the face beside it, and a ray through
// the edge itself has no tangent plane to reflect in. Taken as a crossing,
// such a hit pairs a refraction out with another out and the path gains
// ior^2; the integrators pass through it instead.
#pragma once

#include <algorithm>
#include <array>

namespace isotrace {

class InteriorStack {
public:
    /// Solids nested deeper than this leave the record incomplete: from
    /// then on the path's solids are judged by their normals alone.
    static constexpr int kCapacity = 8;

    enum class Side { Unknown, Outside, Inside };

    Side side(int object) const {
        if (incomplete_) return Side::Unknown;
        return indexOf(object) >= 0 ? Side::Inside : Side::Outside;
    }

    /// Records which side of a solid's surface (`object`, of refractive
    /// index `ior`) the path is on after meeting it.
    void record(int object, double ior, bool inside) {
        const int at = indexOf(object);
        if (!inside) {
            if (at >= 0) {
                std::copy(solids_.begin() + at + 1, solids_.begin() + count_, solids_.begin() + at);
                --count_;
            }
        } else if (at < 0) {
            if (count_ == kCapacity) incomplete_ = true;
            else solids_[count_++] = {object, ior};
        }
    }

    /// The radiance scaling the path owes for the solids it is inside:
    /// the product of their ior^2 (1 outside every solid). A path that
    /// escapes the scene is outside every solid whatever its record says;
    /// an exit the tracer missed (through a sharp edge, closer than the ray
    /// offset) is settled by this factor.
    double radianceScale() const {
        double scale = 1.0;
        for (int i = 0; i < count_; ++i) scale *= solids_[i].ior * solids_[i].ior;
        return scale;
    }

private:
    struct Solid {
        int object;
        double ior;
    };
    int indexOf(int object) const {
        for (int i = 0; i < count_; ++i)
            if (solids_[i].object == object) return i;
        return -1;
    }

    std::array<Solid, kCapacity> solids_{};
    int count_ = 0;
    bool incomplete_ = false;
};

}  // namespace isotrace
