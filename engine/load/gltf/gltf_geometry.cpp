#include "engine/load/gltf/gltf_geometry.h"

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_accessors.h"

namespace rf::gltf {

namespace {
/// KHR_materials_clearcoat's normal texture needs tangents as the base's does.
bool hasClearcoatNormal(const tinygltf::Material& m) {
    auto it = m.extensions.find("KHR_materials_clearcoat");
    return it != m.extensions.end() && it->second.Has("clearcoatNormalTexture");
}
}  // namespace

namespace {

template <typename V>
std::vector<V> toVectors(const AccessorData& d) {
    std::vector<V> out(d.count);
    constexpr int n = V::length();
    for (size_t i = 0; i < d.count; ++i)
        for (int c = 0; c < n; ++c) {
            const float x = c < d.components ? d.at(i, c) : 0.f;
            out[i][c] = std::isfinite(x) ? x : 0.f;
        }
    return out;
}

int attribute(const tinygltf::Primitive& p, const char* name) {
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
}

/// Triangle list from TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN vertex order.
std::vector<uint32_t> unroll(const std::vector<uint32_t>& v, int mode) {
    std::vector<uint32_t> t;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        t.assign(v.begin(), v.begin() + (v.size() / 3) * 3);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < v.size(); ++i) {
            // Every other triangle is reversed so all keep the strip's winding.
            const bool odd = i & 1;
            t.insert(t.end(), {v[i], v[i + 1 + odd], v[i + 2 - odd]});
        }
    } else {  // fan
        for (size_t i = 1; i + 1 < v.size(); ++i) t.insert(t.end(), {v[i], v[i + 1], v[0]});
    }
    return t;
}

/// POSITION's declared min/max, which glTF requires; a vertex outside them (beyond float
/// rounding of the written bounds) marks a corrupt buffer, e.g. a flipped exponent bit.
struct DeclaredBounds {
    bool present = false;  ///< min and max given
    glm::dvec3 lo{0.0}, hi{0.0}, slack{0.0};
    bool contain(const Vec3& p) const {
        if (!present) return true;
        for (int c = 0; c < 3; ++c)
            if (double(p[c]) < lo[c] - slack[c] || double(p[c]) > hi[c] + slack[c]) return false;
        return true;
    }
};

DeclaredBounds declaredBounds(const tinygltf::Accessor& a) {
    DeclaredBounds b;
    if (a.minValues.size() != 3 || a.maxValues.size() != 3) return b;
    b.present = true;
    for (int c = 0; c < 3; ++c) {
        // Quantized positions (KHR_mesh_quantization) declare their bounds in the stored units:
        // integers, normalized to the values read only by the same rule as the data.
        b.lo[c] = componentValue(a.minValues[size_t(c)], a.componentType, a.normalized);
        b.hi[c] = componentValue(a.maxValues[size_t(c)], a.componentType, a.normalized);
        b.slack[c] = 1e-4 * (std::abs(b.hi[c] - b.lo[c]) + std::abs(b.lo[c]) + std::abs(b.hi[c])) + 1e-30;
    }
    return b;
}

}  // namespace

std::vector<Vec3> generateNormals(const std::vector<Vec3>& pos, const std::vector<uint32_t>& idx) {
    std::vector<glm::dvec3> acc(pos.size(), glm::dvec3(0.0));
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
        const glm::dvec3 a(pos[idx[t]]), b(pos[idx[t + 1]]), c(pos[idx[t + 2]]);
        const glm::dvec3 n = glm::cross(b - a, c - a);  // length = twice the area: area weighting
        for (int k = 0; k < 3; ++k) acc[idx[t + k]] += n;
    }
    std::vector<Vec3> out(pos.size(), Vec3(0.f));
    for (size_t i = 0; i < pos.size(); ++i) {
        const double l = glm::length(acc[i]);
        if (l > 0.0 && std::isfinite(l)) out[i] = Vec3(acc[i] / l);
    }
    return out;
}

std::vector<Vec3> morphedPositions(const TriangleMesh& m, const std::vector<double>& w) {
    std::vector<Vec3> p = m.objectPositions.empty() ? m.positions : m.objectPositions;
    for (size_t k = 0; k < m.morphPositions.size() && k < w.size(); ++k) {
        if (w[k] == 0.0 || m.morphPositions[k].empty()) continue;
        for (size_t i = 0; i < p.size(); ++i) p[i] += float(w[k]) * m.morphPositions[k][i];
    }
    return p;
}

std::vector<Vec4> morphedTangents(const TriangleMesh& m, const std::vector<double>& w) {
    std::vector<Vec4> t = m.tangents;
    for (size_t k = 0; k < m.morphTangents.size() && k < w.size(); ++k) {
        if (w[k] == 0.0 || m.morphTangents[k].size() != t.size()) continue;
        for (size_t i = 0; i < t.size(); ++i) t[i] += Vec4(float(w[k]) * m.morphTangents[k][i], 0.f);
    }
    return t;
}

std::vector<Vec3> morphedNormals(const TriangleMesh& m, const std::vector<double>& w) {
    std::vector<Vec3> n = m.objectNormals.empty() ? m.normals : m.objectNormals;
    for (size_t k = 0; k < m.morphNormals.size() && k < w.size(); ++k) {
        if (w[k] == 0.0 || m.morphNormals[k].empty()) continue;
        for (size_t i = 0; i < n.size(); ++i) n[i] += float(w[k]) * m.morphNormals[k][i];
    }
    return n;
}

std::vector<Vec4> generateTangents(const std::vector<Vec3>& pos, const std::vector<Vec3>& nor, const std::vector<Vec2>& uv,
                                   const std::vector<uint32_t>& idx) {
    // Per-triangle tangent from the UV gradients (Lengyel), summed per vertex, then made
    // orthogonal to the normal. glTF normal maps put +Y "up" in the image, towards v = 0, so
    // the bitangent cross(n, t)·w must follow −∂p/∂v (three.js negates MikkTSpace's sign for
    // glTF for the same reason).
    std::vector<glm::dvec3> t(pos.size(), glm::dvec3(0.0)), b(pos.size(), glm::dvec3(0.0));
    for (size_t k = 0; k + 2 < idx.size(); k += 3) {
        const uint32_t i0 = idx[k], i1 = idx[k + 1], i2 = idx[k + 2];
        const glm::dvec3 e1 = glm::dvec3(pos[i1] - pos[i0]), e2 = glm::dvec3(pos[i2] - pos[i0]);
        const glm::dvec2 d1 = glm::dvec2(uv[i1] - uv[i0]), d2 = glm::dvec2(uv[i2] - uv[i0]);
        const double det = d1.x * d2.y - d2.x * d1.y;
        if (!(std::abs(det) > 1e-20)) continue;
        const glm::dvec3 tt = (e1 * d2.y - e2 * d1.y) / det, bb = (e2 * d1.x - e1 * d2.x) / det;
        for (uint32_t i : {i0, i1, i2}) t[i] += tt, b[i] += bb;
    }
    std::vector<Vec4> out(pos.size(), Vec4(0.f));
    for (size_t i = 0; i < pos.size(); ++i) {
        const glm::dvec3 n(nor[i]);
        const glm::dvec3 o = t[i] - n * glm::dot(n, t[i]);
        const double len = glm::length(o);
        if (!(len > 0.0) || !std::isfinite(len)) continue;
        const double w = glm::dot(glm::cross(n, o), -b[i]) < 0.0 ? -1.0 : 1.0;
        out[i] = Vec4(Vec3(o / len), float(w));
    }
    return out;
}

namespace {

/// One primitive being read: where it is in the file, for messages, and its vertex count.
struct PrimitiveReader {
    const tinygltf::Model& model;
    const tinygltf::Primitive& p;
    const std::string& file;
    std::string w;  ///< "meshes[i].primitives[j]"
    size_t nv = 0;

    AccessorData read(int accessor, int type, const char* what) const {
        const AccessorData d = readAccessor(model, accessor, file, {type});
        if (d.count != nv)
            throw InputError(file, w + ": " + what + " has " + std::to_string(d.count) + " elements, POSITION has " + std::to_string(nv));
        return d;
    }

    /// POSITION, with corrupt vertices (non-finite, or outside the accessor's declared min/max)
    /// zeroed and flagged in finite so their triangles are dropped.
    void positions(PrimitiveGeometry& out, std::vector<uint8_t>& finite) {
        const int posAcc = attribute(p, "POSITION");
        if (posAcc < 0) throw InputError(file, w + ": no POSITION attribute");
        const AccessorData pos = readAccessor(model, posAcc, file, {TINYGLTF_TYPE_VEC3});
        nv = pos.count;
        std::vector<Vec3>& P = out.mesh.positions;
        P.resize(nv);
        finite.assign(nv, 1);
        const DeclaredBounds declared = declaredBounds(model.accessors[size_t(posAcc)]);
        out.boundsMissing = !declared.present;
        for (size_t i = 0; i < nv; ++i) {
            P[i] = Vec3(pos.at(i, 0), pos.at(i, 1), pos.at(i, 2));
            const bool outside = isFinite(P[i]) && !declared.contain(P[i]);
            out.outsideBounds += outside;
            if (!isFinite(P[i]) || outside) {
                finite[i] = 0;
                P[i] = Vec3(0.f);
            }
        }
    }

    void attributes(TriangleMesh& m) const {
        if (int a = attribute(p, "NORMAL"); a >= 0) m.normals = toVectors<Vec3>(read(a, TINYGLTF_TYPE_VEC3, "NORMAL"));
        if (int a = attribute(p, "TEXCOORD_0"); a >= 0) m.uvs = toVectors<Vec2>(read(a, TINYGLTF_TYPE_VEC2, "TEXCOORD_0"));
        if (int a = attribute(p, "TEXCOORD_1"); a >= 0) m.uvs1 = toVectors<Vec2>(read(a, TINYGLTF_TYPE_VEC2, "TEXCOORD_1"));
        if (int a = attribute(p, "TANGENT"); a >= 0) m.tangents = toVectors<Vec4>(read(a, TINYGLTF_TYPE_VEC4, "TANGENT"));
        if (int a = attribute(p, "COLOR_0"); a >= 0) m.colors = colors(a);
    }

    /// COLOR_0: RGB or RGBA (alpha 1), float or normalized unsigned byte/short, as the core
    /// specification allows; linear, multiplying the base colour.
    std::vector<Vec4> colors(int a) const {
        const tinygltf::Accessor& acc = model.accessors[size_t(a)];
        const bool normalizedInt = acc.normalized && (acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                      acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
        if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalizedInt)
            throw InputError(file, w + ": COLOR_0 must be float or normalized unsigned byte/short");
        const AccessorData d = readAccessor(model, a, file, {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4});
        if (d.count != nv)
            throw InputError(file, w + ": COLOR_0 has " + std::to_string(d.count) + " elements, POSITION has " + std::to_string(nv));
        std::vector<Vec4> out(d.count, Vec4(1.f));
        for (size_t i = 0; i < d.count; ++i)
            for (int c = 0; c < d.components; ++c) {
                const float x = d.at(i, c);
                out[i][c] = std::isfinite(x) ? std::clamp(x, 0.f, 1.f) : 1.f;
            }
        return out;
    }

    /// The vertex order (indices, or 0…n−1), checked against the vertex count.
    std::vector<uint32_t> order() const {
        std::vector<uint32_t> o;
        if (p.indices >= 0) {
            o = readIndices(model, p.indices, file);
            for (size_t i = 0; i < o.size(); ++i)
                if (o[i] >= nv)
                    throw InputError(file, w + ".indices: index " + std::to_string(o[i]) + " at position " + std::to_string(i) +
                                               " is out of range (" + std::to_string(nv) + " vertices)");
        } else {
            o.resize(nv);
            for (uint32_t i = 0; i < nv; ++i) o[i] = i;
        }
        return o;
    }

    /// JOINTS_n and WEIGHTS_n for every n the primitive has (they come in pairs): joints
    /// unsigned byte or short, weights float or normalized unsigned byte or short. Weights
    /// are normalized per vertex when their sum is off by more than the type's rounding.
    void skinAttributes(PrimitiveGeometry& out) const {
        TriangleMesh& m = out.mesh;
        int sets = 0;
        while (attribute(p, ("JOINTS_" + std::to_string(sets)).c_str()) >= 0 ||
               attribute(p, ("WEIGHTS_" + std::to_string(sets)).c_str()) >= 0)
            ++sets;
        if (sets == 0) return;
        m.influences = 4 * sets;
        m.skinJoints.assign(nv * size_t(m.influences), 0);
        m.skinWeights.assign(nv * size_t(m.influences), 0.f);
        double tolerance = 2e-3;  // float weights: "as close as reasonably possible to 1"
        for (int s = 0; s < sets; ++s) {
            const std::string jn = "JOINTS_" + std::to_string(s), wn = "WEIGHTS_" + std::to_string(s);
            const int ja = attribute(p, jn.c_str()), wa = attribute(p, wn.c_str());
            if (ja < 0 || wa < 0)
                throw InputError(file, w + ": " + (ja < 0 ? wn + " has no " + jn : jn + " has no " + wn) + " (they come in pairs)");
            const tinygltf::Accessor& jacc = model.accessors[size_t(ja)];
            if ((jacc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && jacc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) ||
                jacc.normalized)
                throw InputError(file, w + ".attributes." + jn + " (accessors[" + std::to_string(ja) + "]): joints must be unsigned byte or unsigned short, not normalized");
            const tinygltf::Accessor& wacc = model.accessors[size_t(wa)];
            const bool wInt = wacc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                              wacc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
            if (!(wacc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT || (wInt && wacc.normalized)))
                throw InputError(file, w + ".attributes." + wn + " (accessors[" + std::to_string(wa) + "]): weights must be float or normalized unsigned byte or short");
            if (wInt)  // the stored integers SHOULD sum to 255 or 65535: allow one step per influence
                tolerance = std::max(tolerance, 4.0 * sets / (wacc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 255.0 : 65535.0));
            const AccessorData J = read(ja, TINYGLTF_TYPE_VEC4, jn.c_str());
            const AccessorData W = read(wa, TINYGLTF_TYPE_VEC4, wn.c_str());
            PrimitiveGeometry::JointSet js;
            js.accessor = ja;
            js.set = s;
            for (size_t i = 0; i < nv; ++i)
                for (int c = 0; c < 4; ++c) {
                    const size_t k = i * size_t(m.influences) + size_t(4 * s + c);
                    const float j = J.at(i, c);
                    m.skinJoints[k] = uint16_t(j);  // exact: an integer below 65536
                    if (uint32_t(j) > js.maxJoint) js.maxJoint = uint32_t(j), js.vertex = i;
                    const float x = W.at(i, c);
                    if (!(x >= 0.f) || !std::isfinite(x))
                        throw InputError(file, w + ".attributes." + wn + " (accessors[" + std::to_string(wa) + "]): vertex " +
                                                   std::to_string(i) + " has a negative or non-finite weight");
                    m.skinWeights[k] = x;
                }
            out.jointSets.push_back(js);
        }
        for (size_t i = 0; i < nv; ++i) {
            float* wv = &m.skinWeights[i * size_t(m.influences)];
            double sum = 0.0;
            for (int k = 0; k < m.influences; ++k) sum += wv[k];
            if (sum == 0.0) {
                wv[0] = 1.f;  // unweighted: follows its first joint rather than collapsing
                ++out.weightsZero;
            } else if (std::abs(sum - 1.0) > tolerance) {
                for (int k = 0; k < m.influences; ++k) wv[k] = float(double(wv[k]) / sum);
                ++out.weightsNormalized;
            }
        }
    }

    void morphTargets(TriangleMesh& m) const {
        for (const auto& target : p.targets) {
            std::vector<Vec3> dp, dn, dt;
            if (auto it = target.find("POSITION"); it != target.end())
                dp = toVectors<Vec3>(read(it->second, TINYGLTF_TYPE_VEC3, "a morph target POSITION"));
            if (auto it = target.find("NORMAL"); it != target.end())
                dn = toVectors<Vec3>(read(it->second, TINYGLTF_TYPE_VEC3, "a morph target NORMAL"));
            // Tangent deltas are xyz only (glTF 2.0 §3.7.2.2): the handedness w does not morph.
            if (auto it = target.find("TANGENT"); it != target.end())
                dt = toVectors<Vec3>(read(it->second, TINYGLTF_TYPE_VEC3, "a morph target TANGENT"));
            if (dp.empty()) dp.assign(nv, Vec3(0.f));
            m.morphPositions.push_back(std::move(dp));
            m.morphNormals.push_back(std::move(dn));
            m.morphTangents.push_back(std::move(dt));
        }
    }
};

/// Keeps the triangles whose corners are finite, distinct and span a non-zero area (in double).
void keepGoodTriangles(const std::vector<uint32_t>& tris, const std::vector<uint8_t>& finite, PrimitiveGeometry& out) {
    TriangleMesh& m = out.mesh;
    m.indices.reserve(tris.size());
    for (size_t t = 0; t + 2 < tris.size(); t += 3) {
        const uint32_t a = tris[t], b = tris[t + 1], c = tris[t + 2];
        if (!finite[a] || !finite[b] || !finite[c]) {
            ++out.droppedNonFinite;
            continue;
        }
        const glm::dvec3 pa(m.positions[a]), pb(m.positions[b]), pc(m.positions[c]);
        if (a == b || b == c || a == c || glm::length(glm::cross(pb - pa, pc - pa)) == 0.0) {
            ++out.droppedDegenerate;
            continue;
        }
        m.indices.insert(m.indices.end(), {a, b, c});
    }
}

/// POINTS' dots, or LINES' (pairs), LINE_STRIP's (each vertex to the next) and LINE_LOOP's (and
/// the last back to the first) segments, from the vertex order; a segment with a non-finite end
/// is dropped (counted) and one of zero length is drawn as its dot. Every end of a segment is a
/// dot, once, so the tubes join into capsules.
void wireElements(const std::vector<uint32_t>& order, int mode, const std::vector<uint8_t>& finite, PrimitiveGeometry& out) {
    out.wire = true;
    const std::vector<Vec3>& pos = out.mesh.positions;
    std::vector<uint8_t> dot(pos.size(), 0);
    auto addDot = [&](uint32_t v) {
        if (!dot[v]) dot[v] = 1, out.wirePoints.push_back(v);
    };
    if (mode == TINYGLTF_MODE_POINTS) {
        for (uint32_t v : order) {
            if (finite[v]) addDot(v);
            else ++out.droppedNonFinite;
        }
        return;
    }
    auto addSegment = [&](uint32_t a, uint32_t b) {
        if (!finite[a] || !finite[b]) {
            ++out.droppedNonFinite;
            return;
        }
        addDot(a);
        addDot(b);
        if (a != b && pos[a] != pos[b]) out.wireSegments.insert(out.wireSegments.end(), {a, b});
    };
    if (mode == TINYGLTF_MODE_LINE) {
        for (size_t i = 0; i + 1 < order.size(); i += 2) addSegment(order[i], order[i + 1]);
        out.leftoverIndices = order.size() % 2;
    } else {
        for (size_t i = 0; i + 1 < order.size(); ++i) addSegment(order[i], order[i + 1]);
        if (mode == TINYGLTF_MODE_LINE_LOOP && order.size() > 2) addSegment(order.back(), order.front());
        if (order.size() == 1 && finite[order[0]]) addDot(order[0]);
    }
}

/// Copies of v's per-vertex entries (`per` of them a vertex) for the vertices src lists.
template <class T>
std::vector<T> remapVertices(const std::vector<T>& v, const std::vector<uint32_t>& src, size_t per = 1) {
    if (v.empty()) return {};
    std::vector<T> out;
    out.reserve(src.size() * per);
    for (uint32_t s : src) out.insert(out.end(), v.begin() + ptrdiff_t(size_t(s) * per), v.begin() + ptrdiff_t(size_t(s + 1) * per));
    return out;
}

}  // namespace

PrimitiveGeometry wireGeometry(const PrimitiveGeometry& g, float radius) {
    const TriangleMesh& w = g.mesh;
    std::vector<uint32_t> src;   // the wire vertex each new vertex grew from
    std::vector<Vec3> offset;    // its offset from it: the sphere's or the tube's normal × radius
    std::vector<uint32_t> tris;
    auto vertex = [&](uint32_t from, const Vec3& n) {
        src.push_back(from);
        offset.push_back(n);
        return uint32_t(src.size() - 1);
    };
    for (uint32_t v : g.wirePoints) {
        // An octahedron: its eight faces, each wound counter-clockwise seen from outside.
        uint32_t c[6];
        const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (int k = 0; k < 6; ++k) c[k] = vertex(v, axes[k]);
        for (int sx = 0; sx < 2; ++sx)
            for (int sy = 0; sy < 2; ++sy)
                for (int sz = 0; sz < 2; ++sz) {
                    const uint32_t a = c[sx], b = c[2 + sy], d = c[4 + sz];
                    if ((sx + sy + sz) % 2 == 0) tris.insert(tris.end(), {a, b, d});
                    else tris.insert(tris.end(), {a, d, b});
                }
    }
    constexpr int kSides = 6;
    for (size_t i = 0; i + 1 < g.wireSegments.size(); i += 2) {
        const uint32_t a = g.wireSegments[i], b = g.wireSegments[i + 1];
        const Vec3 d = glm::normalize(w.positions[b] - w.positions[a]);
        // u, v, d right-handed, so (ring k, ring k + 1, the far ring's k) winds outwards.
        const Vec3 helper = std::abs(d.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        const Vec3 u = glm::normalize(glm::cross(d, helper));
        const Vec3 v = glm::cross(d, u);
        uint32_t near[kSides], far[kSides];
        for (int k = 0; k < kSides; ++k) {
            const float t = 2.f * kPi * float(k) / float(kSides);
            const Vec3 n = std::cos(t) * u + std::sin(t) * v;
            near[k] = vertex(a, n);
            far[k] = vertex(b, n);
        }
        for (int k = 0; k < kSides; ++k) {
            const int k1 = (k + 1) % kSides;
            tris.insert(tris.end(), {near[k], near[k1], far[k], near[k1], far[k1], far[k]});
        }
    }
    PrimitiveGeometry out = g;
    out.wire = false;
    out.wirePoints.clear();
    out.wireSegments.clear();
    TriangleMesh& m = out.mesh;
    m.positions.resize(src.size());
    m.normals.resize(src.size());
    for (size_t i = 0; i < src.size(); ++i) {
        m.positions[i] = w.positions[src[i]] + radius * offset[i];
        m.normals[i] = offset[i];
    }
    m.uvs = remapVertices(w.uvs, src);
    m.uvs1 = remapVertices(w.uvs1, src);
    m.colors = remapVertices(w.colors, src);
    m.tangents.clear();  // no normal map on a dot or a line: their normals are their own
    for (auto& t : m.morphPositions) t = remapVertices(t, src);
    for (auto& t : m.morphNormals) t.clear();
    for (auto& t : m.morphTangents) t.clear();
    m.skinJoints = remapVertices(w.skinJoints, src, size_t(w.influences));
    m.skinWeights = remapVertices(w.skinWeights, src, size_t(w.influences));
    m.indices = std::move(tris);
    out.generatedNormals = false;
    return out;
}

bool buildPrimitive(const tinygltf::Model& model, int meshIndex, int primIndex, const std::string& file, PrimitiveGeometry& out,
                    bool tangents) {
    const tinygltf::Primitive& p = model.meshes[size_t(meshIndex)].primitives[size_t(primIndex)];
    PrimitiveReader r{model, p, file, "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(primIndex) + "]"};
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN)
        throw InputError(file, r.w + ".mode: " + std::to_string(mode) + " is not a glTF primitive mode");
    TriangleMesh& m = out.mesh;
    std::vector<uint8_t> finite;
    r.positions(out, finite);
    r.attributes(m);
    const std::vector<uint32_t> order = r.order();
    if (mode <= TINYGLTF_MODE_LINE_STRIP) {
        r.morphTargets(m);
        r.skinAttributes(out);
        wireElements(order, mode, finite, out);
        out.materialOutOfRange = p.material >= int(model.materials.size());
        out.gltfMaterial = out.materialOutOfRange ? -1 : p.material;
        return !out.wirePoints.empty();
    }
    if (mode == TINYGLTF_MODE_TRIANGLES) out.leftoverIndices = order.size() % 3;
    r.morphTargets(m);
    r.skinAttributes(out);
    keepGoodTriangles(unroll(order, mode), finite, out);
    if (m.normals.empty()) {
        // Indexed: smooth, area-weighted per vertex. Non-indexed: every triangle owns its
        // vertices, so the same sum gives flat normals.
        m.normals = generateNormals(m.positions, m.indices);
        out.generatedNormals = true;
    }
    // Normal maps need tangents; glTF asks for generated ones when TANGENT is missing.
    const bool normalMapped = p.material >= 0 && size_t(p.material) < model.materials.size() &&
                              (model.materials[size_t(p.material)].normalTexture.index >= 0 ||
                               hasClearcoatNormal(model.materials[size_t(p.material)]));
    if (tangents && normalMapped && m.tangents.empty() && !m.uvs.empty())
        m.tangents = generateTangents(m.positions, m.normals, model.materials[size_t(p.material)].normalTexture.texCoord == 1 && !m.uvs1.empty() ? m.uvs1 : m.uvs, m.indices);
    out.materialOutOfRange = p.material >= int(model.materials.size());
    out.gltfMaterial = out.materialOutOfRange ? -1 : p.material;
    return true;
}

bool placePrimitive(TriangleMesh& m, const DMat4& renderFromNode, const std::vector<double>& weights, bool flipWinding) {
    const glm::dmat3 l(renderFromNode);
    const double det = glm::determinant(l);
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return false;  // zero scale: nothing visible
    const glm::dmat3 nm = glm::transpose(glm::inverse(l));
    const std::vector<Vec3> pos = morphedPositions(m, weights);
    const std::vector<Vec3> nor = morphedNormals(m, weights);
    m.positions.resize(pos.size());
    m.normals.resize(nor.size());
    for (size_t i = 0; i < pos.size(); ++i) {
        m.positions[i] = Vec3(glm::dvec3(renderFromNode * glm::dvec4(glm::dvec3(pos[i]), 1.0)));
        if (!isFinite(m.positions[i])) return false;
    }
    for (size_t i = 0; i < nor.size(); ++i) {
        const glm::dvec3 n = nm * glm::dvec3(nor[i]);
        const double len = glm::length(n);
        m.normals[i] = len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3(0.f);
    }
    m.tangents = morphedTangents(m, weights);
    for (Vec4& t : m.tangents) {
        const glm::dvec3 v = l * glm::dvec3(Vec3(t));
        const double len = glm::length(v);
        t = Vec4(len > 0.0 && std::isfinite(len) ? Vec3(v / len) : Vec3(0.f), det < 0.0 ? -t.w : t.w);
    }
    // A mirroring transform turns counter-clockwise triangles clockwise: swap two corners so the
    // front face stays where glTF put it (a moving mesh keeps its order and says so instead).
    m.mirrored = !flipWinding && det < 0.0;
    if (det < 0.0 && flipWinding)
        for (size_t t = 0; t + 2 < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
    return !m.indices.empty();
}

}  // namespace rf::gltf
