// osd-limit: OpenSubdiv's Catmull-Clark limit surface at chosen points of a
// control cage, as reference data for the project's cage converter.
//
// Usage: osd_limit CAGE.obj [--boundary none|edge-only|edge-and-corner]
//                  [--samples grid|nine|four|dense|corners:M|rings:M]
//                  [--fvar corners-only|all]
//
// Reads `v` and `f` lines and OpenSubdiv's `t crease`, `t corner`,
// `t interpolateboundary`, `t hole`, `t creasemethod` and
// `t smoothtriangles` tags (the same reading rules as the converter, see
// src/cage/tags.rs); `--boundary` is used only when the file has no
// interpolateboundary tag. Prints one line per sample:
//
//     FACE SUB U V X Y Z
//
// FACE is the 0-based `f` line, SUB the ptex sub-face (0 for quads, k for the
// quad of an n-gon at its corner k), (U, V) the sub-face parameters, and
// X Y Z the limit point in double precision, or the word `hole` for faces the
// boundary rule removes. With `--fvar RULE` the cage's texture coordinates
// (`vt`, `f v/vt`) are a face-varying channel interpolated by OpenSubdiv's
// FVAR_LINEAR_CORNERS_ONLY or FVAR_LINEAR_ALL, and each line ends with the
// channel's limit S T there as well.
//
// Sample sets: `grid` 5x5 per (sub-)face, edges included; `nine` 3x3;
// `four` four points; `dense` 17x17 (every 1/16: between the quarters,
// where a fitted cubic's largest error lies); `corners:M` the 5x5 grid
// and, at each corner whose vertex is not regular, the 5x5 grids of the
// squares of side 2^-m there, m = 1..M (where isolation's irregular rings
// lie, down to level M); `rings:M` the same with 9x9 grids (the rings'
// patches between their quarters too).
//
// The points are exact: the cage is refined uniformly until every semi-sharp
// feature has run out and every sample is a vertex of the last level (the
// parameters are multiples of 1/4, of 1/16 for dense, of 2^-(M+2) for
// corners:M, of 2^-(M+3) for rings:M; faces that
// are not quads take one level more, their sub-faces being the first), and
// OpenSubdiv's limit masks put each on the limit surface. (A feature-adaptive patch table
// would be cheaper but is not exact: its end caps next to an irregular
// crease vertex miss the limit by up to 5e-5 of the model at level 10.)

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <array>
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
    std::vector<Point> uvs;     // `vt` (u, v, 0)
    std::vector<int> faceUvs;   // per face corner, as faceVerts; empty without
    bool uvMissing = false;     // some corner had no `vt`
    std::vector<int> creasePairs;
    std::vector<float> creaseSharpness;
    std::vector<int> corners;
    std::vector<float> cornerSharpness;
    std::vector<int> holes;
    int boundaryTag = -1; // OpenSubdiv's integer, -1 when absent
    bool chaikin = false;
    bool smoothTriangles = false;
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
        } else if (key == "vt") {
            Point t;
            if (!(words >> t.x >> t.y)) fail(where, "bad texture coordinate");
            t.x = (float)t.x;
            t.y = (float)t.y;
            cage.uvs.push_back(t);
        } else if (key == "f") {
            std::string w;
            int n = 0;
            while (words >> w) {
                cage.faceVerts.push_back(vertexIndex(w, (int)cage.points.size(), where));
                size_t slash = w.find('/');
                if (slash == std::string::npos || slash + 1 >= w.size() || w[slash + 1] == '/')
                    cage.uvMissing = true;
                else
                    cage.faceUvs.push_back(
                        vertexIndex(w.substr(slash + 1), (int)cage.uvs.size(), where));
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
            std::vector<std::string> strings(ns);
            for (int &i : ints) words >> i;
            for (float &f : floats) words >> f;
            for (std::string &w : strings) words >> w;
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
            } else if (name == "hole") {
                for (int f : ints) cage.holes.push_back(f);
            } else if (name == "creasemethod" && ns == 1) {
                cage.chaikin = strings[0] == "chaikin";
            } else if (name == "smoothtriangles" && ns == 1) {
                cage.smoothTriangles = strings[0] == "smooth";
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

// A corner of a face at the last level: where a sample's vertex and its
// face-varying value are read.
struct FaceCorner {
    int face, corner;
};

// The level-`level` face corner at (u, v) of `face` at level `at` (quad
// faces only below level 1): a quad's child j keeps its parent's orientation
// and covers the quadrant at corner j, so the descent halves (u, v) each
// step; a corner's child face c has the corner's child vertex as its corner c.
FaceCorner sampleCorner(Far::TopologyRefiner const &refiner, int at, int face, double u,
                        double v, int level) {
    static const double cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
    for (;;) {
        Far::TopologyLevel const &here = refiner.GetLevel(at);
        for (int c = 0; c < 4; ++c) {
            if (std::abs(u - cu[c]) < 1e-12 && std::abs(v - cv[c]) < 1e-12) {
                for (int l = at; l < level; ++l)
                    face = refiner.GetLevel(l).GetFaceChildFaces(face)[c];
                return {face, c};
            }
        }
        if (at == level) fail("sample", "a parameter is finer than the refinement level");
        int j = u < 0.5 ? (v < 0.5 ? 0 : 3) : (v < 0.5 ? 1 : 2);
        face = here.GetFaceChildFaces(face)[j];
        u = 2 * u - cu[j];
        v = 2 * v - cv[j];
        ++at;
    }
}

// The face-varying rule a `--fvar` option names.
Sdc::Options::FVarLinearInterpolation fvarRule(std::string const &option) {
    if (option == "corners-only") return Sdc::Options::FVAR_LINEAR_CORNERS_ONLY;
    if (option == "all") return Sdc::Options::FVAR_LINEAR_ALL;
    fail("--fvar", "expected corners-only or all");
}

// A sample set: the (u, v) of the whole (sub-)face, and per corner c the
// (u, v) of the rings at that corner (corners:M only), and the number of
// halvings the finest parameter needs.
struct SampleSet {
    std::vector<std::pair<double, double>> face;
    std::vector<std::pair<double, double>> ring[4];
    int depth = 2;
};

SampleSet sampleSet(std::string const &samples) {
    SampleSet set;
    auto &uvs = set.face;
    if (samples == "grid") {
        for (double v : {0.0, 0.25, 0.5, 0.75, 1.0})
            for (double u : {0.0, 0.25, 0.5, 0.75, 1.0}) uvs.push_back({u, v});
    } else if (samples == "nine") {
        for (double v : {0.0, 0.5, 1.0})
            for (double u : {0.0, 0.5, 1.0}) uvs.push_back({u, v});
    } else if (samples == "four") {
        uvs = {{0, 0}, {0.5, 0}, {0.5, 0.5}, {0.25, 0.75}};
    } else if (samples == "dense") {
        set.depth = 4;
        for (int j = 0; j <= 16; ++j)
            for (int i = 0; i <= 16; ++i) uvs.push_back({i / 16.0, j / 16.0});
    } else if (samples.rfind("corners:", 0) == 0 || samples.rfind("rings:", 0) == 0) {
        bool rings = samples[0] == 'r';
        // Grid intervals per square side, and its log2.
        int n = rings ? 8 : 4, bits = rings ? 3 : 2;
        int m = std::atoi(samples.c_str() + (rings ? 6 : 8));
        if (m < 0 || m > 8) fail("--samples", "corners:M and rings:M need 0 <= M <= 8");
        set.depth = m + bits;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) uvs.push_back({double(i) / n, double(j) / n});
        // Corner c of the square at (0,0), (1,0), (1,1), (0,1).
        for (int l = 1; l <= m; ++l) {
            double side = std::ldexp(1.0, -l);
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i) {
                    double a = side * i / n, b = side * j / n;
                    std::pair<double, double> at[4] = {{a, b}, {1 - a, b}, {1 - a, 1 - b}, {a, 1 - b}};
                    for (int c = 0; c < 4; ++c) {
                        auto &r = set.ring[c];
                        if (std::find(uvs.begin(), uvs.end(), at[c]) == uvs.end() &&
                            std::find(r.begin(), r.end(), at[c]) == r.end())
                            r.push_back(at[c]);
                    }
                }
        }
    } else {
        fail("--samples", "expected grid, nine, four, dense, corners:M or rings:M");
    }
    return set;
}

// Whether the limit surface near vertex v of the base level is anything but
// a regular interior B-spline patch's: the rings are sampled there.
// (A regular boundary vertex, two faces and three edges with only the
// boundary sharp, counts as regular.)
bool irregular(Far::TopologyLevel const &base, int v) {
    if (base.IsVertexNonManifold(v) || base.GetVertexSharpness(v) > 0) return true;
    int edges = base.GetVertexEdges(v).size(), faces = base.GetVertexFaces(v).size();
    bool boundary = base.IsVertexBoundary(v);
    if (boundary ? (edges != 3 || faces != 2) : (edges != 4 || faces != 4)) return true;
    for (int e : base.GetVertexEdges(v))
        if (base.GetEdgeSharpness(e) > 0 && !base.IsEdgeBoundary(e)) return true;
    return false;
}

// The limit of a dart, or of a smooth vertex of valence 2, of the last
// level: OpenSubdiv's smooth limit mask is exact only where every edge is
// smooth and the valence is 3 or more (at a dart on catmark_inf_crease0 it
// misses by 8.6e-4 of the model at level 2, and still 3e-6 at level 8), so
// the vertex's one-ring is subdivided with OpenSubdiv's rules until it has
// shrunk to a point (the converter does the same, src/cage/acc.rs).
bool iteratedLimit(Far::TopologyLevel const &lv, std::vector<Point> const &pos, int vert,
                   Point &out) {
    Far::ConstIndexArray faces = lv.GetVertexFaces(vert);
    Far::ConstLocalIndexArray local = lv.GetVertexFaceLocalIndices(vert);
    int n = faces.size();
    if (n < 2 || lv.IsVertexBoundary(vert) || lv.IsVertexNonManifold(vert)) return false;
    if (lv.GetVertexSharpness(vert) > 0) return false;
    struct Corner { int a, d, b; };
    std::vector<Corner> ring;
    for (int i = 0; i < n; ++i) {
        Far::ConstIndexArray fv = lv.GetFaceVertices(faces[i]);
        if (fv.size() != 4) return false;
        int k = local[i];
        ring.push_back({fv[(k + 1) % 4], fv[(k + 2) % 4], fv[(k + 3) % 4]});
    }
    // Chain the faces: the next one across the edge to a.
    std::vector<Corner> order = {ring[0]};
    while ((int)order.size() < n) {
        auto next = std::find_if(ring.begin(), ring.end(),
                                 [&](Corner const &c) { return c.b == order.back().a; });
        if (next == ring.end()) return false;
        order.push_back(*next);
    }
    auto vec = [](Point const &p) { return std::array<double, 3>{p.x, p.y, p.z}; };
    using V = std::array<double, 3>;
    auto add = [](V a, V b) { return V{a[0] + b[0], a[1] + b[1], a[2] + b[2]}; };
    auto mul = [](V a, double s) { return V{a[0] * s, a[1] * s, a[2] * s}; };
    V v = vec(pos[vert]);
    std::vector<V> e(n), d(n);
    std::vector<double> sharp(n);
    int sharpEdges = 0;
    for (int i = 0; i < n; ++i) {
        e[i] = vec(pos[order[i].a]);
        d[i] = vec(pos[order[i].d]);
        sharp[i] = lv.GetEdgeSharpness(lv.FindEdge(vert, order[i].a));
        sharpEdges += sharp[i] > 0;
    }
    if (sharpEdges != 1 && !(sharpEdges == 0 && n == 2)) return false;
    for (int step = 0; step < 60; ++step) {
        std::vector<V> f(n);
        V q{0, 0, 0}, r{0, 0, 0};
        for (int i = 0; i < n; ++i) {
            f[i] = mul(add(add(v, e[i]), add(d[i], e[(i + n - 1) % n])), 0.25);
            q = add(q, mul(f[i], 1.0 / n));
            r = add(r, mul(add(v, e[i]), 0.5 / n));
        }
        V nv = mul(add(add(q, mul(r, 2.0)), mul(v, n - 3.0)), 1.0 / n);
        for (int i = 0; i < n; ++i) {
            V mid = mul(add(v, e[i]), 0.5);
            V smooth = mul(add(add(v, e[i]), add(f[i], f[(i + 1) % n])), 0.25);
            double s = sharp[i];
            e[i] = s >= 1 ? mid : add(smooth, mul(add(mid, mul(smooth, -1)), std::max(s, 0.0)));
            sharp[i] = s >= 10 ? s : (s > 1 ? s - 1 : 0);
        }
        d = f;
        v = nv;
    }
    out.x = v[0];
    out.y = v[1];
    out.z = v[2];
    return true;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: osd_limit CAGE.obj [--boundary RULE] [--samples grid|nine|four|dense|corners:M|rings:M]\n");
        return 2;
    }
    std::string boundary = "edge-and-corner", samples = "grid", fvar;
    for (int i = 2; i + 1 < argc; i += 2) {
        std::string flag = argv[i];
        if (flag == "--boundary") boundary = argv[i + 1];
        else if (flag == "--samples") samples = argv[i + 1];
        else if (flag == "--fvar") fvar = argv[i + 1];
        else fail(flag, "unknown option");
    }
    Cage cage = readCage(argv[1]);
    bool uv = !fvar.empty();
    if (uv && (cage.uvMissing || cage.faceUvs.size() != cage.faceVerts.size()))
        fail(argv[1], "--fvar needs a `vt` at every face corner");

    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(boundaryRule(cage.boundaryTag, boundary));
    sdc.SetCreasingMethod(cage.chaikin ? Sdc::Options::CREASE_CHAIKIN
                                       : Sdc::Options::CREASE_UNIFORM);
    sdc.SetTriangleSubdivision(cage.smoothTriangles ? Sdc::Options::TRI_SUB_SMOOTH
                                                    : Sdc::Options::TRI_SUB_CATMARK);
    if (uv) sdc.SetFVarLinearInterpolation(fvarRule(fvar));

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
    desc.numHoles = (int)cage.holes.size();
    desc.holeIndices = cage.holes.data();
    Far::TopologyDescriptor::FVarChannel channel;
    channel.numValues = (int)cage.uvs.size();
    channel.valueIndices = cage.faceUvs.data();
    if (uv) {
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }

    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner *refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc));
    if (!refiner) fail(argv[1], "OpenSubdiv refused the topology");
    SampleSet set = sampleSet(samples);
    int depth = set.depth;
    // Deep enough that no semi-sharp feature is left (infinite ones stay;
    // Chaikin's rule never leaves more than the largest sharpness minus the
    // steps taken) and every sample is a vertex.
    float semi = 0;
    for (float s : cage.creaseSharpness) if (s < 10) semi = std::max(semi, s);
    for (float s : cage.cornerSharpness) if (s < 10) semi = std::max(semi, s);
    bool nonQuads = std::any_of(cage.faceSizes.begin(), cage.faceSizes.end(),
                                [](int n) { return n != 4; });
    int level = std::max(depth + (nonQuads ? 1 : 0), (int)std::ceil(semi));
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
    // The face-varying channel the same way, its values per level.
    std::vector<Point> uvCoarse(cage.uvs), uvFine, uvLimit;
    if (uv) {
        for (int l = 1; l <= level; ++l) {
            uvFine.assign(refiner->GetLevel(l).GetNumFVarValues(), Point());
            Point const *s = uvCoarse.data();
            Point *d = uvFine.data();
            primvar.InterpolateFaceVarying(l, s, d);
            uvCoarse.swap(uvFine);
        }
        uvLimit.assign(uvCoarse.size(), Point());
        Point const *s = uvCoarse.data();
        Point *d = uvLimit.data();
        primvar.LimitFaceVarying(s, d);
    }
    Far::TopologyLevel const &last = refiner->GetLevel(level);
    int iterated = 0;
    for (int v = 0; v < last.GetNumVertices(); ++v) {
        Sdc::Crease::Rule rule = last.GetVertexRule(v);
        bool dart = rule == Sdc::Crease::RULE_DART;
        bool val2 = rule == Sdc::Crease::RULE_SMOOTH && last.GetVertexFaces(v).size() == 2;
        if ((dart || val2) && iteratedLimit(last, coarse, v, limit[v])) ++iterated;
    }

    std::printf("# osd_limit %s boundary=%d level=%d samples=%s iterated=%d fvar=%s\n", argv[1],
                (int)sdc.GetVtxBoundaryInterpolation(), level, samples.c_str(), iterated,
                uv ? fvar.c_str() : "-");
    Far::TopologyLevel const &base = refiner->GetLevel(0);
    for (int f = 0; f < desc.numFaces; ++f) {
        int n = cage.faceSizes[f];
        int subs = n == 4 ? 1 : n;
        Far::ConstIndexArray fv = base.GetFaceVertices(f);
        for (int k = 0; k < subs; ++k) {
            // Which corners of the (sub-)face are irregular: a quad's own
            // vertices; a sub-face's corner 0 (the n-gon's vertex k) and
            // corner 2 (its centre, of valence n).
            bool at[4];
            for (int c = 0; c < 4; ++c)
                at[c] = subs == 1 ? irregular(base, fv[c])
                                  : (c == 0 ? irregular(base, fv[k]) : c == 2);
            std::vector<std::pair<double, double>> uvs = set.face;
            for (int c = 0; c < 4; ++c)
                if (at[c]) uvs.insert(uvs.end(), set.ring[c].begin(), set.ring[c].end());
            for (auto [u, v] : uvs) {
                if (base.IsFaceHole(f)) {
                    std::printf("%d %d %g %g hole\n", f, k, u, v);
                    continue;
                }
                // The quad of an n-gon at its corner k is child face k,
                // whose corner 0 is the n-gon's vertex k (ptex sub-face k).
                FaceCorner at = subs == 1 ? sampleCorner(*refiner, 0, f, u, v, level)
                                          : sampleCorner(*refiner, 1,
                                                         base.GetFaceChildFaces(f)[k], u, v,
                                                         level);
                Point const &p = limit[last.GetFaceVertices(at.face)[at.corner]];
                std::printf("%d %d %.17g %.17g %.9g %.9g %.9g", f, k, u, v, p.x, p.y, p.z);
                if (uv) {
                    Point const &t = uvLimit[last.GetFaceFVarValues(at.face)[at.corner]];
                    std::printf(" %.9g %.9g", t.x, t.y);
                }
                std::printf("\n");
            }
        }
    }
    delete refiner;
    return 0;
}
