#include "whitted.h"

#include "optics.h"

namespace rf {

namespace {

/// Hanika 2021, "Hacking the shadow terminator": move the shadow-ray origin of a smooth-shaded
/// triangle towards the surface its vertex normals describe, so faces turned to the light are
/// not shadowed by their own flat neighbours.
/// side = −1 when the surface is seen from behind: the vertex normals are flipped with it, so the
/// point moves towards the viewer's side, never through the surface.
Vec3 terminatorSafeOrigin(const Scene& scene, const SurfaceInteraction& si, float side) {
    if (si.mesh < 0) return si.p;
    const TriangleMesh& mesh = scene.meshes[si.mesh];
    if (mesh.normals.empty()) return si.p;
    const uint32_t* idx = &mesh.indices[3 * si.tri];
    const float b[3] = {si.bary.b0, si.bary.b1, si.bary.b2};
    Vec3 shifted = si.p;
    for (int k = 0; k < 3; ++k) {
        const Vec3& v = mesh.positions[idx[k]];
        const Vec3 n = side * mesh.normals[idx[k]];
        Vec3 tmp = si.p - v;
        const float dn = std::min(0.f, glm::dot(tmp, n));
        tmp -= dn * n;
        shifted += b[k] * (tmp - (si.p - v));
    }
    // Vertex normals that disagree with the facet (turned away from it) would push the point
    // through the surface; Hanika's shift only ever lifts it to the viewer's side.
    if (!isFinite(shifted) || glm::dot(shifted - si.p, side * si.ng) < 0.f) return si.p;
    return shifted;
}

/// Where a ray leaving si starts. One that skips si's own primitive (the plane, or the sphere it
/// leaves outwards: Scene::skipFor) cannot re-meet it however p rounded, so it starts at p and
/// saves the offset; any other is pushed off the surface by p's error bound.
Vec3 spawnOrigin(const Vec3& p, const SurfaceInteraction& si, const Vec3& ng, const Vec3& side, uint32_t skip) {
    return skip == si.prim ? p : offsetRayOrigin(p, si.pError, ng, side);
}

}  // namespace

WhittedTracer::WhittedTracer(const Scene& scene, const RenderSettings& settings)
    : scene_(scene), settings_(settings) {
    specFloor_.reserve(scene.materials.size());
    for (const Material& m : scene.materials)
        specFloor_.push_back(m.shininess > 0.f ? std::exp2(-40.f / m.shininess) : 0.f);
}

Color WhittedTracer::baseColor(const SurfaceInteraction& si, float* alphaOut) const {
    const Material& m = scene_.materials[si.material];
    Color c = m.color;
    float alpha = m.alpha;
    if (m.checkerScale > 0.f) {
        // World coordinates in double: the render-space point plus the rebasing origin. The
        // small scale-relative bias keeps points lying exactly on a cell face (a floor at y = 0)
        // on one side, as POV-Ray's checker does.
        const DVec3 w = (DVec3(si.p) + scene_.renderOrigin) * (1.0 / double(m.checkerScale)) + DVec3(1e-4);
        // floor by truncation: baseline x86-64 has no roundsd, and libm's floor is a call.
        auto fl = [](double v) -> long long {
            if (!(std::abs(v) < 1e18)) return 0;  // beyond long long (or NaN): no meaningful cell
            const long long i = static_cast<long long>(v);
            return i - (static_cast<double>(i) > v);
        };
        const long long cell = fl(w.x) + fl(w.y) + fl(w.z);
        c = (cell & 1) ? m.color2 : m.color;
    }
    if (m.baseColorTexture >= 0) {
        const Vec2 uv = applyTextureTransform(m.baseColorTransform, m.baseColorTransform.texCoord == 1 ? si.uv1 : si.uv);
        const Vec4 t = sampleTexture(scene_.textures[m.baseColorTexture], uv);
        c *= Color(t);
        alpha *= t.a;
    }
    if (alphaOut) *alphaOut = alpha;
    return c;
}

Color WhittedTracer::shade(const SurfaceInteraction& si, const Vec3& d, RayStats& stats, const Color& weight) const {
    const Material& m = scene_.materials[si.material];
    const Vec3 V = -d;
    const Color base = baseColor(si);
    Vec3 ng = si.ng, ns = si.ns;
    float side = 1.f;
    if (glm::dot(ng, V) < 0.f) {  // seen from behind: light the side the viewer sees
        ng = -ng;
        ns = -ns;
        side = -1.f;
    }
    if (m.normalTexture >= 0 && si.tangent != Vec4(0.f)) {
        const Vec2 uv = applyTextureTransform(m.normalTransform, m.normalTransform.texCoord == 1 ? si.uv1 : si.uv);
        Vec3 tn = Vec3(sampleTexture(scene_.textures[m.normalTexture], uv)) * 2.f - 1.f;
        tn.x *= m.normalScale;
        tn.y *= m.normalScale;
        Vec3 t = Vec3(si.tangent) - ns * glm::dot(ns, Vec3(si.tangent));
        const float tl = glm::length(t);
        if (tl > 0.f) {
            t /= tl;
            const Vec3 b = glm::cross(ns, t) * (si.tangent.w < 0.f ? -1.f : 1.f);
            const Vec3 n = t * tn.x + b * tn.y + ns * tn.z;
            const float nl = glm::length(n);
            if (nl > 0.f && std::isfinite(nl)) ns = n / nl;
        }
    }
    // An interpolated normal turned away from the viewer on a visible face would draw a black
    // contour: fall back on the geometric normal.
    if (glm::dot(ns, V) <= 0.f) ns = ng;

    Color c = m.emission + scene_.ambientLight * m.ambient * base;
    if (m.diffuse <= 0.f && m.specular <= 0.f) return c;
    bool terminatorDone = false;
    Vec3 shadowBase = si.p;
    float pruned = 0.f;  // worth of the lights left out so far
    for (const Light& L : scene_.lights) {
        Vec3 Ldir;
        float dist = kInf;
        float att = 1.f;
        float nl;
        if (L.type == LightType::Directional) {
            Ldir = -L.direction;
            nl = glm::dot(ns, Ldir);
        } else {
            // Both early outs read squared or unnormalised values, so neither waits for the
            // square root and the division (a dependent chain of ~30 cycles).
            const Vec3 toL = L.position - si.p;
            const float dist2 = glm::dot(toL, toL);
            const float nlRaw = glm::dot(ns, toL);
            if (!(dist2 > 0.f) || nlRaw <= 0.f) continue;
            dist = std::sqrt(dist2);
            const float invDist = 1.f / dist;
            Ldir = toL * invDist;
            nl = nlRaw * invDist;
            att = attenuationFactor(L.attenuation, dist);
            if (L.range > 0.f) {
                const float r = dist / L.range;
                const float w = std::clamp(1.f - r * r * r * r, 0.f, 1.f);
                att *= w * w;
            }
            if (L.type == LightType::Spot) att *= spotFactor(L, -Ldir);
        }
        if (!(nl > 0.f) || att <= 0.f) continue;
        // The light is behind the flat facet but in front of the smooth (interpolated) surface:
        // Hanika's shadow-terminator case. Lit only if a shadow ray from the shifted point,
        // leaving on the viewer's side of the facet, clears the facet and its neighbours.
        const bool behindFacet = glm::dot(ng, Ldir) <= 0.f;
        if (behindFacet && (si.mesh < 0 || !L.castShadows)) continue;
        float spec = 0.f;
        if (m.specular > 0.f) {
            const float x = settings_.shading == ShadingModel::BlinnPhong
                                ? glm::dot(ns, glm::normalize(Ldir + V))
                                : glm::dot(reflect(-Ldir, ns), V);
            // x^n below 2^-40 cannot show: skip pow (and its slow underflow path) there.
            if (x > specFloor_[si.material]) spec = m.specular * std::pow(x, m.shininess);
        }
        const Color term = att * L.intensity * L.color * (m.diffuse * nl * base + Color(spec));
        // The seed's pruning rule applied to the shadow ray: a light whose whole unshadowed term
        // would reach the pixel below the weight threshold is left out with its ray, as long as
        // all lights left out at this point stay below it together (many dim lights add up).
        const float worth = maxComponent(weight * term);
        if (pruned + worth <= settings_.minWeight) {
            pruned += worth;
            continue;
        }
        if (L.castShadows) {
            if (!terminatorDone) {
                shadowBase = terminatorSafeOrigin(scene_, si, side);
                terminatorDone = true;
            }
            const uint32_t skip = scene_.skipFor(si, Ldir);
            Ray sr;
            sr.o = spawnOrigin(shadowBase, si, ng, behindFacet ? ng : Ldir, skip);
            sr.d = Ldir;
            // Shorten the far end relatively, so a light lying on a surface still lights it. An
            // origin still at si.p (no offset) already has its distance.
            const float tMax = std::isinf(dist) ? kInf
                                                : (sr.o == si.p ? dist : glm::length(L.position - sr.o)) * (1.f - 1e-4f);
            ++stats.shadow;
            if (scene_.occluded(sr, tMax, skip)) continue;
        }
        c += term;
    }
    return c;
}

Color WhittedTracer::tracePrimary(const Ray& r, RayStats& stats, bool* hit) const {
    ++stats.primary;
    if (!hit && !scene_.transparentBackground) return trace(r, 1, Color(1.f), stats);
    Hit h;
    const bool met = scene_.intersect(r, h);
    if (hit) *hit = met;
    if (!met) return scene_.transparentBackground ? Color(0.f) : scene_.background;
    return traceHit(r, h, 1, Color(1.f), stats);
}

Color WhittedTracer::trace(const Ray& r, int depth, const Color& weight, RayStats& stats, uint32_t skip) const {
    Hit hit;
    if (!scene_.intersect(r, hit, skip)) return scene_.background;
    return traceHit(r, hit, depth, weight, stats);
}

Color WhittedTracer::traceHit(const Ray& r, const Hit& hit, int depth, const Color& weight, RayStats& stats) const {
    const SurfaceInteraction si = scene_.interaction(r, hit);
    Color c = shade(si, r.d, stats, weight);
    if (depth >= settings_.maxDepth) return c;

    const Material& m = scene_.materials[si.material];
    float kr = m.reflection;
    float kt = 0.f;
    Vec3 ng = si.ng;
    const bool entering = glm::dot(r.d, ng) < 0.f;
    if (!entering) ng = -ng;  // ng now faces the incoming ray
    Vec3 refrDir(0.f);
    if (m.transmission > 0.f) {
        const float etaI = entering ? 1.f : m.ior, etaT = entering ? m.ior : 1.f;
        const float F = fresnelDielectric(-glm::dot(r.d, ng), etaT / etaI);
        kr += m.transmission * F;
        if (F < 1.f && refract(r.d, ng, etaI / etaT, refrDir)) kt = m.transmission * (1.f - F);
    }
    if (kr > 0.f) {
        const Color w = weight * kr;
        if (maxComponent(w) > settings_.minWeight) {
            Vec3 ns = si.ns;
            if (glm::dot(ns, ng) < 0.f) ns = -ns;
            Vec3 dir = reflect(r.d, ns);
            if (glm::dot(dir, ng) <= 0.f) dir = reflect(r.d, ng);  // below the surface: use ng
            const uint32_t skip = scene_.skipFor(si, dir);
            Ray rr;
            rr.o = spawnOrigin(si.p, si, ng, dir, skip);
            rr.d = dir;
            ++stats.reflection;
            c += kr * trace(rr, depth + 1, w, stats, skip);
        }
    }
    if (kt > 0.f) {
        const Color filter = baseColor(si);
        const Color w = weight * kt * filter;
        if (maxComponent(w) > settings_.minWeight) {
            const uint32_t skip = scene_.skipFor(si, refrDir);
            Ray tr;
            tr.o = spawnOrigin(si.p, si, ng, refrDir, skip);
            tr.d = refrDir;
            ++stats.refraction;
            c += kt * filter * trace(tr, depth + 1, w, stats, skip);
        }
    }
    return c;
}

}  // namespace rf
