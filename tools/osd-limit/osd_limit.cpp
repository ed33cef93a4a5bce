// osd-limit: OpenSubdiv's Catmull-Clark limit surface at chosen points of a
// control cage, as reference data for the project's cage converter.
//
// Usage: osd_limit CAGE.obj [--boundary none|edge-only|edge-and-corner]
//                  [--samples grid|nine|four]
//
// Reads `v` and `f` lines and OpenSubdiv's `t crease`, `t corner` and
// `t interpolateboundary` tags (the same reading rules as the converter,
// see src/scene/tags.rs); `--boundary` is used only when the file has no
// interpolateboundary tag. Prints one line per sample:
//
//     FACE SUB U V X Y Z
//
// FACE is the 0-based `f` line, SUB the ptex sub-face (0 for quads, k for the
// quad of an n-gon at its corner k), (U, V) the sub-face parameters, and
// X Y Z the limit point in double precision, or the word `hole` for faces the
// boundary rule removes.
//
// The points are exact: the cage is refined uniformly until every semi-sharp
// feature has run out (and to level 2 at least), each sample is a vertex of
// that level (all sample parameters are multiples of 1/4), and OpenSubdiv's
// limit masks put it on the limit surface. (A feature-adaptive patch table
// would be cheaper but is not exact: its end caps next to an irregular
// crease vertex miss the limit by up to 5e-5 of the model at level 10.)

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

struct Point {
    double x = 0, y = 0, z = 0;
    void Clear(void * = nullptr) { x = y = z = 0; }
    void AddWithWeight(Point const &p, double w) {
        x += w * p.x;
        y += w * p.y;
        z += w * p.z;
    }
};

struct Cage {
    std::vector<Point> points;
    std::vector<int> faceSizes;
    std::vector<int> faceVerts;
    std::vector<int> creasePairs;
    std::vector<float> creaseSharpness;
    std::vector<int> corners;
    std::vector<float> cornerSharpness;
    int boundaryTag = -1; // OpenSubdiv's integer, -1 when absent
};

[[noreturn]] void fail(std::string const &where, std::string const &msg) {
    std::fprintf(stderr, "osd_limit: %s: %s\n", where.c_str(), msg.c_str());
    std::exit(1);
}

// A face corner: "7", "7/2", "7//3" or "7/2/3"; negative counts back.
int vertexIndex(std::string const &word, int seen, std::string const &where) {
    int i = std::atoi(word.c_str());
    if (i < 0) i = seen + i + 1;
    if (i <= 0) fail(where, "bad vertex index " + word);
    return i - 1;
}

Cage readCage(char const *path) {
    std::ifstream in(path);
    if (!in) fail(path, "cannot open");
    Cage cage;
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        std::string where = std::string(path) + ":" + std::to_string(lineNo);
        std::istringstream words(line);
        std::string key;
        if (!(words >> key)) continue;
        if (key == "v") {
            Point p;
            if (!(words >> p.x >> p.y >> p.z)) fail(where, "bad vertex");
            // The converter reads coordinates as f32; so does the reference.
            p.x = (float)p.x;
            p.y = (float)p.y;
            p.z = (float)p.z;
            cage.points.push_back(p);
        } else if (key == "f") {
            std::string w;
            int n = 0;
            while (words >> w) {
                cage.faceVerts.push_back(vertexIndex(w, (int)cage.points.size(), where));
                ++n;
            }
            cage.faceSizes.push_back(n);
        } else if (key == "t") {
            std::string name, counts;
            words >> name >> counts;
            int ni = 0, nf = 0, ns = 0;
            if (std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns) != 3)
                fail(where, "bad tag counts");
            std::vector<int> ints(ni);
            std::vector<float> floats(nf);
            for (int &i : ints) words >> i;
            for (float &f : floats) words >> f;
            if (!words) fail(where, "tag arguments missing");
            if (name == "crease") {
                if (ni % 2 || nf < 1) fail(where, "crease needs vertex pairs and a sharpness");
                for (int k = 0; k < ni / 2; ++k) {
                    cage.creasePairs.push_back(ints[2 * k]);
                    cage.creasePairs.push_back(ints[2 * k + 1]);
                    cage.creaseSharpness.push_back(nf == 1 ? floats[0] : floats[k]);
                }
            } else if (name == "corner") {
                if (nf < 1) fail(where, "corner needs a sharpness");
                for (int k = 0; k < ni; ++k) {
                    cage.corners.push_back(ints[k]);
                    cage.cornerSharpness.push_back(nf == 1 ? floats[0] : floats[k]);
                }
            } else if (name == "interpolateboundary") {
                if (ni != 1) fail(where, "interpolateboundary needs one integer");
                cage.boundaryTag = ints[0];
            } else {
                std::fprintf(stderr, "osd_limit: %s: tag '%s' ignored\n", where.c_str(),
                             name.c_str());
            }
        }
    }
    return cage;
}

Sdc::Options::VtxBoundaryInterpolation boundaryRule(int tag, std::string const &option) {
    using O = Sdc::Options;
    switch (tag) {
    case 0: return O::VTX_BOUNDARY_NONE;
    case 1: return O::VTX_BOUNDARY_EDGE_AND_CORNER;
    case 2: return O::VTX_BOUNDARY_EDGE_ONLY;
    default: break;
    }
    if (option == "none") return O::VTX_BOUNDARY_NONE;
    if (option == "edge-only") return O::VTX_BOUNDARY_EDGE_ONLY;
    if (option == "edge-and-corner") return O::VTX_BOUNDARY_EDGE_AND_CORNER;
    fail("--boundary", "expected none, edge-only or edge-and-corner");
}

} // namespace

// The level-`level` vertex at (u, v) of `face` at level `at` (quad faces
// only below level 1): a quad's child j keeps its parent's orientation and
// covers the quadrant at corner j, so the descent halves (u, v) each step.
int sampleVertex(Far::TopologyRefiner const &refiner, int at, int face, double u, double v,
                 int level) {
    static const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
    for (;;) {
        Far::TopologyLevel const &here = refiner.GetLevel(at);
        for (int c = 0; c < 4; ++c) {
            if (std::abs(u - cu[c]) < 1e-12 && std::abs(v - cv[c]) < 1e-12) {
                int vert = here.GetFaceVertices(face)[c];
                for (int l = at; l < level; ++l)
                    vert = refiner.GetLevel(l).GetVertexChildVertex(vert);
                return vert;
            }
        }
        if (at == level) fail("sample", "a parameter is not a multiple of 1/4");
        int j = u < 0.5 ? (v < 0.5 ? 0 : 3) : (v < 0.5 ? 1 : 2);
        face = here.GetFaceChildFaces(face)[j];
        u = 2 * u - cu[j];
        v = 2 * v - cv[j];
        ++at;
    }
}

int main(int argc, char **argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: osd_limit CAGE.obj [--boundary RULE] [--samples grid|nine|four]\n");
        return 2;
    }
    std::string boundary = "edge-and-corner", samples = "grid";
    for (int i = 2; i + 1 < argc; i += 2) {
        std::string flag = argv[i];
        if (flag == "--boundary") boundary = argv[i + 1];
        else if (flag == "--samples") samples = argv[i + 1];
        else fail(flag, "unknown option");
    }
    Cage cage = readCage(argv[1]);

    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(boundaryRule(cage.boundaryTag, boundary));
    sdc.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);

    Far::TopologyDescriptor desc;
    desc.numVertices = (int)cage.points.size();
    desc.numFaces = (int)cage.faceSizes.size();
    desc.numVertsPerFace = cage.faceSizes.data();
    desc.vertIndicesPerFace = cage.faceVerts.data();
    desc.numCreases = (int)cage.creaseSharpness.size();
    desc.creaseVertexIndexPairs = cage.creasePairs.data();
    desc.creaseWeights = cage.creaseSharpness.data();
    desc.numCorners = (int)cage.cornerSharpness.size();
    desc.cornerVertexIndices = cage.corners.data();
    desc.cornerWeights = cage.cornerSharpness.data();

    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner *refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc));
    if (!refiner) fail(argv[1], "OpenSubdiv refused the topology");
    // Deep enough that no semi-sharp feature is left (infinite ones stay).
    float semi = 0;
    for (float s : cage.creaseSharpness) if (s < 10) semi = std::max(semi, s);
    for (float s : cage.cornerSharpness) if (s < 10) semi = std::max(semi, s);
    int level = std::max(2, (int)std::ceil(semi));
    Far::TopologyRefiner::UniformOptions uniform(level);
    // The limit masks need each last-level vertex's edges and faces.
    uniform.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uniform);

    std::vector<Point> coarse(cage.points), fine;
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    for (int l = 1; l <= level; ++l) {
        fine.assign(refiner->GetLevel(l).GetNumVertices(), Point());
        Point const *src = coarse.data();
        Point *dst = fine.data();
        primvar.Interpolate(l, src, dst);
        coarse.swap(fine);
    }
    std::vector<Point> limit(coarse.size());
    Point const *src = coarse.data();
    Point *dst = limit.data();
    primvar.Limit(src, dst);

    std::vector<std::pair<double, double>> uvs;
    // Sample sets: every set but `four` covers the face's corners and
    // edges too, where creases and boundaries are.
    if (samples == "grid") {
        for (double v : {0.0, 0.25, 0.5, 0.75, 1.0})
            for (double u : {0.0, 0.25, 0.5, 0.75, 1.0}) uvs.push_back({u, v});
    } else if (samples == "nine") {
        for (double v : {0.0, 0.5, 1.0})
            for (double u : {0.0, 0.5, 1.0}) uvs.push_back({u, v});
    } else if (samples == "four") {
        uvs = {{0, 0}, {0.5, 0}, {0.5, 0.5}, {0.25, 0.75}};
    } else {
        fail("--samples", "expected grid, nine or four");
    }

    std::printf("# osd_limit %s boundary=%d level=%d samples=%s\n", argv[1],
                (int)sdc.GetVtxBoundaryInterpolation(), level, samples.c_str());
    Far::TopologyLevel const &base = refiner->GetLevel(0);
    for (int f = 0; f < desc.numFaces; ++f) {
        int subs = cage.faceSizes[f] == 4 ? 1 : cage.faceSizes[f];
        for (int k = 0; k < subs; ++k) {
            for (auto [u, v] : uvs) {
                if (base.IsFaceHole(f)) {
                    std::printf("%d %d %g %g hole\n", f, k, u, v);
                    continue;
                }
                // The quad of an n-gon at its corner k is child face k,
                // whose corner 0 is the n-gon's vertex k (ptex sub-face k).
                int vert = subs == 1 ? sampleVertex(*refiner, 0, f, u, v, level)
                                     : sampleVertex(*refiner, 1, base.GetFaceChildFaces(f)[k],
                                                    u, v, level);
                Point const &p = limit[vert];
                std::printf("%d %d %g %g %.9g %.9g %.9g\n", f, k, u, v, p.x, p.y, p.z);
            }
        }
    }
    delete refiner;
    return 0;
}
