#include "geometry/description/field_parser.h"

#include "geometry/description/transform_description.h"
#include "geometry/description/mpu_description.h"
#include "geometry/description/variational_description.h"
#include "geometry/fields/vdb_level_set.h"
#include "geometry/physical_memory.h"
#include "geometry/description/sphere_file.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <sstream>

namespace isotrace::geometry {

namespace {

class Compiler;
using FieldFactory = std::function<uint32_t(Compiler&, JsonObjectReader&, const LeafPlacement&)>;
const std::map<std::string, FieldFactory>& registry();

/// The deepest a field graph may nest (each level a frame of the
/// recursive compiler; 1,000 use well under a megabyte of stack).
constexpr int kMaxFieldDepth = 1000;

class Compiler final : public FieldReferences {
public:
    Compiler(const Json& library, std::string libraryPointer, std::string file, const FieldLibraryOptions& options)
        : library_(library), libraryPointer_(std::move(libraryPointer)), file_(std::move(file)), options_(options) {}

    FieldProgram program;

    const std::string& file() const { return file_; }
    const FieldLibraryOptions& options() const { return options_; }

    /// A field compiled on its own (names resolve in the same library, with
    /// the same cycle check).
    FieldProgram compileField(const Json& description, const std::string& pointer) override {
        Compiler alone(library_, libraryPointer_, file_, options_);
        alone.stack_ = stack_;
        alone.node(description, pointer, {});
        return std::move(alone.program);
    }

    /// The description a name stands for, and its pointer.
    std::pair<const Json*, std::string> describe(const std::string& name, const std::string& pointer) override {
        if (!library_.contains(name)) {
            std::vector<std::string> names;
            for (auto it = library_.begin(); it != library_.end(); ++it) names.push_back(it.key());
            std::string message = "unknown field \"" + name + "\"";
            if (auto near = nearestName(name, names)) message += " (did you mean \"" + *near + "\"?)";
            throw InputError(file_, pointer, message);
        }
        return {&library_.at(name), jsonPointerAppend(libraryPointer_, name)};
    }

    uint32_t node(const Json& j, const std::string& pointer, const LeafPlacement& placement) {
        if (j.is_string()) return reference(j.get<std::string>(), pointer, placement);
        // Compiling recurses through operands and names: bounded, so a deep
        // graph is an error at its place rather than the end of the stack.
        struct Depth {
            int& depth;
            explicit Depth(int& d) : depth(++d) {}
            ~Depth() { --depth; }
        } depth(depth_);
        if (depth_ > kMaxFieldDepth)
            throw InputError(file_, pointer,
                             "the field graph nests deeper than " + std::to_string(kMaxFieldDepth) +
                                 " levels of operands and names here; flatten it (one node can take many operands)");
        if (!j.is_object())
            throw InputError(file_, pointer, "expected a field name or a field description object");
        JsonObjectReader reader(j, pointer, file_);
        std::vector<std::string> types;
        for (const auto& [name, factory] : registry()) types.push_back(name);
        const std::string type = reader.choice("type", types, "");
        const Json* lipschitzClaim = reader.optionalValue("lipschitz");
        const Json* bounds = reader.optionalValue("bounds");
        const uint32_t slot = registry().at(type)(*this, reader, placement);
        reader.finish();
        if (bounds) program.narrowSlotBounds(slot, worldBox(readBox(*bounds, reader.pointerOf("bounds")), placement));
        if (lipschitzClaim) checkLipschitzClaim(j, reader, *lipschitzClaim);
        return slot;
    }

    /// The operands listed under "of" (at least `minimum`).
    std::vector<uint32_t> operands(JsonObjectReader& reader, const LeafPlacement& placement, size_t minimum) {
        const Json& of = reader.value("of");
        const std::string pointer = reader.pointerOf("of");
        if (!of.is_array()) throw InputError(file_, pointer, "expected an array of fields");
        if (of.size() < minimum)
            throw InputError(file_, pointer, "needs at least " + std::to_string(minimum) + " operand" +
                                                 (minimum == 1 ? "" : "s") + ", found " + std::to_string(of.size()));
        std::vector<uint32_t> slots;
        for (size_t i = 0; i < of.size(); ++i) slots.push_back(node(of[i], jsonPointerAppend(pointer, i), placement));
        return slots;
    }
    /// The single operand under "of" (a name, a description, or a one-element array).
    uint32_t operand(JsonObjectReader& reader, const LeafPlacement& placement) {
        const Json& of = reader.value("of");
        if (of.is_array()) {
            if (of.size() != 1) reader.fail("of", "expected exactly one field, found " + std::to_string(of.size()));
            return node(of[0], reader.pointerOf("of") + "/0", placement);
        }
        return node(of, reader.pointerOf("of"), placement);
    }

    Box3 readBox(const Json& j, const std::string& pointer) const {
        if (!j.is_array() || j.size() != 2)
            throw InputError(file_, pointer, "expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]");
        const Vec3 lo = JsonObjectReader::asVec3(j[0], pointer + "/0", file_);
        const Vec3 hi = JsonObjectReader::asVec3(j[1], pointer + "/1", file_);
        if ((lo.array() >= hi.array()).any())
            throw InputError(file_, pointer, "each minimum must be less than its maximum");
        return {lo, hi};
    }
    static Box3 worldBox(const Box3& local, const LeafPlacement& placement) {
        if (placement.identity) return local;
        const Mat3 inverse = placement.linear.inverse();
        return transformBox(inverse, -inverse * placement.offset, local);
    }

private:
    uint32_t reference(const std::string& name, const std::string& pointer, const LeafPlacement& placement) {
        const auto [description, at] = describe(name, pointer);
        if (std::find(stack_.begin(), stack_.end(), name) != stack_.end()) {
            std::string chain;
            for (auto it = std::find(stack_.begin(), stack_.end(), name); it != stack_.end(); ++it) chain += *it + " -> ";
            throw InputError(file_, pointer, "cycle in the field graph: " + chain + name);
        }
        stack_.push_back(name);
        const uint32_t slot = node(*description, at, placement);
        stack_.pop_back();
        return slot;
    }

    // A bound written in a description is checked against the gradient at
    // many points of the field's bounds; it never replaces the proven bounds.
    void checkLipschitzClaim(const Json& description, JsonObjectReader& reader, const Json& claimJson) {
        const double claim = JsonObjectReader::asNumber(claimJson, reader.pointerOf("lipschitz"), file_);
        if (!(claim > 0)) reader.fail("lipschitz", "must be greater than 0");
        Compiler alone(library_, libraryPointer_, file_, options_);
        alone.stack_ = stack_;
        Json copy = description;
        copy.erase("lipschitz");
        alone.node(copy, reader.pointer(), LeafPlacement{});
        const Box3 box = alone.program.bounds();
        if (!box.isFinite() || box.isEmpty())
            reader.fail("lipschitz", "cannot check a Lipschitz bound of an unbounded field; give \"bounds\"");
        std::mt19937_64 rng(12345);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        double worst = 0.0;
        Vec3 worstAt = box.center();
        for (int i = 0; i < 20000; ++i) {
            const Vec3 p = box.lower + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
            Vec3 g;
            alone.program.valueAndGradient(p, g);
            if (g.norm() > worst) {
                worst = g.norm();
                worstAt = p;
            }
        }
        if (worst > claim * (1.0 + 1e-9)) {
            std::ostringstream s;
            s << "declared Lipschitz bound " << claim << " is violated: the gradient's length is " << worst
              << " at (" << worstAt.x() << ", " << worstAt.y() << ", " << worstAt.z() << ")";
            reader.fail("lipschitz", s.str());
        }
    }

    const Json& library_;
    std::string libraryPointer_;
    std::string file_;
    FieldLibraryOptions options_;
    std::vector<std::string> stack_;
    int depth_ = 0;
};

// ---- primitives -----------------------------------------------------------

uint32_t makeSphere(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    return c.program.addLeaf(SphereField{r.vec3("center", Vec3::Zero()), r.positiveNumber("radius")}, p);
}

uint32_t makeBox(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    BoxField box;
    box.center = r.vec3("center", Vec3::Zero());
    const Vec3 size = r.vec3("size");
    if ((size.array() <= 0).any()) r.fail("size", "every edge length must be greater than 0");
    box.halfSize = 0.5 * size;
    box.rounding = r.number("rounding", 0.0);
    if (box.rounding < 0 || box.rounding > box.halfSize.minCoeff())
        r.fail("rounding", "must be between 0 and half the shortest edge");
    return c.program.addLeaf(box, p);
}

uint32_t makeTorus(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    TorusField t{r.vec3("center", Vec3::Zero()), r.positiveNumber("major"), r.positiveNumber("minor")};
    return c.program.addLeaf(t, p);
}

uint32_t makeCylinder(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    return c.program.addLeaf(RevolvedProfileField::cylinder(r.vec3("center", Vec3::Zero()), r.positiveNumber("radius"),
                                                            r.positiveNumber("height")),
                             p);
}

uint32_t makeCone(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const Vec3 center = r.vec3("center", Vec3::Zero());
    const double radius = r.positiveNumber("radius");
    const double top = r.number("top_radius", 0.0);
    if (top < 0) r.fail("top_radius", "must not be negative");
    return c.program.addLeaf(RevolvedProfileField::cone(center, radius, top, r.positiveNumber("height")), p);
}

uint32_t makeCapsule(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    PolylineDistanceField f{{r.vec3("from"), r.vec3("to")}, r.positiveNumber("radius")};
    return c.program.addLeaf(f, p);
}

uint32_t makePlane(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const Vec3 n = r.vec3("normal", Vec3(0, 1, 0));
    if (!(n.norm() > 0)) r.fail("normal", "must not be the zero vector");
    return c.program.addLeaf(PlaneField{n.normalized(), r.number("offset", 0.0)}, p);
}

uint32_t makeEllipsoid(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const Vec3 radii = r.vec3("radii");
    if ((radii.array() <= 0).any()) r.fail("radii", "every radius must be greater than 0");
    return c.program.addLeaf(EllipsoidField{r.vec3("center", Vec3::Zero()), radii}, p);
}

uint32_t makeOctahedron(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    return c.program.addLeaf(OctahedronField{r.vec3("center", Vec3::Zero()), r.positiveNumber("size")}, p);
}

// ---- algebraic surfaces ---------------------------------------------------

Box3 requiredDomain(Compiler& c, JsonObjectReader& r, const char* what) {
    const Json* b = r.optionalValue("domain");
    if (!b) r.failHere(std::string(what) + " needs a \"domain\" box [[xmin, ymin, zmin], [xmax, ymax, zmax]] to search");
    return c.readBox(*b, r.pointerOf("domain"));
}

uint32_t makeQuadric(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const std::vector<double> k = r.numbers("coefficients");
    if (k.size() != 10)
        r.fail("coefficients", "expected 10 numbers (xx yy zz xy yz xz x y z 1), found " + std::to_string(k.size()));
    const std::array<std::array<int, 3>, 10> powers{{{2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {1, 1, 0}, {0, 1, 1},
                                                     {1, 0, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 0}}};
    std::vector<PolynomialTerm> terms;
    for (int i = 0; i < 10; ++i) terms.push_back({k[i], powers[i]});
    Polynomial poly(terms);
    if (poly.terms().empty()) r.fail("coefficients", "all coefficients are zero");
    return c.program.addLeaf(PolynomialField(poly, requiredDomain(c, r, "a quadric")), p);
}

uint32_t makePolynomial(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    if (r.has("preset")) {
        const std::string name = r.choice("preset", polynomialPresetNames(), "");
        PolynomialField field = polynomialPreset(name);
        if (const Json* d = r.optionalValue("domain")) field.domain = c.readBox(*d, r.pointerOf("domain"));
        return c.program.addLeaf(field, p);
    }
    const Json& terms = r.value("terms");
    const std::string pointer = r.pointerOf("terms");
    if (!terms.is_array() || terms.empty())
        throw InputError(c.file(), pointer, "expected a non-empty array of [coefficient, i, j, k] terms");
    std::vector<PolynomialTerm> out;
    for (size_t i = 0; i < terms.size(); ++i) {
        const std::string tp = jsonPointerAppend(pointer, i);
        const Json& t = terms[i];
        if (!t.is_array() || t.size() != 4)
            throw InputError(c.file(), tp, "expected [coefficient, power of x, power of y, power of z]");
        PolynomialTerm term;
        term.coefficient = JsonObjectReader::asNumber(t[0], tp + "/0", c.file());
        for (int a = 0; a < 3; ++a) {
            const double v = JsonObjectReader::asNumber(t[a + 1], tp + "/" + std::to_string(a + 1), c.file());
            if (v < 0 || v > Polynomial::kMaxDegree || std::floor(v) != v)
                throw InputError(c.file(), tp + "/" + std::to_string(a + 1),
                                 "powers are whole numbers from 0 to " + std::to_string(Polynomial::kMaxDegree));
            term.powers[a] = static_cast<int>(v);
        }
        out.push_back(term);
    }
    Polynomial poly(out);
    if (poly.terms().empty()) r.fail("terms", "every coefficient is zero");
    return c.program.addLeaf(PolynomialField(poly, requiredDomain(c, r, "a polynomial")), p);
}

// ---- blobs, distance and convolution surfaces ----------------------------

// A matrix's singular values, largest first. GCC 12 warns falsely that
// Eigen's fixed-size SVD may leave them uninitialised.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
Vec3 singularValues(const Mat3& m) { return Eigen::JacobiSVD<Mat3>(m).singularValues(); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// A blob's core box and frame (Blender's metaball elements): `half_size`
// (0 to 1e6 each), and `axes`, the blob's own x, y and z axes in the
// field's space, any lengths, not (nearly) linearly dependent.
BlobShape readBlobShape(JsonObjectReader& b) {
    BlobShape shape;
    shape.halfSize = b.vec3("half_size", Vec3::Zero());
    if (!(shape.halfSize.array() >= 0.0).all() || !(shape.halfSize.array() <= 1e6).all())
        b.fail("half_size", "every half size must be between 0 and 1e6");
    if (const Json* axes = b.optionalValue("axes")) {
        const std::string pointer = b.pointerOf("axes");
        if (!axes->is_array() || axes->size() != 3)
            throw InputError(b.file(), pointer, "expected three axes: [[x, y, z], [x, y, z], [x, y, z]]");
        Mat3 toWorld;
        for (int i = 0; i < 3; ++i) toWorld.col(i) = JsonObjectReader::asVec3((*axes)[size_t(i)], jsonPointerAppend(pointer, size_t(i)), b.file());
        const double lengths = toWorld.col(0).norm() * toWorld.col(1).norm() * toWorld.col(2).norm();
        if (!(lengths > 0.0) || !(std::abs(toWorld.determinant()) > 1e-9 * lengths) || !(lengths < 1e18))
            throw InputError(b.file(), pointer, "the axes must be three vectors that are not (nearly) in one plane");
        shape.toLocal = toWorld.inverse();
    }
    shape.stretch = singularValues(shape.toLocal)(0);
    return shape;
}

uint32_t makeBlobby(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    BlobbyField f;
    const std::string kernel = r.choice("kernel", {"blinn", "metaball", "soft", "poly6"}, "metaball");
    f.kernel = kernel == "blinn"  ? BlobKernel::Blinn
               : kernel == "soft" ? BlobKernel::SoftObject
               : kernel == "poly6" ? BlobKernel::Poly6
                                   : BlobKernel::Metaball;
    f.threshold = r.positiveNumber("threshold", 0.5);
    if (kernel != "blinn" && r.has("blobbiness")) r.fail("blobbiness", "applies to the \"blinn\" kernel only");
    f.blobbiness = r.positiveNumber("blobbiness", 4.0);
    const Json& blobs = r.value("blobs");
    const std::string pointer = r.pointerOf("blobs");
    if (!blobs.is_array() || blobs.empty()) throw InputError(c.file(), pointer, "expected a non-empty array of blobs");
    auto shapes = std::make_shared<std::vector<BlobShape>>();
    for (size_t i = 0; i < blobs.size(); ++i) {
        JsonObjectReader b(blobs[i], jsonPointerAppend(pointer, i), c.file());
        Blob blob{b.vec3("center"), b.positiveNumber("radius"), b.number("weight", 1.0)};
        if (b.has("half_size") || b.has("axes")) {
            blob.shape = uint32_t(shapes->size());
            shapes->push_back(readBlobShape(b));
        }
        f.blobs.push_back(blob);
        b.finish();
    }
    if (!shapes->empty()) f.shapes = std::move(shapes);
    return c.program.addLeaf(std::move(f), p);
}

// Spheres scattered at random through a region, combined by one
// operation: one leaf (fields/sphere_set.h), however many.
uint32_t makeScatter(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const std::string name = r.choice("operation", {"union", "smooth_union", "intersection"}, "union");
    const SetOperation operation = name == "smooth_union"   ? SetOperation::SmoothUnion
                                   : name == "intersection" ? SetOperation::Intersection
                                                            : SetOperation::Union;
    double blend = 0.0;
    if (operation == SetOperation::SmoothUnion) blend = r.positiveNumber("radius");
    else if (r.has("radius")) r.fail("radius", "is the blend radius of \"operation\": \"smooth_union\" only");

    // A sphere costs its 32 bytes here and more in the cells that hold it:
    // a few hundred in a union, solved in closed form, and up to 1.7 KB in
    // a sphere-traced smooth union, whose cells keep every sphere that can
    // decide their value (bench/RESULTS.md, "Scale"). Refuse what would not
    // fit before allocating, erring high.
    const double bytesPerSphere = operation == SetOperation::Union ? 1024.0 : 2048.0;
    const double maxSpheres = 0.5 * physicalMemoryBytes() / bytesPerSphere;

    std::optional<double> radius;
    if (r.has("shape") || !r.has("file")) {
        JsonObjectReader shape = r.object("shape");
        shape.choice("type", {"sphere"}, "");
        radius = r.has("file") && !shape.has("radius") ? std::nullopt : std::optional(shape.positiveNumber("radius"));
        shape.finish();
    }

    std::vector<SphereField> spheres;
    if (r.has("file")) {
        // An operand list: one sphere per vertex of a PLY file.
        for (const char* key : {"count", "seed", "region", "scale"})
            if (r.has(key)) r.fail(key, "draws spheres at random; a scatter from a \"file\" takes them from the file");
        const std::string file = r.string("file");
        const std::string path = (std::filesystem::path(c.file()).parent_path() / file).string();
        try {
            spheres = readSphereFile(path, radius, maxSpheres);
        } catch (const InputError& e) {
            throw InputError(c.file(), r.pointerOf("file"), e.what());
        }
        return c.program.addLeaf(SphereSetField::of(std::move(spheres), operation, blend), p);
    }

    if (!r.has("count")) r.fail("count", "is required: how many spheres to scatter (or a \"file\" of them)");
    const long long count = r.integer("count", 1, 1, 100'000'000);
    if (double(count) > maxSpheres)
        r.fail("count", std::to_string(count) + " spheres would need about " + std::to_string(double(count) * bytesPerSphere / 1e9).substr(0, 4) +
                            " GB, more than half of this machine's memory");
    const auto seed = uint64_t(r.integer("seed", 0, 0, 1LL << 53));
    const Json* regionJson = r.optionalValue("region");
    if (!regionJson) r.fail("region", "is required: [[xmin, ymin, zmin], [xmax, ymax, zmax]], the box the centres fill");
    const Box3 region = c.readBox(*regionJson, r.pointerOf("region"));
    double smallest = 1.0, largest = 1.0;
    if (r.has("scale")) {
        const std::vector<double> range = r.numbers("scale");
        if (range.size() != 2 || !(range[0] > 0) || !(range[0] <= range[1]) || !std::isfinite(range[1]))
            r.fail("scale", "expected [smallest, largest] with 0 < smallest <= largest");
        smallest = range[0], largest = range[1];
    }

    // Uniform centres and scales from a 64-bit Mersenne twister, turned into
    // doubles by their top 53 bits: the same spheres on every machine.
    std::mt19937_64 random(seed);
    auto uniform = [&random] { return double(random() >> 11) * 0x1.0p-53; };
    spheres.reserve(size_t(count));
    const Vec3 extent = region.extent();
    for (long long i = 0; i < count; ++i) {
        const Vec3 u(uniform(), uniform(), uniform());
        const double scale = smallest + (largest - smallest) * uniform();
        spheres.push_back({region.lower + u.cwiseProduct(extent), *radius * scale});
    }
    return c.program.addLeaf(SphereSetField::of(std::move(spheres), operation, blend), p);
}

uint32_t makeDistance(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const double radius = r.positiveNumber("radius");
    if (r.has("circle")) {
        // Distance to a circle: a torus whose y axis is turned onto the normal.
        JsonObjectReader circle = r.object("circle");
        const Vec3 center = circle.vec3("center", Vec3::Zero());
        const Vec3 normal = circle.vec3("normal", Vec3(0, 1, 0));
        const double circleRadius = circle.positiveNumber("radius");
        circle.finish();
        if (!(normal.norm() > 0)) circle.fail("normal", "must not be the zero vector");
        const Mat3 rotation = Eigen::Quaterniond::FromTwoVectors(Vec3(0, 1, 0), normal.normalized()).toRotationMatrix();
        // child = R^T (parent - center)
        const LeafPlacement placed = p.composed(rotation.transpose(), -rotation.transpose() * center, 1.0);
        return c.program.addLeaf(TorusField{Vec3::Zero(), circleRadius, radius}, placed);
    }
    const Json& points = r.value("points");
    const std::string pointer = r.pointerOf("points");
    if (!points.is_array() || points.empty())
        throw InputError(c.file(), pointer, "expected an array of points: one (a point), two (a segment) or more (a polyline)");
    PolylineDistanceField f;
    f.radius = radius;
    for (size_t i = 0; i < points.size(); ++i)
        f.points.push_back(JsonObjectReader::asVec3(points[i], jsonPointerAppend(pointer, i), c.file()));
    return c.program.addLeaf(std::move(f), p);
}

uint32_t makeConvolution(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    ConvolutionField f;
    f.threshold = r.positiveNumber("threshold", 0.5);
    const Json& segments = r.value("segments");
    const std::string pointer = r.pointerOf("segments");
    if (!segments.is_array() || segments.empty())
        throw InputError(c.file(), pointer, "expected a non-empty array of segments");
    for (size_t i = 0; i < segments.size(); ++i) {
        JsonObjectReader s(segments[i], jsonPointerAppend(pointer, i), c.file());
        ConvolutionSegment seg{s.vec3("from"), s.vec3("to"), s.positiveNumber("radius"), s.number("weight", 1.0)};
        if (!((seg.b - seg.a).norm() > 0)) s.fail("to", "a segment needs two distinct ends");
        s.finish();
        f.segments.push_back(seg);
    }
    return c.program.addLeaf(std::move(f), p);
}

// ---- variational implicit surfaces (Turk and O'Brien) ---------------------

uint32_t makeVariational(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    VariationalContext context;
    // Files named in the description are relative to the scene file.
    context.baseDirectory = std::filesystem::path(c.file()).parent_path().string();
    context.references = &c;
    if (c.options().fitCache) context.fits = c.options().fitCache;
    context.warn = c.options().warn;
    VariationalFit fit = variationalFitFromDescription(r, context);
    if (fit.partition) return c.program.addLeaf(MpuLeafField{std::move(fit.partition)}, p);
    return c.program.addLeaf(VariationalLeafField{std::move(fit.dense)}, p);
}

// ---- multi-level partition of unity implicits (Ohtake et al.) -------------

uint32_t makeMpu(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    VariationalContext context;
    context.baseDirectory = std::filesystem::path(c.file()).parent_path().string();
    context.references = &c;
    if (c.options().fitCache) context.fits = c.options().fitCache;
    context.warn = c.options().warn;
    return c.program.addLeaf(MpuLeafField{mpuFieldFromDescription(r, context)}, p);
}

// ---- OpenVDB level sets ----------------------------------------------------

uint32_t makeVdb(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const std::string name = r.string("file");
    const std::string grid = r.string("grid", "");
    r.finish();  // a misspelt key fails before the file is read
    const std::string path = resolvedFileName(name, std::filesystem::path(c.file()).parent_path().string());
    const std::string where = r.pointerOf("file");
    std::error_code error;
    const auto size = std::filesystem::file_size(path, error);
    const auto time = std::filesystem::last_write_time(path, error);
    if (error) throw InputError(c.file(), where, "cannot read " + path + ": " + error.message());
    const std::string key = path + "\n" + grid + "\n" + std::to_string(size) + "\n" +
                            std::to_string(time.time_since_epoch().count());
    std::shared_ptr<const VdbLevelSet> levelSet = c.options().fitCache ? c.options().fitCache->findLevelSet(key) : nullptr;
    if (!levelSet) {
        // The block bounds and the surface's voxels may take half of memory.
        try {
            levelSet = std::make_shared<const VdbLevelSet>(openVdbLibrary().readLevelSet(path, grid, 0.5 * physicalMemoryBytes()));
        } catch (const std::exception& e) {
            throw InputError(c.file(), where, path + ": " + e.what());
        }
        if (c.options().fitCache) c.options().fitCache->storeLevelSet(key, levelSet);
    }
    return c.program.addLeaf(VdbLevelSetField{std::move(levelSet)}, p);
}

// ---- operators -----------------------------------------------------------

// Folds operands pairwise as a balanced tree, so pruning can drop whole halves.
uint32_t fold(Compiler& c, std::vector<uint32_t> slots, FieldOp op, double parameter) {
    while (slots.size() > 1) {
        std::vector<uint32_t> next;
        for (size_t i = 0; i + 1 < slots.size(); i += 2) next.push_back(c.program.addBinary(op, slots[i], slots[i + 1], parameter));
        if (slots.size() % 2) next.push_back(slots.back());
        slots = std::move(next);
    }
    return slots[0];
}

uint32_t makeUnion(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    return fold(c, c.operands(r, p, 1), FieldOp::Min, 0.0);
}
uint32_t makeIntersection(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    return fold(c, c.operands(r, p, 1), FieldOp::Max, 0.0);
}
// a minus the union of the rest: max(a, -(b1 u b2 ...)).
uint32_t makeDifference(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    std::vector<uint32_t> s = c.operands(r, p, 2);
    const uint32_t rest = fold(c, std::vector<uint32_t>(s.begin() + 1, s.end()), FieldOp::Min, 0.0);
    return c.program.addBinary(FieldOp::Max, s[0], c.program.addUnary(FieldOp::Negate, rest));
}
uint32_t makeComplement(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    return c.program.addUnary(FieldOp::Negate, c.operand(r, p));
}

double blendRadius(JsonObjectReader& r, const LeafPlacement& p) {
    // A placement scales values by valueScale; the blend radius follows.
    return r.positiveNumber("radius") * p.valueScale;
}
uint32_t makeSmoothUnion(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const double k = blendRadius(r, p);
    return fold(c, c.operands(r, p, 1), FieldOp::SmoothMin, k);
}
uint32_t makeSmoothIntersection(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const double k = blendRadius(r, p);
    return fold(c, c.operands(r, p, 1), FieldOp::SmoothMax, k);
}
uint32_t makeSmoothDifference(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const double k = blendRadius(r, p);
    std::vector<uint32_t> s = c.operands(r, p, 2);
    const uint32_t rest = fold(c, std::vector<uint32_t>(s.begin() + 1, s.end()), FieldOp::SmoothMin, k);
    return c.program.addBinary(FieldOp::SmoothMax, s[0], c.program.addUnary(FieldOp::Negate, rest), k);
}

uint32_t makeOffset(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    const double distance = r.number("distance");
    const uint32_t a = c.operand(r, p);
    return c.program.addUnary(FieldOp::AddConstant, a, -distance * p.valueScale);
}

uint32_t makeTransform(Compiler& c, JsonObjectReader& r, const LeafPlacement& p) {
    // parent = T R S child: scale first, then rotate, then translate.
    const AffineDescription affine = readScaleRotateTranslate(r);
    const Mat3& a = affine.linear;
    const Vec3& translate = affine.translation;
    const Mat3 inverse = a.inverse();
    const double sigma = singularValues(a)(2);  // the smallest
    return c.operand(r, p.composed(inverse, -inverse * translate, sigma));
}

const std::map<std::string, FieldFactory>& registry() {
    static const std::map<std::string, FieldFactory> factories{
        {"sphere", makeSphere},
        {"box", makeBox},
        {"torus", makeTorus},
        {"cylinder", makeCylinder},
        {"cone", makeCone},
        {"capsule", makeCapsule},
        {"plane", makePlane},
        {"ellipsoid", makeEllipsoid},
        {"octahedron", makeOctahedron},
        {"quadric", makeQuadric},
        {"polynomial", makePolynomial},
        {"blobby", makeBlobby},
        {"scatter", makeScatter},
        {"distance", makeDistance},
        {"convolution", makeConvolution},
        {"variational", makeVariational},
        {"mpu", makeMpu},
        {"vdb", makeVdb},
        {"union", makeUnion},
        {"intersection", makeIntersection},
        {"difference", makeDifference},
        {"complement", makeComplement},
        {"smooth_union", makeSmoothUnion},
        {"smooth_intersection", makeSmoothIntersection},
        {"smooth_difference", makeSmoothDifference},
        {"offset", makeOffset},
        {"transform", makeTransform},
    };
    return factories;
}

}  // namespace

std::vector<std::string> polynomialPresetNames() { return {"tangle", "heart", "decocube", "pretzel2", "pretzel4"}; }

PolynomialField polynomialPreset(const std::string& name) {
    const Polynomial x = Polynomial::variable(0), y = Polynomial::variable(1), z = Polynomial::variable(2);
    auto k = [](double v) { return Polynomial::constant(v); };
    if (name == "tangle") {
        // Goursat's tangle cube: x^4 - 5x^2 + y^4 - 5y^2 + z^4 - 5z^2 + 11.8 = 0.
        Polynomial p = x.power(4) - 5.0 * x.power(2) + y.power(4) - 5.0 * y.power(2) + z.power(4) - 5.0 * z.power(2) + k(11.8);
        return PolynomialField(p, Box3(Vec3::Constant(-3), Vec3::Constant(3)));
    }
    if (name == "heart") {
        // Taubin's heart, turned y-up: (x^2 + 9/4 z^2 + y^2 - 1)^3 - x^2 y^3 - 9/80 z^2 y^3 = 0.
        Polynomial p = (x.power(2) + 2.25 * z.power(2) + y.power(2) - k(1)).power(3) - x.power(2) * y.power(3) -
                       (9.0 / 80.0) * z.power(2) * y.power(3);
        return PolynomialField(p, Box3(Vec3(-1.5, -1.5, -1.0), Vec3(1.5, 1.5, 1.0)));
    }
    if (name == "decocube") {
        const Polynomial c2 = k(0.64);
        auto arm = [&](const Polynomial& a, const Polynomial& b, const Polynomial& c) {
            return (a.power(2) + b.power(2) - c2).power(2) + (c.power(2) - k(1)).power(2);
        };
        Polynomial p = arm(x, y, z) * arm(y, z, x) * arm(z, x, y) - k(0.04);
        return PolynomialField(p, Box3(Vec3::Constant(-1.6), Vec3::Constant(1.6)));
    }
    if (name == "pretzel2") {
        // A tube around Gerono's lemniscate y^2 = x^2 (1 - x^2): two holes.
        Polynomial p = (x.power(2) * (k(1) - x.power(2)) - y.power(2)).power(2) + 0.5 * z.power(2) - k(0.01);
        return PolynomialField(p, Box3(Vec3(-1.3, -0.9, -0.4), Vec3(1.3, 0.9, 0.4)));
    }
    if (name == "pretzel4") {
        // A tube around y^2 = 16 x^2 (1 - x^2)(x^2 - 1/2)^2: four lobes in a
        // row, equally tall because the double root sits at x^2 = 1/2.
        Polynomial curve = 16.0 * x.power(2) * (k(1) - x.power(2)) * (x.power(2) - k(0.5)).power(2);
        Polynomial p = (curve - y.power(2)).power(2) + 0.5 * z.power(2) - k(0.0036);
        return PolynomialField(p, Box3(Vec3(-1.2, -0.8, -0.25), Vec3(1.2, 0.8, 0.25)));
    }
    throw std::invalid_argument("unknown polynomial preset " + name);
}

FieldLibrary::FieldLibrary(const Json& fields, std::string pointer, std::string file, FieldLibraryOptions options)
    : fields_(fields), pointer_(std::move(pointer)), file_(std::move(file)), options_(std::move(options)) {
    if (!options_.fitCache) options_.fitCache = std::make_shared<FitCache>();
    if (!fields_.is_object()) throw InputError(file_, pointer_, "expected an object mapping field names to descriptions");
    checkShapes();
    checkForCycles();
}

void FieldLibrary::checkShapes() const {
    // Only the fields objects use are compiled (an unused fit costs
    // nothing), but every entry must at least be a field: a description with
    // a known type or the name of another field.
    const std::vector<std::string> types = typeNames();
    for (auto it = fields_.begin(); it != fields_.end(); ++it) {
        const std::string at = jsonPointerAppend(pointer_, it.key());
        const Json& entry = it.value();
        if (entry.is_string()) {
            if (!fields_.contains(entry.get<std::string>()))
                throw InputError(file_, at, "unknown field \"" + entry.get<std::string>() + "\"");
            continue;
        }
        if (!entry.is_object())
            throw InputError(file_, at, "expected a field description (an object with a \"type\") or a field name");
        const auto type = entry.find("type");
        if (type == entry.end()) throw InputError(file_, at, "missing key \"type\"; valid types: " + joinNames(types));
        if (!type->is_string()) throw InputError(file_, jsonPointerAppend(at, "type"), "expected a string");
        const std::string name = type->get<std::string>();
        if (std::find(types.begin(), types.end(), name) == types.end()) {
            std::string message = "unknown field type \"" + name + "\"";
            if (auto near = nearestName(name, types)) message += " (did you mean \"" + *near + "\"?)";
            throw InputError(file_, jsonPointerAppend(at, "type"), message + "; valid types: " + joinNames(types));
        }
    }
}

namespace {

// The names a description refers to, with where: strings where a field goes
// ("of", variational "sample" and "blend", and the arrays under them), in
// nested descriptions too.
struct FieldReference {
    std::string name, pointer;
};

void collectReferences(const Json& j, const std::string& pointer, const Json& fields, std::vector<FieldReference>& out) {
    if (j.is_string()) {
        if (fields.contains(j.get<std::string>())) out.push_back({j.get<std::string>(), pointer});
        return;
    }
    if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i) collectReferences(j[i], jsonPointerAppend(pointer, i), fields, out);
        return;
    }
    if (!j.is_object()) return;
    for (const char* key : {"of", "sample", "blend"})
        if (const auto it = j.find(key); it != j.end()) collectReferences(*it, jsonPointerAppend(pointer, key), fields, out);
}

}  // namespace

void FieldLibrary::checkForCycles() const {
    // Depth-first search with an explicit stack (chains of thousands of
    // named fields must not exhaust the call stack): 0 unvisited, 1 on the
    // current path, 2 done.
    std::map<std::string, int> state;
    std::map<std::string, std::vector<FieldReference>> references;
    for (auto it = fields_.begin(); it != fields_.end(); ++it)
        collectReferences(it.value(), jsonPointerAppend(pointer_, it.key()), fields_, references[it.key()]);
    for (auto it = fields_.begin(); it != fields_.end(); ++it) {
        if (state[it.key()] != 0) continue;
        std::vector<std::pair<std::string, size_t>> path{{it.key(), 0}};
        state[it.key()] = 1;
        while (!path.empty()) {
            auto& [name, next] = path.back();
            const std::vector<FieldReference>& out = references[name];
            if (next == out.size()) {
                state[name] = 2;
                path.pop_back();
                continue;
            }
            const FieldReference& reference = out[next++];
            const std::string& target = reference.name;
            if (state[target] == 1) {
                std::string chain;
                bool on = false;
                for (const auto& [step, unused] : path) {
                    on = on || step == target;
                    if (on) chain += step + " -> ";
                }
                throw InputError(file_, reference.pointer, "cycle in the field graph: " + chain + target);
            }
            if (state[target] == 0) {
                state[target] = 1;
                path.emplace_back(target, 0);
            }
        }
    }
}

bool FieldLibrary::contains(const std::string& name) const { return fields_.contains(name); }

std::vector<std::string> FieldLibrary::names() const {
    std::vector<std::string> out;
    for (auto it = fields_.begin(); it != fields_.end(); ++it) out.push_back(it.key());
    return out;
}

FieldProgram FieldLibrary::compile(const std::string& name) const {
    Compiler compiler(fields_, pointer_, file_, options_);
    compiler.node(Json(name), pointer_, LeafPlacement{});
    return std::move(compiler.program);
}

FieldProgram FieldLibrary::compileDescription(const Json& description, const std::string& pointer) const {
    Compiler compiler(fields_, pointer_, file_, options_);
    compiler.node(description, pointer, LeafPlacement{});
    return std::move(compiler.program);
}

std::vector<std::string> FieldLibrary::typeNames() {
    std::vector<std::string> out;
    for (const auto& [name, factory] : registry()) out.push_back(name);
    return out;
}

}  // namespace isotrace::geometry
