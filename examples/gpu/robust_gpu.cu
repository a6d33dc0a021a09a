// robust_sphere.h and the textbook quadratic on a GPU, over the cases that
// `rayverify corpus export` writes as .npy, with results files rayverify
// audits like any built-in variant (docs/robust_sphere.md, "On a GPU").
//
//   rayverify corpus export --precision float -o cases.npy      # and cases.json
//   nvcc -O3 -std=c++20 -I src/intersectors examples/gpu/robust_gpu.cu -o robust_gpu
//   ./robust_gpu cases.npy out                                  # out/naive.npy, robust.npy, … with .json
//   rayverify audit --results out/robust.npy --contract query=line_roots,reports_tangent=yes --name gpu_robust
//
// Built with nvcc's defaults (-fmad=true: a·b + c fused where the compiler
// likes), as a renderer's kernels are. The program answers in the cases'
// precision (float32 or float64 .npy) and writes, per intersector, an (n, 3)
// array count, t0, t1 and its companion .json (the cases' fingerprint and
// ids, which it copies from cases.json).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "robust_sphere.h"

namespace rs = robust_sphere;

namespace {

// The textbook quadratic (rayverify's `naive`): b = 2 d·f, C = f·f − r²,
// Δ = b² − 4aC, t = (−b ∓ √Δ)/2a.
template <class T>
__device__ void naive(const T* x, T* out) {
    const T fx = x[0] - x[6], fy = x[1] - x[7], fz = x[2] - x[8];
    const T a = x[3] * x[3] + x[4] * x[4] + x[5] * x[5];
    const T b = T(2) * (x[3] * fx + x[4] * fy + x[5] * fz);
    const T C = fx * fx + fy * fy + fz * fz - x[9] * x[9];
    const T disc = b * b - T(4) * a * C;
    out[0] = 0, out[1] = out[2] = 0;
    if (disc < 0) return;
    if (disc == 0) {
        out[0] = 1, out[1] = out[2] = -b / (T(2) * a);
        return;
    }
    const T s = sqrt(disc);
    out[0] = 2, out[1] = (-b - s) / (T(2) * a), out[2] = (-b + s) / (T(2) * a);
}

enum class query { naive, robust, robust_nearest, robust_any_hit, robust_bounded };

template <class T>
__global__ void answer(query q, const T* cases, T* answers, int n) {
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const T* x = cases + 12 * i;
    T* out = answers + 3 * i;
    const rs::ray<T> ray{{x[0], x[1], x[2]}, {x[3], x[4], x[5]}};
    const rs::sphere<T> ball{{x[6], x[7], x[8]}, x[9]};
    // A case without an interval has NaN ends: the ray's (0, +inf).
    const T tmin = x[10] == x[10] ? x[10] : T(0), tmax = x[11] == x[11] ? x[11] : T(INFINITY);
    switch (q) {
        case query::naive: naive(x, out); break;
        case query::robust:
        case query::robust_bounded: {
            const rs::line_roots<T> l = q == query::robust ? rs::intersect_line(ray, ball)
                                                           : rs::intersect_line<rs::roots::bounded>(ray, ball);
            out[0] = T(l.count), out[1] = l.t0, out[2] = l.t1;
            break;
        }
        case query::robust_nearest: {
            const rs::ray_hit<T> h = rs::nearest_hit(ray, ball, tmin, tmax);
            out[0] = h.found ? 1 : 0, out[1] = out[2] = h.found ? h.t : T(0);
            break;
        }
        case query::robust_any_hit: {
            out[0] = rs::any_hit(ray, ball, tmin, tmax) ? 1 : 0, out[1] = out[2] = 0;
            break;
        }
    }
}

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "robust_gpu: %s\n", what.c_str());
    std::exit(2);
}

void check(cudaError_t e, const char* what) {
    if (e != cudaSuccess) fail(std::string(what) + ": " + cudaGetErrorString(e));
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot read " + path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A .npy of version 1: magic, version, header length (bytes 8–9), header, data.
struct npy {
    std::string descr;  // "<f4" or "<f8"
    std::size_t rows = 0, columns = 0;
    std::string data;
};

npy read_npy(const std::string& path) {
    const std::string bytes = read_file(path);
    if (bytes.size() < 10 || bytes.compare(0, 6, "\x93NUMPY") != 0) fail(path + ": not a .npy file");
    const std::size_t header_length = static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
    const std::string header = bytes.substr(10, header_length);
    npy a;
    const std::size_t d = header.find("'descr': '");
    const std::size_t s = header.find("'shape': (");
    if (d == std::string::npos || s == std::string::npos) fail(path + ": no descr or shape in the header");
    a.descr = header.substr(d + 10, 3);
    if (std::sscanf(header.c_str() + s + 10, "%zu, %zu", &a.rows, &a.columns) != 2 || a.columns != 12)
        fail(path + ": expected an (n, 12) array");
    a.data = bytes.substr(10 + header_length);
    const std::size_t size = a.descr == "<f4" ? 4 : (a.descr == "<f8" ? 8 : 0);
    if (size == 0) fail(path + ": expected float32 or float64, not " + a.descr);
    if (a.data.size() != a.rows * a.columns * size) fail(path + ": data size does not match the shape");
    return a;
}

void write_npy(const std::string& path, const std::string& descr, std::size_t rows, const void* data, std::size_t bytes) {
    std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", 3), }";
    while ((10 + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    std::string out = "\x93NUMPY";
    out += '\x01', out += '\x00';
    out += static_cast<char>(header.size() & 0xff), out += static_cast<char>(header.size() >> 8);
    out += header;
    out.append(static_cast<const char*>(data), bytes);
    std::ofstream(path, std::ios::binary) << out;
}

// The part of cases.json after `"key":` up to the matching end (a string or an array), verbatim.
std::string json_member(const std::string& json, const std::string& key) {
    const std::size_t k = json.find("\"" + key + "\":");
    if (k == std::string::npos) fail("cases.json has no " + key);
    std::size_t begin = k + key.size() + 3;
    const char open = json[begin];
    std::size_t end = begin + 1;
    if (open == '"') {
        end = json.find('"', end) + 1;
    } else if (open == '[') {
        for (bool quoted = false; end < json.size() && (quoted || json[end] != ']'); ++end) {
            if (json[end] == '\\') ++end;
            else if (json[end] == '"') quoted = !quoted;
        }
        ++end;
    }
    return json.substr(begin, end - begin);
}

template <class T>
void run(const npy& cases, const std::string& meta, const std::string& directory) {
    const int n = static_cast<int>(cases.rows);
    T *device_cases = nullptr, *device_answers = nullptr;
    check(cudaMalloc(&device_cases, cases.data.size()), "cudaMalloc");
    check(cudaMalloc(&device_answers, std::size_t(n) * 3 * sizeof(T)), "cudaMalloc");
    check(cudaMemcpy(device_cases, cases.data.data(), cases.data.size(), cudaMemcpyHostToDevice), "cudaMemcpy");
    const char* precision = sizeof(T) == 4 ? "float" : "double";
    const struct {
        query q;
        const char* name;
    } runs[] = {{query::naive, "naive"},
                {query::robust, "robust"},
                {query::robust_nearest, "robust_nearest"},
                {query::robust_any_hit, "robust_any_hit"},
                {query::robust_bounded, "robust_bounded"}};
    std::vector<T> answers(std::size_t(n) * 3);
    for (const auto& r : runs) {
        answer<T><<<(n + 127) / 128, 128>>>(r.q, device_cases, device_answers, n);
        check(cudaGetLastError(), "kernel launch");
        check(cudaMemcpy(answers.data(), device_answers, answers.size() * sizeof(T), cudaMemcpyDeviceToHost),
              "cudaMemcpy");
        const std::string stem = directory + "/" + r.name;
        write_npy(stem + ".npy", cases.descr, cases.rows, answers.data(), answers.size() * sizeof(T));
        std::ofstream(stem + ".json") << "{\"rayverify\":\"results\",\"version\":1,\"precision\":\"" << precision
                                      << "\",\"fingerprint\":" << json_member(meta, "fingerprint")
                                      << ",\"columns\":[\"count\",\"t0\",\"t1\"],\"ids\":" << json_member(meta, "ids")
                                      << "}\n";
        std::printf("wrote %s.npy and %s.json (%d answers, %s)\n", stem.c_str(), stem.c_str(), n, precision);
    }
    cudaFree(device_cases);
    cudaFree(device_answers);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) fail("usage: robust_gpu CASES.npy OUT_DIRECTORY (CASES.json beside the .npy)");
    const std::string cases_path = argv[1];
    const npy cases = read_npy(cases_path);
    const std::string meta = read_file(cases_path.substr(0, cases_path.size() - 4) + ".json");
    cudaDeviceProp device{};
    check(cudaGetDeviceProperties(&device, 0), "cudaGetDeviceProperties");
    int runtime = 0;
    cudaRuntimeGetVersion(&runtime);
    std::printf("device: %s (sm_%d%d), CUDA runtime %d, nvcc %d.%d\n", device.name, device.major, device.minor, runtime,
                __CUDACC_VER_MAJOR__, __CUDACC_VER_MINOR__);
    if (cases.descr == "<f4")
        run<float>(cases, meta, argv[2]);
    else
        run<double>(cases, meta, argv[2]);
    return 0;
}
