// The "colors": [a, b] pair that solid textures blend between.
#pragma once

#include "renderer/texture.h"

namespace isotrace {

struct TwoColors {
    RGB a = RGB::Zero(), b = RGB::Ones();
    int channels = 1;

    static TwoColors read(geometry::JsonObjectReader& r) {
        TwoColors c;
        if (!r.has("colors")) return c;
        const geometry::Json& j = r.value("colors");
        if (!j.is_array() || j.size() != 2) r.fail("colors", "expected two values [a, b]");
        int ca = 1, cb = 1;
        c.a = readTextureValue(j[0], r.pointerOf("colors") + "/0", r.file(), ca);
        c.b = readTextureValue(j[1], r.pointerOf("colors") + "/1", r.file(), cb);
        c.channels = std::max(ca, cb);
        return c;
    }
    RGB mix(double t) const { return (1 - t) * a + t * b; }
};

}  // namespace isotrace
