// Minimal 3-vector for the floating-point intersectors.
//
// Arithmetic is written out component by component in a fixed order so that
// every intersector evaluates exactly the expression it cites (no hidden FMA,
// no reassociation; the project builds with -ffp-contract=off).
#pragma once

namespace rayverify {

template <class T>
struct vec3 {
    T x{}, y{}, z{};

    friend constexpr vec3 operator+(vec3 a, vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend constexpr vec3 operator-(vec3 a, vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend constexpr vec3 operator*(T s, vec3 v) { return {s * v.x, s * v.y, s * v.z}; }
    friend constexpr bool operator==(const vec3&, const vec3&) = default;

    constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

// (x·x + y·y) + z·z, left to right, as D3DXVec3Dot, GLM and pbrt evaluate it.
template <class T>
constexpr T dot(vec3<T> a, vec3<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <class T>
constexpr T length_squared(vec3<T> v) {
    return dot(v, v);
}

template <class To, class From>
constexpr vec3<To> vec3_cast(vec3<From> v) {
    return {static_cast<To>(v.x), static_cast<To>(v.y), static_cast<To>(v.z)};
}

}  // namespace rayverify
