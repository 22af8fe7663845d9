// The root of a function of one variable inside a bracket whose ends have
// values of opposite sign: the Illinois variant of regula falsi,
// superlinear on smooth crossings, never leaving the bracket, falling back
// to bisection when it stalls. Shared by the sphere tracers.
#pragma once

namespace isotrace::geometry {

/// `valueAt(t)` evaluates the function; each call adds one to *evaluations
/// when given.
template <class ValueAt>
double bracketedRoot(const ValueAt& valueAt, double ta, double fa, double tb, double fb, double tolerance,
                     int* evaluations) {
    auto negative = [](double v) { return v < 0; };
    int side = 0;
    for (int i = 0; i < 100 && tb - ta > tolerance; ++i) {
        double t = (ta * fb - tb * fa) / (fb - fa);
        if (!(t > ta && t < tb)) t = 0.5 * (ta + tb);
        const double f = valueAt(t);
        if (evaluations) ++*evaluations;
        if (f == 0.0) return t;
        if (negative(f) != negative(fa)) {
            tb = t;
            fb = f;
            if (side == -1) fa *= 0.5;
            side = -1;
        } else {
            ta = t;
            fa = f;
            if (side == 1) fb *= 0.5;
            side = 1;
        }
    }
    return 0.5 * (ta + tb);
}

}  // namespace isotrace::geometry
