// osd-stencils: OpenSubdiv's per-frame cost of a deforming cage, for the
// peer check of the animation's stencil tables (docs/BENCHMARKS.md,
// "Animation").
//
// Usage: osd_stencils CAGE.obj [--isolation N] [--frames N]
//
// Reads `v` and `f` lines and the `t crease`, `t corner` and
// `t interpolateboundary` tags (default boundary rule edge-and-corner, as
// the project's converter), refines the cage the way an OpenSubdiv
// application drawing a deforming mesh does (feature-adaptive to level N,
// default 2, OpenSubdiv's viewers' default; Gregory-basis end caps, the
// default), builds the stencil table that gives every point the patch
// table reads from the cage vertices (Far::StencilTableFactory, with the
// end caps' local points appended and factorized), then times
// StencilTable::UpdateValues over --frames frames (default 200) of a
// deforming cage (the vertices moved a little every frame, outside the
// timed call). Prints one line of key = value pairs: the cage, patches,
// stencils, terms, bytes of the table (sizes, offsets, indices: 4 bytes
// each; weights: 4-byte floats) and per patch, the patch table's control
// point indices per patch (4 bytes each: regular patches read the cage
// and refined vertices directly, without a stencil), and the median,
// minimum and maximum milliseconds per frame.

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

struct Vertex {
    float x = 0, y = 0, z = 0;
    void Clear(void * = nullptr) { x = y = z = 0; }
    void AddWithWeight(Vertex const &p, float w) {
        x += w * p.x;
        y += w * p.y;
        z += w * p.z;
    }
};

struct Cage {
    std::vector<Vertex> vertices;
    std::vector<int> faceSizes;
    std::vector<int> faceVertices;
    std::vector<int> creasePairs;
    std::vector<float> creaseSharpness;
    std::vector<int> corners;
    std::vector<float> cornerSharpness;
    int boundary = 2; // edge-and-corner unless a tag says otherwise
};

[[noreturn]] void fail(std::string const &what) {
    std::fprintf(stderr, "osd_stencils: %s\n", what.c_str());
    std::exit(1);
}

Cage read(char const *path) {
    std::ifstream in(path);
    if (!in) fail(std::string("cannot read ") + path);
    Cage cage;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string word;
        if (!(s >> word)) continue;
        if (word == "v") {
            Vertex v;
            s >> v.x >> v.y >> v.z;
            cage.vertices.push_back(v);
        } else if (word == "f") {
            int n = 0;
            std::string corner;
            while (s >> corner) {
                int index = std::atoi(corner.c_str());
                if (index < 0) index += (int)cage.vertices.size() + 1;
                cage.faceVertices.push_back(index - 1);
                ++n;
            }
            cage.faceSizes.push_back(n);
        } else if (word == "t") {
            std::string name, counts;
            s >> name >> counts;
            int ni = 0, nf = 0, ns = 0;
            std::sscanf(counts.c_str(), "%d/%d/%d", &ni, &nf, &ns);
            std::vector<int> ints(ni);
            std::vector<float> floats(nf);
            for (int &i : ints) s >> i;
            for (float &f : floats) s >> f;
            if (name == "crease") {
                for (int k = 0; 2 * k + 1 < ni; ++k) {
                    cage.creasePairs.push_back(ints[2 * k]);
                    cage.creasePairs.push_back(ints[2 * k + 1]);
                    cage.creaseSharpness.push_back(nf == 1 ? floats[0] : floats[k]);
                }
            } else if (name == "corner") {
                for (int k = 0; k < ni; ++k) {
                    cage.corners.push_back(ints[k]);
                    cage.cornerSharpness.push_back(nf == 1 ? floats[0] : floats[k]);
                }
            } else if (name == "interpolateboundary" && ni == 1) {
                cage.boundary = ints[0];
            }
        }
    }
    if (cage.faceSizes.empty()) fail(std::string("no faces in ") + path);
    return cage;
}

Far::TopologyRefiner *refiner(Cage const &cage) {
    Far::TopologyDescriptor d;
    d.numVertices = (int)cage.vertices.size();
    d.numFaces = (int)cage.faceSizes.size();
    d.numVertsPerFace = cage.faceSizes.data();
    d.vertIndicesPerFace = cage.faceVertices.data();
    d.numCreases = (int)cage.creaseSharpness.size();
    d.creaseVertexIndexPairs = cage.creasePairs.data();
    d.creaseWeights = cage.creaseSharpness.data();
    d.numCorners = (int)cage.cornerSharpness.size();
    d.cornerVertexIndices = cage.corners.data();
    d.cornerWeights = cage.cornerSharpness.data();
    Sdc::Options options;
    using O = Sdc::Options;
    options.SetVtxBoundaryInterpolation(cage.boundary == 0   ? O::VTX_BOUNDARY_NONE
                                        : cage.boundary == 1 ? O::VTX_BOUNDARY_EDGE_ONLY
                                                             : O::VTX_BOUNDARY_EDGE_AND_CORNER);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner *r =
        Factory::Create(d, Factory::Options(Sdc::SCHEME_CATMARK, options));
    if (!r) fail("OpenSubdiv refused the cage");
    return r;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace

int main(int argc, char **argv) {
    if (argc < 2) fail("usage: osd_stencils CAGE.obj [--isolation N] [--frames N]");
    int isolation = 2, frames = 200;
    for (int i = 2; i + 1 < argc; i += 2) {
        std::string flag = argv[i];
        if (flag == "--isolation") isolation = std::atoi(argv[i + 1]);
        else if (flag == "--frames") frames = std::atoi(argv[i + 1]);
        else fail("unknown flag " + flag);
    }
    Cage cage = read(argv[1]);
    Far::TopologyRefiner *r = refiner(cage);
    Far::TopologyRefiner::AdaptiveOptions adaptive(isolation);
    r->RefineAdaptive(adaptive);

    Far::StencilTableFactory::Options so;
    so.generateOffsets = true;
    so.generateIntermediateLevels = true;
    so.factorizeIntermediateLevels = true;
    Far::StencilTable const *vertexStencils = Far::StencilTableFactory::Create(*r, so);
    Far::PatchTableFactory::Options po(isolation);
    po.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    Far::PatchTable const *patches = Far::PatchTableFactory::Create(*r, po);
    Far::StencilTable const *table = vertexStencils;
    if (Far::StencilTable const *local = patches->GetLocalPointStencilTable()) {
        table = Far::StencilTableFactory::AppendLocalPointStencilTable(*r, vertexStencils, local);
    }

    int coarse = (int)cage.vertices.size();
    int stencils = table->GetNumStencils();
    size_t terms = table->GetControlIndices().size();
    size_t bytes = 4 * (size_t)stencils * 2 + terms * (4 + sizeof(float));
    int npatches = patches->GetNumPatchesTotal();
    size_t indexBytes = patches->GetPatchControlVerticesTable().size() * 4;

    // Coarse vertices first, then the points the stencils make (the layout
    // OpenSubdiv's examples draw from).
    std::vector<Vertex> buffer(coarse + stencils);
    std::vector<Vertex> rest = cage.vertices;
    std::vector<double> ms;
    double sink = 0;
    for (int f = 0; f < frames + 5; ++f) {
        float a = 0.001f * (float)f;
        for (int v = 0; v < coarse; ++v) {
            buffer[v] = rest[v];
            buffer[v].z += a * rest[v].x;
        }
        auto t0 = std::chrono::steady_clock::now();
        table->UpdateValues(buffer.data(), buffer.data() + coarse);
        auto t1 = std::chrono::steady_clock::now();
        sink += buffer[coarse + (f % stencils)].x;
        if (f >= 5) ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::printf("cage = %s vertices = %d faces = %d isolation = %d patches = %d "
                "stencils = %d terms = %zu bytes = %zu bytes_per_patch = %.0f "
                "index_bytes_per_patch = %.0f bytes_per_face = %.0f frames = %d ms_median = %.4f ms_min = %.4f "
                "ms_max = %.4f (checksum %.3g)\n",
                argv[1], coarse, (int)cage.faceSizes.size(), isolation, npatches, stencils,
                terms, bytes, (double)bytes / npatches, (double)indexBytes / npatches,
                (double)bytes / cage.faceSizes.size(),
                frames, median(ms), *std::min_element(ms.begin(), ms.end()),
                *std::max_element(ms.begin(), ms.end()), sink);
    return 0;
}
