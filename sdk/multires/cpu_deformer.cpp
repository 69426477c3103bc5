// SPDX-License-Identifier: GPL-3.0-or-later
#include "multires/cpu_deformer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/parallel_for.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// GCC function multiversioning: an AVX2+FMA clone of the block kernels next to the baseline
// x86-64 (SSE2) one, picked once at load time by the CPU (ifunc). Elsewhere: one plain version.
// Not under ThreadSanitizer: the ifunc resolvers run during relocation, before the TSan runtime
// is initialised, and the instrumented resolver crashes the process at load time.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(__SANITIZE_THREAD__)
#define CAGEKIT_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CAGEKIT_KERNEL_CLONES
#endif

constexpr size_t kBlock = 64;  // vertices evaluated at once (the float outputs stay in L1)

// One cell's polynomial, relative to its corner S(0, 0): coefficient of s^a t^b at a + 4 b.
struct CellPolynomial {
  float x[16], y[16], z[16];
};

struct BlockIn {
  const float *s, *t, *d, *k[6], *ta, *tb;
};

struct BlockOut {
  float px[kBlock], py[kBlock], pz[kBlock], nx[kBlock], ny[kBlock], nz[kBlock];
};

// p(s, t), dp/ds, dp/dt of one coordinate (Horner in s per power of t, then in t).
#define CAGEKIT_BICUBIC(C, v, vs, vt)                                                          \
  {                                                                                            \
    const float r0 = ((C[3] * s + C[2]) * s + C[1]) * s + C[0];                                \
    const float r1 = ((C[7] * s + C[6]) * s + C[5]) * s + C[4];                                \
    const float r2 = ((C[11] * s + C[10]) * s + C[9]) * s + C[8];                              \
    const float r3 = ((C[15] * s + C[14]) * s + C[13]) * s + C[12];                            \
    const float q0 = (3.0f * C[3] * s + 2.0f * C[2]) * s + C[1];                               \
    const float q1 = (3.0f * C[7] * s + 2.0f * C[6]) * s + C[5];                               \
    const float q2 = (3.0f * C[11] * s + 2.0f * C[10]) * s + C[9];                             \
    const float q3 = (3.0f * C[15] * s + 2.0f * C[14]) * s + C[13];                            \
    v = ((r3 * t + r2) * t + r1) * t + r0;                                                     \
    vt = (3.0f * r3 * t + 2.0f * r2) * t + r1;                                                 \
    vs = ((q3 * t + q2) * t + q1) * t + q0;                                                    \
  }

template <bool kLocal>
inline __attribute__((always_inline)) void block_kernel(const CellPolynomial& poly, const BlockIn& in, size_t n,
                                                        BlockOut& out) {
  // Local copies: the compiler then knows the outputs do not alias the coefficients.
  float cx[16], cy[16], cz[16];
  std::memcpy(cx, poly.x, sizeof cx), std::memcpy(cy, poly.y, sizeof cy), std::memcpy(cz, poly.z, sizeof cz);
  const float* __restrict S = in.s;
  const float* __restrict T = in.t;
  const float* __restrict D = in.d;
  const float* __restrict K0 = in.k[0];
  const float* __restrict K1 = in.k[1];
  const float* __restrict K2 = in.k[2];
  const float* __restrict K3 = in.k[3];
  const float* __restrict K4 = in.k[4];
  const float* __restrict K5 = in.k[5];
  const float* __restrict TA = in.ta;
  const float* __restrict TB = in.tb;
  float* __restrict PX = out.px;
  float* __restrict PY = out.py;
  float* __restrict PZ = out.pz;
  float* __restrict NX = out.nx;
  float* __restrict NY = out.ny;
  float* __restrict NZ = out.nz;
  // Whole groups of 8 lanes (the inner loop has a constant trip count, so it becomes one AVX2
  // or two SSE vectors without scalar peeling); the lanes past n read the next cell's data
  // (the table's arrays are padded at the end) and are never written out.
  for (size_t g = 0; g < (n + 7) / 8; ++g)
#pragma GCC unroll 8
  for (size_t l = 0; l < 8; ++l) {
    const size_t i = 8 * g + l;
    const float s = S[i], t = T[i];
    float x, xs, xt, y, ys, yt, z, zs, zt;
    CAGEKIT_BICUBIC(cx, x, xs, xt)
    CAGEKIT_BICUBIC(cy, y, ys, yt)
    CAGEKIT_BICUBIC(cz, z, zs, zt)
    // N_S = normalize(S_s x S_t) ((0, 0, 1) where the derivatives are parallel, as the reference).
    const float crx = ys * zt - zs * yt, cry = zs * xt - xs * zt, crz = xs * yt - ys * xt;
    const float l2 = crx * crx + cry * cry + crz * crz;
    const float inv = 1.0f / std::sqrt(std::max(l2, 1e-30f));
    const bool ok = l2 > 0.0f;
    const float nsx = ok ? crx * inv : 0.0f, nsy = ok ? cry * inv : 0.0f, nsz = ok ? crz * inv : 1.0f;
    const float d = D[i];
    float px = x + d * nsx, py = y + d * nsy, pz = z + d * nsz;
    if (kLocal) {
      // T1 = S_s / |S_s| (= S_u / |S_u|), T2 = N_S x T1.
      const float li = 1.0f / std::sqrt(std::max(xs * xs + ys * ys + zs * zs, 1e-30f));
      const float t1x = xs * li, t1y = ys * li, t1z = zs * li;
      const float t2x = nsy * t1z - nsz * t1y, t2y = nsz * t1x - nsx * t1z, t2z = nsx * t1y - nsy * t1x;
      const float a = TA[i], b = TB[i];
      px += a * t1x + b * t2x, py += a * t1y + b * t2y, pz += a * t1z + b * t2z;
    }
    PX[i] = px, PY[i] = py, PZ[i] = pz;
    // G_u = k0 S_s + k1 S_t + k2 N_S, G_v = k3 S_s + k4 S_t + k5 N_S (k0, k1, k3, k4 prescaled).
    const float gux = K0[i] * xs + K1[i] * xt + K2[i] * nsx, guy = K0[i] * ys + K1[i] * yt + K2[i] * nsy,
                guz = K0[i] * zs + K1[i] * zt + K2[i] * nsz;
    const float gvx = K3[i] * xs + K4[i] * xt + K5[i] * nsx, gvy = K3[i] * ys + K4[i] * yt + K5[i] * nsy,
                gvz = K3[i] * zs + K4[i] * zt + K5[i] * nsz;
    const float mx = guy * gvz - guz * gvy, my = guz * gvx - gux * gvz, mz = gux * gvy - guy * gvx;
    const float m2 = mx * mx + my * my + mz * mz;
    const float minv = m2 > 0.0f ? 1.0f / std::sqrt(std::max(m2, 1e-30f)) : 0.0f;
    NX[i] = mx * minv, NY[i] = my * minv, NZ[i] = mz * minv;
  }
}

// Where the cells' vertices go: straight into the caller's arrays (Vec3, or double / float xyz),
// whose vertex order is not the cells' (scattered stores: the next cell's output lines are
// prefetched for writing while this one is evaluated).


// The caller's arrays: Vec3, or xyz triples of double or float.
inline void put(Vec3* a, size_t i, double x, double y, double z) { a[i] = Vec3{x, y, z}; }
template <typename S>
inline void put(S* a, size_t i, double x, double y, double z) {
  a[3 * i] = S(x), a[3 * i + 1] = S(y), a[3 * i + 2] = S(z);
}
inline const void* address(const Vec3* a, size_t i) { return a + i; }
template <typename S>
inline const void* address(const S* a, size_t i) { return a + 3 * i; }

// Copies `bytes` to `to` with streaming (non-temporal) stores for the whole 64-byte lines and
// plain stores for the partial lines at both ends: a written line is not first read for
// ownership (half of the traffic of the outputs). Callers end their writes with stream_fence().
inline void stream_copy(void* to, const void* from, size_t bytes) {
  char* d = static_cast<char*>(to);
  const char* f = static_cast<const char*>(from);
#if defined(__SSE2__)
  const size_t head = std::min(bytes, size_t((64 - reinterpret_cast<uintptr_t>(d) % 64) % 64));
  std::memcpy(d, f, head);
  d += head, f += head, bytes -= head;
  for (; bytes >= 64; d += 64, f += 64, bytes -= 64)
    for (int q = 0; q < 4; ++q)
      _mm_stream_si128(reinterpret_cast<__m128i*>(d) + q, _mm_loadu_si128(reinterpret_cast<const __m128i*>(f) + q));
#endif
  std::memcpy(d, f, bytes);
}
inline void stream_fence() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

// Where the cells' vertices go. A cell whose vertices are consecutive scan vertices (all of them
// in a scan numbered in the deformer's order, deformer_vertex_order.h) is staged: runs of
// consecutive vertices (up to kRun) are collected in the caller's layout and copied out with
// streaming stores. Other cells are scattered (their next cells' lines prefetched for writing).
template <typename T>
struct ScatterSink {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "the staged runs copy Vec3 arrays as xyz doubles");
  using Scalar = typename std::conditional<std::is_same<T, Vec3>::value, double, T>::type;
  static constexpr size_t kRun = 256;
  T *positions, *normals;
  const uint8_t* contiguous;  // per cell: 1 when its vertices are v0, v0 + 1, ...
  size_t run_begin = 0, run_size = 0;
  alignas(64) Scalar run_p[3 * kRun], run_n[3 * kRun];

  inline __attribute__((always_inline)) void block(uint32_t cell, const Vec3& origin, uint32_t, const uint32_t* vertex,
                                                   size_t n, const BlockOut& out) {
    if (contiguous[cell]) {
      const size_t v0 = vertex[0];
      if (run_size && (v0 != run_begin + run_size || run_size + n > kRun)) flush();
      if (!run_size) run_begin = v0;
      Scalar* p = run_p + 3 * run_size;
      Scalar* q = run_n + 3 * run_size;
      for (size_t i = 0; i < n; ++i) {
        p[3 * i] = Scalar(origin.x + out.px[i]), p[3 * i + 1] = Scalar(origin.y + out.py[i]);
        p[3 * i + 2] = Scalar(origin.z + out.pz[i]);
        q[3 * i] = Scalar(out.nx[i]), q[3 * i + 1] = Scalar(out.ny[i]), q[3 * i + 2] = Scalar(out.nz[i]);
      }
      run_size += n;
      return;
    }
    if (positions)
      for (size_t i = 0; i < n; ++i) put(positions, vertex[i], origin.x + out.px[i], origin.y + out.py[i], origin.z + out.pz[i]);
    if (normals)
      for (size_t i = 0; i < n; ++i) put(normals, vertex[i], out.nx[i], out.ny[i], out.nz[i]);
  }
  void flush() {
    if (!run_size) return;
    const size_t bytes = 3 * run_size * sizeof(Scalar);
    if (positions) stream_copy(const_cast<void*>(address(positions, run_begin)), run_p, bytes);
    if (normals) stream_copy(const_cast<void*>(address(normals, run_begin)), run_n, bytes);
    run_size = 0;
  }
  // After the last cell: the staged run, and the streaming stores ordered before the caller's.
  void finish() {
    flush();
    stream_fence();
  }
  // The next cells' output lines, for writing (their read-for-ownership overlaps this cell's
  // work): both ends of each element (an element may straddle two lines).
  void prefetch(uint32_t cell, const uint32_t* vertex, uint32_t first, uint32_t last) {
    if (contiguous[cell]) return;  // sequential stores: the hardware prefetcher follows them
    constexpr size_t kBytes = std::is_same<T, Vec3>::value ? sizeof(Vec3) : 3 * sizeof(T);
    for (uint32_t i = first; i < last; ++i) {
      if (positions) {
        const char* p = static_cast<const char*>(address(positions, vertex[i]));
        __builtin_prefetch(p, 1), __builtin_prefetch(p + kBytes - 1, 1);
      }
      if (normals) {
        const char* p = static_cast<const char*>(address(normals, vertex[i]));
        __builtin_prefetch(p, 1), __builtin_prefetch(p + kBytes - 1, 1);
      }
    }
  }
};

// Evaluates cells[begin, end): per cell the coefficients from the control points, then its
// vertices in blocks, handed to `sink` (one function per clone and sink, so that the
// coefficients stay in registers and L1 across the cell's blocks).
template <bool kLocal, typename Sink>
inline __attribute__((always_inline)) void cells_kernel(const PatchDeformerTable& c, const uint32_t* cells,
                                                        size_t begin, size_t end, const Vec3* control, Sink& sink);

#define CAGEKIT_CELLS_FUNCTION(name, local, Sink)                                                       \
  CAGEKIT_KERNEL_CLONES void name(const PatchDeformerTable& c, const uint32_t* cells, size_t begin, size_t end, \
                                  const Vec3* control, Sink& sink) {                                     \
    cells_kernel<local>(c, cells, begin, end, control, sink);                                           \
  }
CAGEKIT_CELLS_FUNCTION(cells_normal_scatter, false, ScatterSink<Vec3>)
CAGEKIT_CELLS_FUNCTION(cells_local_frame_scatter, true, ScatterSink<Vec3>)
CAGEKIT_CELLS_FUNCTION(cells_normal_scatter_f64, false, ScatterSink<double>)
CAGEKIT_CELLS_FUNCTION(cells_local_frame_scatter_f64, true, ScatterSink<double>)
CAGEKIT_CELLS_FUNCTION(cells_normal_scatter_f32, false, ScatterSink<float>)
CAGEKIT_CELLS_FUNCTION(cells_local_frame_scatter_f32, true, ScatterSink<float>)
#undef CAGEKIT_CELLS_FUNCTION

inline void run_cells_with(const PatchDeformerTable& c, const uint32_t* cells, size_t begin, size_t end,
                           const Vec3* control, ScatterSink<Vec3>& sink) {
  (c.local_frame ? cells_local_frame_scatter : cells_normal_scatter)(c, cells, begin, end, control, sink);
}
inline void run_cells_with(const PatchDeformerTable& c, const uint32_t* cells, size_t begin, size_t end,
                           const Vec3* control, ScatterSink<double>& sink) {
  (c.local_frame ? cells_local_frame_scatter_f64 : cells_normal_scatter_f64)(c, cells, begin, end, control, sink);
}
inline void run_cells_with(const PatchDeformerTable& c, const uint32_t* cells, size_t begin, size_t end,
                           const Vec3* control, ScatterSink<float>& sink) {
  (c.local_frame ? cells_local_frame_scatter_f32 : cells_normal_scatter_f32)(c, cells, begin, end, control, sink);
}

// poly = sum over the cell's terms of coefficients[16 k ..] * (control[j_k] - ref): 16 floats
// per term = two 8-wide vectors per coordinate (GCC vector extensions; two SSE halves each in
// the baseline clone).
typedef float Float8 __attribute__((vector_size(32)));

inline __attribute__((always_inline)) void gather_cell(const float* coefficients, const uint32_t* controls, size_t terms,
                                       const Vec3* control, const Vec3& ref, CellPolynomial& poly) {
  Float8 x0 = {}, x1 = {}, y0 = {}, y1 = {}, z0 = {}, z1 = {};
  for (size_t k = 0; k < terms; ++k) {
    const Vec3& p = control[controls[k]];
    const float dx = float(p.x - ref.x), dy = float(p.y - ref.y), dz = float(p.z - ref.z);
    Float8 m0, m1;
    std::memcpy(&m0, coefficients + 16 * k, sizeof m0);
    std::memcpy(&m1, coefficients + 16 * k + 8, sizeof m1);
    x0 += m0 * dx, x1 += m1 * dx, y0 += m0 * dy, y1 += m1 * dy, z0 += m0 * dz, z1 += m1 * dz;
  }
  std::memcpy(poly.x, &x0, sizeof x0), std::memcpy(poly.x + 8, &x1, sizeof x1);
  std::memcpy(poly.y, &y0, sizeof y0), std::memcpy(poly.y + 8, &y1, sizeof y1);
  std::memcpy(poly.z, &z0, sizeof z0), std::memcpy(poly.z + 8, &z1, sizeof z1);
}

template <bool kLocal, typename Sink>
inline __attribute__((always_inline)) void cells_kernel(const PatchDeformerTable& c, const uint32_t* cells,
                                                        size_t begin, size_t end, const Vec3* control, Sink& sink) {
  BlockOut out;
  for (size_t k = begin; k < end; ++k) {
    const uint32_t cell = cells[k];
    // The cell's coefficients from its control points, relative to its first control point
    // (the coefficients of s^a t^b, (a, b) != (0, 0), sum to 0 over the terms, those of 1 to 1).
    const uint32_t e0 = c.cell_term_offsets[cell], e1 = c.cell_term_offsets[cell + 1];
    const Vec3 ref = e1 > e0 ? control[c.term_control[e0]] : Vec3();
    if (k + 2 < end) {  // the output lines of the cell after, for writing (their read for ownership
      const uint32_t next = cells[k + 2];  // overlaps this cell's work: the stores then hit the cache)
      sink.prefetch(next, c.vertex.data(), c.cell_vertex_offsets[next], c.cell_vertex_offsets[next + 1]);
    }
    CellPolynomial poly;
    gather_cell(c.term_coefficients.data() + 16 * size_t(e0), c.term_control.data() + e0, e1 - e0, control, ref, poly);
    // Vertices relative to S(0, 0).
    const Vec3 origin{ref.x + poly.x[0], ref.y + poly.y[0], ref.z + poly.z[0]};
    poly.x[0] = poly.y[0] = poly.z[0] = 0.0f;
    for (uint32_t first = c.cell_vertex_offsets[cell]; first < c.cell_vertex_offsets[cell + 1]; first += kBlock) {
      const size_t n = std::min<size_t>(kBlock, c.cell_vertex_offsets[cell + 1] - first);
      BlockIn in{c.s.data() + first, c.t.data() + first, c.displacement.data() + first, {}, nullptr, nullptr};
      for (int q = 0; q < 6; ++q) in.k[q] = c.k[q].data() + first;
      if (kLocal) in.ta = c.tangent_a.data() + first, in.tb = c.tangent_b.data() + first;
      block_kernel<kLocal>(poly, in, n, out);
      sink.block(cell, origin, first, c.vertex.data() + first, n, out);
    }
  }
  sink.finish();
}

// Splits `count` work items with weights `weight(i)` (summing to `total`) into `workers` ranges
// of about equal total weight: split[w], split[w + 1] bound range w.
template <typename Weight>
std::vector<size_t> balanced_split(size_t count, size_t total, size_t workers, Weight&& weight) {
  std::vector<size_t> split(workers + 1, count);
  split[0] = 0;
  size_t acc = 0, w = 1;
  for (size_t i = 0; i < count && w < workers; ++i) {
    acc += weight(i);
    if (acc * workers >= total * w) split[w++] = i + 1;
  }
  return split;
}

size_t worker_count(int threads, size_t total, size_t min_per_worker) {
  return std::max<size_t>(1, std::min<size_t>(size_t(std::max(threads, 1)), total / min_per_worker));
}

// One irregular vertex from its sparse row (double): position and/or normal.

constexpr size_t kIrregularData = 9;  // per irregular vertex: D, 6 normal coefficients, a, b

// Irregular vertices items[0, count) from their sparse rows (double), in batches: first the rows
// (S, S_u, S_v per vertex: scalar, the rows differ in length), then the frames, offsets and
// normals of the batch in a loop the compiler vectorises (2 or 4 doubles; the square roots and
// divisions of neighbouring vertices overlap instead of forming one latency chain each).
// `data`: per item D, the normal coefficients (8.11)-(8.12), the tangent offsets (a, b), copied
// from the binding in item order.
template <bool kLocal, typename T>
inline __attribute__((always_inline)) void irregular_kernel(const PatchDeformerTable& c, const double* data,
                                                            const Vec3* control, const uint32_t* items, size_t count,
                                                            T* positions, T* normals) {
  constexpr size_t kBatch = 32;
  struct Batch {
    double sx[kBatch], sy[kBatch], sz[kBatch], ux[kBatch], uy[kBatch], uz[kBatch], vx[kBatch], vy[kBatch], vz[kBatch];
    double q[kIrregularData][kBatch];
    double px[kBatch], py[kBatch], pz[kBatch], nx[kBatch], ny[kBatch], nz[kBatch];
  } b;
  for (size_t first = 0; first < count; first += kBatch) {
    const size_t m = std::min(kBatch, count - first);
    for (size_t j = 0; j < m; ++j) {
      const uint32_t item = items[first + j];
      const uint32_t e0 = c.irregular_offsets[item], e1 = c.irregular_offsets[item + 1];
      // Relative to the first control point (the weights sum to 1, their derivatives to 0).
      const Vec3 ref = e1 > e0 ? control[c.irregular_control[e0]] : Vec3();
      Vec3 s, su, sv;
      for (uint32_t e = e0; e < e1; ++e) {
        const Vec3 d = control[c.irregular_control[e]] - ref;
        s += c.irregular_w[e] * d, su += c.irregular_wu[e] * d, sv += c.irregular_wv[e] * d;
      }
      s += ref;
      b.sx[j] = s.x, b.sy[j] = s.y, b.sz[j] = s.z, b.ux[j] = su.x, b.uy[j] = su.y, b.uz[j] = su.z;
      b.vx[j] = sv.x, b.vy[j] = sv.y, b.vz[j] = sv.z;
      for (size_t q = 0; q < kIrregularData; ++q) b.q[q][j] = data[kIrregularData * item + q];
    }
    for (size_t j = 0; j < kBatch; ++j) {  // whole batch (lanes past m: garbage, not written out)
      const double sux = b.ux[j], suy = b.uy[j], suz = b.uz[j], svx = b.vx[j], svy = b.vy[j], svz = b.vz[j];
      // N_S = normalize(S_u x S_v), (0, 0, 1) where they are parallel.
      const double crx = suy * svz - suz * svy, cry = suz * svx - sux * svz, crz = sux * svy - suy * svx;
      const double cl = std::sqrt(crx * crx + cry * cry + crz * crz);
      const bool ok = cl > 0;
      const double ci = 1.0 / (ok ? cl : 1.0);
      const double nsx = ok ? crx * ci : 0.0, nsy = ok ? cry * ci : 0.0, nsz = ok ? crz * ci : 1.0;
      const double D = b.q[0][j];
      if (!kLocal) {
        b.px[j] = b.sx[j] + D * nsx, b.py[j] = b.sy[j] + D * nsy, b.pz[j] = b.sz[j] + D * nsz;
      } else {
        // T1 = S_u / |S_u|, T2 = N_S x T1; P = S + a T1 + b T2 + D N_S.
        const double ul = std::sqrt(sux * sux + suy * suy + suz * suz);
        const bool uok = ul > 0;
        const double ui = 1.0 / (uok ? ul : 1.0);
        const double t1x = uok ? sux * ui : 0.0, t1y = uok ? suy * ui : 0.0, t1z = uok ? suz * ui : 0.0;
        const double t2x = nsy * t1z - nsz * t1y, t2y = nsz * t1x - nsx * t1z, t2z = nsx * t1y - nsy * t1x;
        const double a = b.q[7][j], bb = b.q[8][j];
        b.px[j] = ((b.sx[j] + a * t1x) + bb * t2x) + D * nsx;
        b.py[j] = ((b.sy[j] + a * t1y) + bb * t2y) + D * nsy;
        b.pz[j] = ((b.sz[j] + a * t1z) + bb * t2z) + D * nsz;
      }
      // G_u = q0 S_u + q1 S_v + q2 N_S, G_v = q3 S_u + q4 S_v + q5 N_S; N = normalize(G_u x G_v).
      const double q0 = b.q[1][j], q1 = b.q[2][j], q2 = b.q[3][j], q3 = b.q[4][j], q4 = b.q[5][j], q5 = b.q[6][j];
      const double gux = (q0 * sux + q1 * svx) + q2 * nsx, guy = (q0 * suy + q1 * svy) + q2 * nsy,
                   guz = (q0 * suz + q1 * svz) + q2 * nsz;
      const double gvx = (q3 * sux + q4 * svx) + q5 * nsx, gvy = (q3 * suy + q4 * svy) + q5 * nsy,
                   gvz = (q3 * suz + q4 * svz) + q5 * nsz;
      const double mx = guy * gvz - guz * gvy, my = guz * gvx - gux * gvz, mz = gux * gvy - guy * gvx;
      const double ml = std::sqrt(mx * mx + my * my + mz * mz);
      const bool mok = ml > 0;
      const double mi = 1.0 / (mok ? ml : 1.0);
      b.nx[j] = mok ? mx * mi : 0.0, b.ny[j] = mok ? my * mi : 0.0, b.nz[j] = mok ? mz * mi : 0.0;
    }
    for (size_t j = 0; j < m; ++j) {
      const uint32_t i = c.irregular_vertex[items[first + j]];
      if (positions) put(positions, i, b.px[j], b.py[j], b.pz[j]);
      if (normals) put(normals, i, b.nx[j], b.ny[j], b.nz[j]);
    }
  }
}

#define CAGEKIT_IRREGULAR_FUNCTION(name, local, T)                                                            \
  CAGEKIT_KERNEL_CLONES void name(const PatchDeformerTable& c, const double* data, const Vec3* control,        \
                                  const uint32_t* items, size_t count, T* positions, T* normals) {             \
    irregular_kernel<local>(c, data, control, items, count, positions, normals);                              \
  }
CAGEKIT_IRREGULAR_FUNCTION(irregular_normal, false, Vec3)
CAGEKIT_IRREGULAR_FUNCTION(irregular_local_frame, true, Vec3)
CAGEKIT_IRREGULAR_FUNCTION(irregular_normal_f64, false, double)
CAGEKIT_IRREGULAR_FUNCTION(irregular_local_frame_f64, true, double)
CAGEKIT_IRREGULAR_FUNCTION(irregular_normal_f32, false, float)
CAGEKIT_IRREGULAR_FUNCTION(irregular_local_frame_f32, true, float)
#undef CAGEKIT_IRREGULAR_FUNCTION

inline void run_irregular_with(const PatchDeformerTable& c, const double* data, const Vec3* control,
                               const uint32_t* items, size_t count, Vec3* positions, Vec3* normals) {
  (c.local_frame ? irregular_local_frame : irregular_normal)(c, data, control, items, count, positions, normals);
}
inline void run_irregular_with(const PatchDeformerTable& c, const double* data, const Vec3* control,
                               const uint32_t* items, size_t count, double* positions, double* normals) {
  (c.local_frame ? irregular_local_frame_f64 : irregular_normal_f64)(c, data, control, items, count, positions, normals);
}
inline void run_irregular_with(const PatchDeformerTable& c, const double* data, const Vec3* control,
                               const uint32_t* items, size_t count, float* positions, float* normals) {
  (c.local_frame ? irregular_local_frame_f32 : irregular_normal_f32)(c, data, control, items, count, positions, normals);
}

template <typename T>
inline void store(T* to, size_t i, const Vec3& v) { put(to, i, v.x, v.y, v.z); }



}  // namespace

CpuDeformer::CpuDeformer(const ScanBinding& binding, int threads) : b_(binding), threads_(resolve_threads(threads)) {
  const PatchDeformerTable& c = b_.compact;
  if (c.empty()) return;
  const uint32_t m = b_.num_control_vertices;
  for (uint32_t j : c.term_control)
    if (j >= m) fail(Status::invalid_argument, "deformer: binding refers to a control vertex out of range");
  for (uint32_t j : c.irregular_control)
    if (j >= m) fail(Status::invalid_argument, "deformer: binding refers to a control vertex out of range");
  const size_t n = b_.num_vertices();
  for (uint32_t i : c.vertex)
    if (i >= n) fail(Status::invalid_argument, "deformer: binding refers to a vertex out of range");
  for (uint32_t i : c.irregular_vertex)
    if (i >= n) fail(Status::invalid_argument, "deformer: binding refers to a vertex out of range");
  cell_contiguous_.assign(c.num_cells(), 1);
  for (size_t cell = 0; cell < c.num_cells(); ++cell)
    for (uint32_t k = c.cell_vertex_offsets[cell] + 1; k < c.cell_vertex_offsets[cell + 1]; ++k)
      if (c.vertex[k] != c.vertex[k - 1] + 1) {
        cell_contiguous_[cell] = 0;
        break;
      }
  cell_stamp_.assign(c.num_cells(), 0);
  irregular_stamp_.assign(c.num_irregular_vertices(), 0);
  irregular_data_.assign(kIrregularData * c.num_irregular_vertices(), 0.0);
  for (size_t k = 0; k < c.num_irregular_vertices(); ++k) {
    const size_t i = c.irregular_vertex[k];
    double* to = &irregular_data_[kIrregularData * k];
    to[0] = b_.displacement[i];
    for (int q = 0; q < 6; ++q) to[1 + q] = b_.normal_coefficients[6 * i + size_t(q)];
    if (c.local_frame) to[7] = b_.tangent_offset[2 * i], to[8] = b_.tangent_offset[2 * i + 1];
  }
  // Full frames: every cell and irregular vertex, split among the workers by vertex count.
  all_cells_.resize(c.num_cells());
  for (size_t k = 0; k < all_cells_.size(); ++k) all_cells_[k] = uint32_t(k);
  all_irregular_.resize(c.num_irregular_vertices());
  for (size_t k = 0; k < all_irregular_.size(); ++k) all_irregular_[k] = uint32_t(k);
}

CpuDeformer::~CpuDeformer() = default;

SparseRowDeformer& CpuDeformer::reference() {
  if (!reference_) reference_ = std::make_unique<SparseRowDeformer>(b_, threads_);
  return *reference_;
}

const std::vector<uint32_t>& CpuDeformer::last_updated() const {
  return last_from_reference_ && reference_ ? reference_->last_updated() : touched_;
}

double deform_bytes_per_vertex(const ScanBinding& b) {
  if (!b.compact.empty()) return b.compact.bytes_per_vertex(b.num_control_vertices);
  const size_t n = b.num_vertices();
  if (n == 0) return 0;
  // Sparse rows: per entry an index and 3 doubles; per vertex row offset, D, 6 coefficients
  // (+ a, b); S, S_u, S_v kept per vertex (written) and the outputs.
  const double per_vertex = 4 + 8 * (7 + (b.mode == DisplacementMode::local_frame ? 2 : 0)) + 3 * 24 + 2 * 24;
  return per_vertex + double(b.num_entries()) * 28 / double(n);
}

double CpuDeformer::bytes_per_vertex() const { return deform_bytes_per_vertex(b_); }

void CpuDeformer::check_control(const std::vector<Vec3>& control) const {
  if (control.size() != b_.num_control_vertices)
    fail(Status::invalid_argument, "deformer: expected " + std::to_string(b_.num_control_vertices) +
                                       " control points, got " + std::to_string(control.size()));
}

// The listed cells and irregular vertices (all of them in a full frame), straight into the
// caller's arrays: one parallel region, each worker its cells (split by vertex count) and its
// share of the irregular vertices.
template <typename T>
void CpuDeformer::scatter(const uint32_t* cells, size_t cell_count, const uint32_t* items, size_t item_count,
                          T* positions, T* normals) {
  const PatchDeformerTable& c = b_.compact;
  const Vec3* control = control_.data();
  const bool full = cells == all_cells_.data() && cell_count == all_cells_.size();
  if (!full || full_split_.empty()) {  // full frames: the split is computed once
    size_t total = 0;
    for (size_t k = 0; k < cell_count; ++k) total += c.cell_vertex_offsets[cells[k] + 1] - c.cell_vertex_offsets[cells[k]];
    const size_t workers = worker_count(threads_, total + item_count, 8192);
    split_ = balanced_split(cell_count, total, workers, [&](size_t k) {
      return size_t(c.cell_vertex_offsets[cells[k] + 1] - c.cell_vertex_offsets[cells[k]]);
    });
    if (full) full_split_ = split_;
  }
  const std::vector<size_t>& split = full ? full_split_ : split_;
  const size_t workers = split.size() - 1;
  run_ranges(workers, workers, [&](size_t w, size_t, size_t) {
    ScatterSink<T> sink;  // (its staging arrays are left uninitialised)
    sink.positions = positions, sink.normals = normals, sink.contiguous = cell_contiguous_.data();
    run_cells_with(c, cells, split[w], split[w + 1], control, sink);
    const size_t i0 = item_count * w / workers, i1 = item_count * (w + 1) / workers;
    run_irregular_with(c, irregular_data_.data(), control, items + i0, i1 - i0, positions, normals);
  });
}

void CpuDeformer::check_mode(NormalMode mode) const {
  if (mode != NormalMode::approximate && mode != NormalMode::exact)
    fail(Status::invalid_argument, "deformer: unknown normal mode");
}

// Exact normals or no compact table, flat outputs: the reference into Vec3 scratch arrays, copied.
template <typename T>
void CpuDeformer::copy_out(const uint32_t* list, size_t count, T* positions, T* normals) const {
  for (size_t k = 0; k < count; ++k) {
    const size_t i = list ? list[k] : k;
    if (positions) store(positions, i, scratch_p_[i]);
    if (normals) store(normals, i, scratch_n_[i]);
  }
}

template <typename T>
void CpuDeformer::deform_impl(const std::vector<Vec3>& control, T* positions, T* normals, NormalMode mode) {
  check_control(control);
  check_mode(mode);
  if (mode == NormalMode::exact || !compact()) {
    if constexpr (std::is_same<T, Vec3>::value) {
      reference().deform(control, positions, normals, mode);
    } else {
      scratch_p_.resize(b_.num_vertices()), scratch_n_.resize(b_.num_vertices());
      reference().deform(control, positions ? scratch_p_.data() : nullptr, normals ? scratch_n_.data() : nullptr, mode);
      copy_out(nullptr, b_.num_vertices(), positions, normals);
    }
    control_ = control;
    reference_synced_ = true;
    return;
  }
  control_ = control;
  reference_synced_ = false;
  scatter(all_cells_.data(), all_cells_.size(), all_irregular_.data(), all_irregular_.size(), positions, normals);
}

void CpuDeformer::deform(const std::vector<Vec3>& control, Vec3* positions, Vec3* normals, NormalMode mode) {
  deform_impl(control, positions, normals, mode);
}

void CpuDeformer::deform(const std::vector<Vec3>& control, double* positions, double* normals, NormalMode mode) {
  deform_impl(control, positions, normals, mode);
}

void CpuDeformer::deform(const std::vector<Vec3>& control, float* positions, float* normals, NormalMode mode) {
  deform_impl(control, positions, normals, mode);
}

template <typename T>
size_t CpuDeformer::update_impl(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, T* positions,
                                T* normals, NormalMode mode) {
  check_update_control(control_.size(), b_.num_control_vertices, control.size());
  check_mode(mode);
  check_moved_control(moved, control.size());
  if (mode == NormalMode::exact || !compact()) {
    SparseRowDeformer& r = reference();
    // Bring the reference to the last frame first (its S, S_u, ... are updated by deltas).
    if (!reference_synced_) r.deform(control_, nullptr, nullptr, mode);
    reference_synced_ = true;
    last_from_reference_ = true;
    size_t count;
    if constexpr (std::is_same<T, Vec3>::value) {
      count = r.update(control, moved, positions, normals, mode);
    } else {
      scratch_p_.resize(b_.num_vertices()), scratch_n_.resize(b_.num_vertices());
      count = r.update(control, moved, positions ? scratch_p_.data() : nullptr, normals ? scratch_n_.data() : nullptr, mode);
      copy_out(r.last_updated().data(), r.last_updated().size(), positions, normals);
    }
    for (uint32_t j : moved) control_[j] = control[j];
    return count;
  }
  last_from_reference_ = false;
  reference_synced_ = false;
  const PatchDeformerTable& c = b_.compact;
  if (++stamp_ == 0) {
    std::fill(cell_stamp_.begin(), cell_stamp_.end(), 0);
    std::fill(irregular_stamp_.begin(), irregular_stamp_.end(), 0);
    stamp_ = 1;
  }
  cells_.clear(), irregular_.clear(), touched_.clear();
  for (uint32_t j : moved) {
    if (control[j] == control_[j]) continue;
    control_[j] = control[j];
    for (uint32_t k = c.control_cell_offsets[j]; k < c.control_cell_offsets[j + 1]; ++k) {
      const uint32_t cell = c.control_cells[k];
      if (cell_stamp_[cell] != stamp_) cell_stamp_[cell] = stamp_, cells_.push_back(cell);
    }
    for (uint32_t k = c.control_irregular_offsets[j]; k < c.control_irregular_offsets[j + 1]; ++k) {
      const uint32_t item = c.control_irregular[k];
      if (irregular_stamp_[item] != stamp_) irregular_stamp_[item] = stamp_, irregular_.push_back(item);
    }
  }
  for (uint32_t cell : cells_)
    touched_.insert(touched_.end(), c.vertex.begin() + c.cell_vertex_offsets[cell],
                    c.vertex.begin() + c.cell_vertex_offsets[cell + 1]);
  for (uint32_t item : irregular_) touched_.push_back(c.irregular_vertex[item]);
  scatter(cells_.data(), cells_.size(), irregular_.data(), irregular_.size(), positions, normals);
  return touched_.size();
}

size_t CpuDeformer::update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, Vec3* positions,
                           Vec3* normals, NormalMode mode) {
  return update_impl(control, moved, positions, normals, mode);
}

size_t CpuDeformer::update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, double* positions,
                           double* normals, NormalMode mode) {
  return update_impl(control, moved, positions, normals, mode);
}

size_t CpuDeformer::update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, float* positions,
                           float* normals, NormalMode mode) {
  return update_impl(control, moved, positions, normals, mode);
}

CAGEKIT_NAMESPACE_END
