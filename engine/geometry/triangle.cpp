#include "engine/geometry/triangle.h"

#include <algorithm>

namespace rf {

bool intersectTriangleClassic(const Ray& r, const Vec3& p0, const Vec3& p1, const Vec3& p2, float tMax,
                              TriangleHit& hit) {
    const Vec3 nRaw = glm::cross(p1 - p0, p2 - p0);
    const float len = glm::length(nRaw);
    if (!(len > 0.f)) return false;
    const Vec3 n = nRaw / len;
    const float denom = glm::dot(n, r.d);
    if (denom == 0.f) return false;
    const float t = glm::dot(n, p0 - r.o) / denom;
    if (!(t > 0.f && t < tMax)) return false;
    const Vec3 x = r.o + t * r.d;
    const float e0 = glm::dot(glm::cross(p1 - p0, x - p0), n);
    const float e1 = glm::dot(glm::cross(p2 - p1, x - p1), n);
    const float e2 = glm::dot(glm::cross(p0 - p2, x - p2), n);
    if (e0 < 0.f || e1 < 0.f || e2 < 0.f) return false;
    hit.t = t;
    hit.b0 = e1 / len;
    hit.b1 = e2 / len;
    hit.b2 = e0 / len;
    return true;
}

bool intersectTriangleMT(const Ray& r, const Vec3& p0, const Vec3& p1, const Vec3& p2, float tMax,
                         TriangleHit& hit) {
    const Vec3 e1 = p1 - p0, e2 = p2 - p0;
    const Vec3 h = glm::cross(r.d, e2);
    const float a = glm::dot(e1, h);
    if (a == 0.f || !std::isfinite(a)) return false;  // ray parallel to the triangle's plane
    const float f = 1.f / a;
    const Vec3 s = r.o - p0;
    const float u = f * glm::dot(s, h);
    if (u < 0.f || u > 1.f) return false;
    const Vec3 q = glm::cross(s, e1);
    const float v = f * glm::dot(r.d, q);
    if (v < 0.f || u + v > 1.f) return false;
    const float t = f * glm::dot(e2, q);
    if (!(t > 0.f && t < tMax)) return false;
    hit.t = t;
    hit.b0 = 1.f - u - v;
    hit.b1 = u;
    hit.b2 = v;
    return true;
}

WatertightRay::WatertightRay(const Ray& r) : o(r.o) {
    const Vec3 ad = absComponents(r.d);
    kz = (ad.x > ad.y) ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (r.d[kz] < 0.f) std::swap(kx, ky);  // keep the winding
    sx = r.d[kx] / r.d[kz];
    sy = r.d[ky] / r.d[kz];
    sz = 1.f / r.d[kz];
}

bool intersectTriangleWatertight(const WatertightRay& wr, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                                 float tMax, TriangleHit& hit) {
    const Vec3 A = p0 - wr.o, B = p1 - wr.o, C = p2 - wr.o;
    const float ax = A[wr.kx] - wr.sx * A[wr.kz], ay = A[wr.ky] - wr.sy * A[wr.kz];
    const float bx = B[wr.kx] - wr.sx * B[wr.kz], by = B[wr.ky] - wr.sy * B[wr.kz];
    const float cx = C[wr.kx] - wr.sx * C[wr.kz], cy = C[wr.ky] - wr.sy * C[wr.kz];
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if (u == 0.f || v == 0.f || w == 0.f) {
        // Exactly on an edge in float: decide in double so neighbours agree (the paper's fallback).
        u = static_cast<float>(double(cx) * by - double(cy) * bx);
        v = static_cast<float>(double(ax) * cy - double(ay) * cx);
        w = static_cast<float>(double(bx) * ay - double(by) * ax);
    }
    if ((u < 0.f || v < 0.f || w < 0.f) && (u > 0.f || v > 0.f || w > 0.f)) return false;
    const float det = u + v + w;
    if (det == 0.f || !std::isfinite(det)) return false;
    const float az = wr.sz * A[wr.kz], bz = wr.sz * B[wr.kz], cz = wr.sz * C[wr.kz];
    const float T = u * az + v * bz + w * cz;
    if (det < 0.f ? (T >= 0.f || T < tMax * det) : (T <= 0.f || T > tMax * det)) return false;
    const float inv = 1.f / det;
    const float t = T * inv;
    if (!(t < tMax)) return false;
    // t is a weighted mean of the vertices' sheared z (the edge functions, all of one sign, are
    // the weights), so a triangle whose vertices all lie certainly ahead of the origin is hit
    // ahead, however the edge functions rounded. Otherwise (a ray leaving a surface, near its own
    // triangle and its neighbours) t carries the rounding of the shear and the edge functions: a
    // t that cannot be told from 0 by its error bound is the surface the ray starts on, never a
    // hit. The bound follows the operations above (the analysis in pbrt-v4's triangle test).
    const float maxZ = std::max({std::abs(az), std::abs(bz), std::abs(cz)});
    if (!(std::min({az, bz, cz}) > gamma(3) * maxZ)) {
        const float maxX = std::max({std::abs(ax), std::abs(bx), std::abs(cx)});
        const float maxY = std::max({std::abs(ay), std::abs(by), std::abs(cy)});
        const float deltaX = gamma(5) * (maxX + maxZ), deltaY = gamma(5) * (maxY + maxZ), deltaZ = gamma(3) * maxZ;
        const float deltaE = 2.f * (gamma(2) * maxX * maxY + deltaY * maxX + deltaX * maxY);
        const float maxE = std::max({std::abs(u), std::abs(v), std::abs(w)});
        const float deltaT = 3.f * (gamma(3) * maxE * maxZ + deltaE * maxZ + deltaZ * maxE) * std::abs(inv);
        if (!(t > deltaT)) return false;
    }
    hit.t = t;
    hit.b0 = u * inv;
    hit.b1 = v * inv;
    hit.b2 = w * inv;
    return t > 0.f;
}

}  // namespace rf
