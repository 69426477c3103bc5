// SPDX-License-Identifier: GPL-3.0-or-later
// GPU deformer (thesis §8.6) through the public C API, in headless EGL contexts (Mesa llvmpipe
// under CI): GPU equals CPU (positions 1e-5 of the diagonal, normals 0.05 deg) in both
// displacement modes on desktop GL 4.3+ (core and compatibility profiles) and GLES 3.1+; the
// host's GL state is unchanged by every call; contexts or loaders lacking features fail with
// UNSUPPORTED_FEATURE and a message, calls out of order (no context current, a reference deform
// before its set) with INVALID_OPERATION.
// Skips (with the reason) when no EGL display or context can be made.
#include <gtest/gtest.h>

#include <GL/glcorearb.h>
#define CAGEKIT_ENABLE_EXPERIMENTAL  // the thesis's reference mode is tested too
#include <cagekit/cagekit_gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "egl_context.h"
#include "fit/surface_fitter.h"
#include "subdiv/uniform_refinement.h"
#include "test_support.h"

namespace {

constexpr double kDegree = 3.141592653589793 / 180.0;

// A bumpy sphere scan and a twice-refined cube cage fitted to it (as test_multires_binding),
// as C API objects.
struct Scene {
  cagekit_context context = nullptr;
  cagekit_mesh scan = nullptr;
  cagekit_cage cage = nullptr;
  std::vector<double> cage_positions;
  Scene() {
    cagekit::PolygonMesh s = cagekit_test::triangle_sphere(5);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> bump(-0.01, 0.01);
    for (cagekit::Vec3& p : s.positions) p = p * (1.0 + bump(rng) + 0.05 * p.x * p.y);
    cagekit::Cage cube;
    cube.mesh = cagekit_test::unit_cube_quads();
    for (cagekit::Vec3& p : cube.mesh.positions) p = (p - cagekit::Vec3{0.5, 0.5, 0.5}) * 1.2;
    cagekit::RefineOptions twice;
    twice.levels = 2;
    cagekit::FitOptions options;
    options.max_passes = 3;
    const cagekit::Cage fitted = cagekit::fit_cage_to_mesh(cagekit::refine_uniform(cube, twice), s, options);
    EXPECT_EQ(cagekit_context_create(nullptr, &context), CAGEKIT_SUCCESS);
    scan = make_mesh(s);
    cagekit_mesh cage_mesh = make_mesh(fitted.mesh);
    EXPECT_EQ(cagekit_cage_create(cage_mesh, &cage), CAGEKIT_SUCCESS) << cagekit_last_error_message(context);
    cagekit_mesh_release(cage_mesh);
    for (const cagekit::Vec3& p : fitted.mesh.positions) cage_positions.insert(cage_positions.end(), {p.x, p.y, p.z});
  }
  ~Scene() {
    cagekit_cage_release(cage);
    cagekit_mesh_release(scan);
    cagekit_context_release(context);
  }
  cagekit_mesh make_mesh(const cagekit::PolygonMesh& m) const {
    std::vector<double> xyz;
    for (const cagekit::Vec3& p : m.positions) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    std::vector<uint32_t> sizes;
    for (size_t f = 0; f < m.num_faces(); ++f) sizes.push_back(m.face_size(f));
    cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
    desc.vertex_count = uint32_t(m.num_vertices());
    desc.positions = xyz.data();
    desc.face_count = uint32_t(m.num_faces());
    desc.face_sizes = sizes.data();
    desc.face_indices = m.face_vertices.data();
    cagekit_mesh out = nullptr;
    EXPECT_EQ(cagekit_mesh_create(context, &desc, &out), CAGEKIT_SUCCESS);
    return out;
  }
  cagekit_binding bind(cagekit_displacement_mode mode) const {
    cagekit_bind_options options = CAGEKIT_BIND_OPTIONS_INIT;
    options.mode = mode;
    cagekit_binding b = nullptr;
    EXPECT_EQ(cagekit_multires_bind(cage, scan, &options, &b), CAGEKIT_SUCCESS) << cagekit_last_error_message(context);
    return b;
  }
};

const Scene& scene() {
  static const Scene* s = new Scene;  // lives to the end (released by the environment below)
  return *s;
}

// The control points of the cage with 6 of them pulled outwards by 10% of the size, the rest
// shifted slightly (a full deformation, not just the identity).
std::vector<double> edited_control(const std::vector<double>& rest) {
  std::vector<double> c = rest;
  for (size_t j = 0; j < c.size() / 3; ++j) {
    double* p = &c[3 * j];
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    const double pull = j < 6 ? 0.2 : 0.01 * std::sin(double(j));
    for (int k = 0; k < 3; ++k) p[k] += pull * p[k] / r;
    p[0] += 0.05;
  }
  return c;
}

#define SKIP_WITHOUT(ctx) \
  if (!(ctx).ok()) GTEST_SKIP() << "no EGL context: " << (ctx).error()

struct ApiCase {
  const char* name;
  EglContext::Api api;
  int major, minor;
};
const ApiCase kApis[] = {{"GL 4.3 core", EglContext::Api::desktop_core, 4, 3},
                         {"GL 4.3 compatibility", EglContext::Api::desktop_compatibility, 4, 3},
                         {"GLES 3.1", EglContext::Api::es, 3, 1}};

double angle(const double* a, const double* b) {
  const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

// Raises worst_p (position gap / diagonal) and worst_n (normal angle, degrees) over n vertices
// of the CPU (cp, cn) and GPU (gp, gn) outputs.
void accumulate_gap(uint32_t n, const std::vector<double>& cp, const std::vector<double>& cn,
                    const std::vector<double>& gp, const std::vector<double>& gn, double diagonal, double& worst_p,
                    double& worst_n) {
  for (uint32_t i = 0; i < n; ++i) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (cp[3 * i + k] - gp[3 * i + k]) * (cp[3 * i + k] - gp[3 * i + k]);
    worst_p = std::max(worst_p, std::sqrt(d2) / diagonal);
    worst_n = std::max(worst_n, angle(&cn[3 * i], &gn[3 * i]) / kDegree);
  }
}

TEST(GlDeformer, gpu_equals_cpu_in_both_apis_and_displacement_modes) {
  const Scene& s = scene();
  const std::vector<double> control = edited_control(s.cage_positions);
  const uint32_t m = uint32_t(control.size() / 3);
  for (const ApiCase& api : kApis) {
    EglContext ctx(api.api, api.major, api.minor);
    SKIP_WITHOUT(ctx);
    for (cagekit_displacement_mode mode : {CAGEKIT_DISPLACEMENT_NORMAL, CAGEKIT_DISPLACEMENT_LOCAL_FRAME}) {
      cagekit_binding binding = s.bind(mode);
      cagekit_binding_info info{};
      info.struct_size = sizeof(info);
      ASSERT_EQ(cagekit_binding_get_info(binding, &info), CAGEKIT_SUCCESS);
      const uint32_t n = info.vertex_count;
      cagekit_cpu_deformer cpu = nullptr;
      ASSERT_EQ(cagekit_cpu_deformer_create(binding, 1, &cpu), CAGEKIT_SUCCESS);
      cagekit_gl_deformer gpu = nullptr;
      ASSERT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, nullptr, &gpu),
                CAGEKIT_SUCCESS)
          << cagekit_last_error_message(s.context);
      cagekit_gl_deformer_info gi{};
      gi.struct_size = sizeof(gi);
      ASSERT_EQ(cagekit_gl_deformer_get_info(gpu, &gi), CAGEKIT_SUCCESS);
      EXPECT_EQ(gi.is_es, api.api == EglContext::Api::es ? 1 : 0);
      EXPECT_EQ(gi.vertex_count, n);
      EXPECT_EQ(gi.index_count, 3 * 8192u);  // the sphere's triangles
      EXPECT_LT(gi.acmr_after, gi.acmr_before);
      double worst_p = 0, worst_n = 0;
      for (const std::vector<double>* c : {&s.cage_positions, &control}) {
        std::vector<double> cp(3 * size_t(n)), cn(3 * size_t(n)), gp(3 * size_t(n)), gn(3 * size_t(n));
        uint32_t written = 0;  // the vertex count output of both calls
        ASSERT_EQ(cagekit_cpu_deformer_deform(cpu, c->data(), m, CAGEKIT_NORMALS_APPROXIMATE, n, &written, cp.data(),
                                              cn.data()),
                  CAGEKIT_SUCCESS);
        ASSERT_EQ(cagekit_gl_deformer_deform(gpu, c->data(), m, CAGEKIT_NORMALS_APPROXIMATE), CAGEKIT_SUCCESS)
            << cagekit_last_error_message(s.context);
        ASSERT_EQ(cagekit_gl_deformer_read_back(gpu, n, &written, gp.data(), gn.data()), CAGEKIT_SUCCESS)
            << cagekit_last_error_message(s.context);
        EXPECT_EQ(written, n);
        accumulate_gap(n, cp, cn, gp, gn, info.bbox_diagonal, worst_p, worst_n);
      }
      std::printf("%s (%s, %s), %s mode: %u vertices, GPU vs CPU: positions %.3g of the diagonal, normals %.3g deg; "
                  "ACMR %.3f -> %.3f\n",
                  api.name, gi.renderer, gi.version, mode == CAGEKIT_DISPLACEMENT_NORMAL ? "normal" : "local-frame", n, worst_p,
                  worst_n, gi.acmr_before, gi.acmr_after);
      EXPECT_LT(worst_p, 1e-5);
      EXPECT_LT(worst_n, 0.05);
      cagekit_gl_deformer_release(gpu);
      cagekit_cpu_deformer_release(cpu);
      cagekit_binding_release(binding);
    }
  }
}

// The thesis's reference mode (vertex attributes, 16 + 3|Q| floats, transform feedback) gives
// the CPU's result too, for |Q| = 1, 6 and the largest |Q|.
TEST(GlDeformer, reference_mode_equals_cpu) {
  const Scene& s = scene();
  const uint32_t m = uint32_t(s.cage_positions.size() / 3);
  for (const ApiCase& api : kApis) {
    EglContext ctx(api.api, api.major, api.minor);
    SKIP_WITHOUT(ctx);
    cagekit_binding binding = s.bind(CAGEKIT_DISPLACEMENT_NORMAL);
    cagekit_binding_info info{};
    info.struct_size = sizeof(info);
    ASSERT_EQ(cagekit_binding_get_info(binding, &info), CAGEKIT_SUCCESS);
    const uint32_t n = info.vertex_count;
    cagekit_cpu_deformer cpu = nullptr;
    ASSERT_EQ(cagekit_cpu_deformer_create(binding, 1, &cpu), CAGEKIT_SUCCESS);
    cagekit_gl_deformer gpu = nullptr;
    ASSERT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, nullptr, &gpu),
              CAGEKIT_SUCCESS);
    cagekit_gl_deformer_info gi{};
    gi.struct_size = sizeof(gi);
    ASSERT_EQ(cagekit_gl_deformer_get_info(gpu, &gi), CAGEKIT_SUCCESS);
    EXPECT_EQ(gi.reference_floats_per_vertex, 0u);
    ASSERT_GE(gi.reference_max_edited, 11u);
    for (uint32_t q : {1u, 6u, gi.reference_max_edited}) {
      std::vector<uint32_t> edited;
      for (uint32_t k = 0; k < q; ++k) edited.push_back((k * 37u) % m);
      ASSERT_EQ(cagekit_gl_deformer_set_reference_set(gpu, edited.data(), q, s.cage_positions.data(), m), CAGEKIT_SUCCESS)
          << cagekit_last_error_message(s.context);
      ASSERT_EQ(cagekit_gl_deformer_get_info(gpu, &gi), CAGEKIT_SUCCESS);
      EXPECT_EQ(gi.reference_floats_per_vertex, 16 + 3 * q);  // AC-8.6
      double worst_p = 0, worst_n = 0;
      for (int frame = 1; frame <= 2; ++frame) {
        std::vector<double> control = s.cage_positions;
        for (uint32_t j : edited)
          for (int k = 0; k < 3; ++k) control[3 * j + k] *= 1.0 + 0.1 * frame;
        std::vector<double> cp(3 * size_t(n)), cn(3 * size_t(n)), gp(3 * size_t(n)), gn(3 * size_t(n));
        uint32_t written = 0;  // the vertex count output of both calls
        ASSERT_EQ(cagekit_cpu_deformer_deform(cpu, control.data(), m, CAGEKIT_NORMALS_APPROXIMATE, n, &written,
                                              cp.data(), cn.data()),
                  CAGEKIT_SUCCESS);
        ASSERT_EQ(cagekit_gl_deformer_deform_reference(gpu, control.data(), m), CAGEKIT_SUCCESS)
            << cagekit_last_error_message(s.context);
        ASSERT_EQ(cagekit_gl_deformer_read_back(gpu, n, &written, gp.data(), gn.data()), CAGEKIT_SUCCESS);
        accumulate_gap(n, cp, cn, gp, gn, info.bbox_diagonal, worst_p, worst_n);
      }
      std::printf("%s reference mode |Q| = %u (%u floats per vertex): GPU vs CPU positions %.3g of the diagonal, "
                  "normals %.3g deg\n", api.name, q, gi.reference_floats_per_vertex, worst_p, worst_n);
      EXPECT_LT(worst_p, 1e-5);
      EXPECT_LT(worst_n, 0.05);
    }
    // Bad sets.
    std::vector<uint32_t> too_many(gi.reference_max_edited + 1);
    for (uint32_t k = 0; k < too_many.size(); ++k) too_many[k] = k;
    EXPECT_EQ(cagekit_gl_deformer_set_reference_set(gpu, too_many.data(), uint32_t(too_many.size()),
                                                    s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    const uint32_t twice[2] = {3, 3}, out_of_range[1] = {m};
    EXPECT_EQ(cagekit_gl_deformer_set_reference_set(gpu, twice, 2, s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_set_reference_set(gpu, out_of_range, 1, s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_set_reference_set(gpu, nullptr, 0, s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_set_reference_set(gpu, nullptr, 2, s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    cagekit_gl_deformer_release(gpu);
    cagekit_cpu_deformer_release(cpu);
    cagekit_binding_release(binding);
    // The reference mode is the thesis's normal-displacement mode; and needs a set first.
    binding = s.bind(CAGEKIT_DISPLACEMENT_LOCAL_FRAME);
    ASSERT_EQ(cagekit_gl_deformer_create(binding, nullptr, EglContext::get_proc_address, nullptr, nullptr, &gpu),
              CAGEKIT_SUCCESS);
    EXPECT_EQ(cagekit_gl_deformer_deform_reference(gpu, s.cage_positions.data(), m), CAGEKIT_ERROR_INVALID_OPERATION);
    const uint32_t one[1] = {0};
    EXPECT_EQ(cagekit_gl_deformer_set_reference_set(gpu, one, 1, s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_OPERATION);
    EXPECT_NE(std::string(cagekit_last_error_message(s.context)).find("local-frame"), std::string::npos);
    cagekit_gl_deformer_release(gpu);
    cagekit_binding_release(binding);
  }
}

// The affine-frame variant (§8.6.2 (b)): a set Q larger than the attribute limit moves by one
// affine map given by four frame points; 28 floats per vertex, the CPU's result.
TEST(GlDeformer, reference_affine_variant_equals_cpu) {
  const Scene& s = scene();
  const uint32_t m = uint32_t(s.cage_positions.size() / 3);
  // An affine map: a shear and scale about a point, plus a shift.
  auto apply = [](const double* p, double* out, double t) {
    const double a[3][3] = {{1 + 0.2 * t, 0.1 * t, 0}, {0, 1, 0.15 * t}, {0.05 * t, 0, 1 - 0.1 * t}};
    for (int r = 0; r < 3; ++r) out[r] = a[r][0] * p[0] + a[r][1] * p[1] + a[r][2] * p[2] + (r == 0 ? 0.05 * t : 0.0);
  };
  const double frame[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (const ApiCase& api : kApis) {
    EglContext ctx(api.api, api.major, api.minor);
    SKIP_WITHOUT(ctx);
    cagekit_binding binding = s.bind(CAGEKIT_DISPLACEMENT_NORMAL);
    cagekit_binding_info info{};
    info.struct_size = sizeof(info);
    ASSERT_EQ(cagekit_binding_get_info(binding, &info), CAGEKIT_SUCCESS);
    const uint32_t n = info.vertex_count;
    cagekit_cpu_deformer cpu = nullptr;
    ASSERT_EQ(cagekit_cpu_deformer_create(binding, 1, &cpu), CAGEKIT_SUCCESS);
    cagekit_gl_deformer gpu = nullptr;
    ASSERT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, nullptr, &gpu),
              CAGEKIT_SUCCESS);
    cagekit_gl_deformer_info gi{};
    gi.struct_size = sizeof(gi);
    ASSERT_EQ(cagekit_gl_deformer_get_info(gpu, &gi), CAGEKIT_SUCCESS);
    // Q: half of the control points (more than the |Q| path's attribute limit).
    std::vector<uint32_t> edited;
    for (uint32_t j = 0; j < m; j += 2) edited.push_back(j);
    ASSERT_GT(edited.size(), size_t(gi.reference_max_edited));
    ASSERT_EQ(cagekit_gl_deformer_set_reference_affine(gpu, edited.data(), uint32_t(edited.size()), frame,
                                                       s.cage_positions.data(), m),
              CAGEKIT_SUCCESS)
        << cagekit_last_error_message(s.context);
    ASSERT_EQ(cagekit_gl_deformer_get_info(gpu, &gi), CAGEKIT_SUCCESS);
    EXPECT_EQ(gi.reference_floats_per_vertex, 28u);  // AC-8.6: 28 floats whatever |Q|
    double worst_p = 0, worst_n = 0, moved = 0;
    for (int step = 1; step <= 2; ++step) {
      const double t = 0.5 * step;
      std::vector<double> control = s.cage_positions;
      for (uint32_t j : edited) apply(&s.cage_positions[3 * j], &control[3 * j], t);
      double moved_frame[12];
      for (int l = 0; l < 4; ++l) apply(&frame[3 * l], &moved_frame[3 * l], t);
      std::vector<double> cp(3 * size_t(n)), cn(3 * size_t(n)), gp(3 * size_t(n)), gn(3 * size_t(n));
      uint32_t written = 0;  // the vertex count output of both calls
      ASSERT_EQ(cagekit_cpu_deformer_deform(cpu, control.data(), m, CAGEKIT_NORMALS_APPROXIMATE, n, &written, cp.data(),
                                            cn.data()),
                CAGEKIT_SUCCESS);
      ASSERT_EQ(cagekit_gl_deformer_deform_reference_affine(gpu, moved_frame), CAGEKIT_SUCCESS)
          << cagekit_last_error_message(s.context);
      ASSERT_EQ(cagekit_gl_deformer_read_back(gpu, n, &written, gp.data(), gn.data()), CAGEKIT_SUCCESS);
      for (uint32_t j : edited)
        for (int k = 0; k < 3; ++k) moved = std::max(moved, std::abs(control[3 * j + k] - s.cage_positions[3 * j + k]));
      accumulate_gap(n, cp, cn, gp, gn, info.bbox_diagonal, worst_p, worst_n);
    }
    std::printf("%s affine reference variant, |Q| = %zu (%u floats per vertex, control points moved up to %.2g): "
                "GPU vs CPU positions %.3g of the diagonal, normals %.3g deg\n",
                api.name, edited.size(), gi.reference_floats_per_vertex, moved, worst_p, worst_n);
    EXPECT_GT(moved, 0.05);
    EXPECT_LT(worst_p, 1e-5);
    EXPECT_LT(worst_n, 0.05);
    // Bad input: a coplanar frame, NaN, a call before the set, a repeated index.
    const double flat[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    EXPECT_EQ(cagekit_gl_deformer_set_reference_affine(gpu, edited.data(), 2, flat, s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    double bad[12];
    std::copy(frame, frame + 12, bad);
    bad[4] = std::nan("");
    EXPECT_EQ(cagekit_gl_deformer_deform_reference_affine(gpu, bad), CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_deform_reference_affine(gpu, nullptr), CAGEKIT_ERROR_INVALID_ARGUMENT);
    const uint32_t twice[2] = {3, 3};
    EXPECT_EQ(cagekit_gl_deformer_set_reference_affine(gpu, twice, 2, frame, s.cage_positions.data(), m),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    // |Q| mode and affine mode do not mix.
    const uint32_t one[1] = {0};
    ASSERT_EQ(cagekit_gl_deformer_set_reference_set(gpu, one, 1, s.cage_positions.data(), m), CAGEKIT_SUCCESS);
    EXPECT_EQ(cagekit_gl_deformer_deform_reference_affine(gpu, frame), CAGEKIT_ERROR_INVALID_OPERATION);
    cagekit_gl_deformer_release(gpu);
    cagekit_cpu_deformer_release(cpu);
    cagekit_binding_release(binding);
  }
}

// The host's state as the GL deformer could touch it, and more.
struct HostState {
  std::vector<GLint64> values;
  bool operator==(const HostState& o) const { return values == o.values; }
};

HostState query_state() {
  auto get = EglContext::load<PFNGLGETINTEGERVPROC>("glGetIntegerv");
  auto get_i = EglContext::load<PFNGLGETINTEGERI_VPROC>("glGetIntegeri_v");
  auto get64_i = EglContext::load<PFNGLGETINTEGER64I_VPROC>("glGetInteger64i_v");
  HostState s;
  for (GLenum e : {GL_CURRENT_PROGRAM, GL_SHADER_STORAGE_BUFFER_BINDING, GL_ARRAY_BUFFER_BINDING,
                   GL_ELEMENT_ARRAY_BUFFER_BINDING, GL_VERTEX_ARRAY_BINDING, GL_COPY_READ_BUFFER_BINDING,
                   GL_COPY_WRITE_BUFFER_BINDING, GL_UNIFORM_BUFFER_BINDING, GL_PIXEL_PACK_BUFFER_BINDING,
                   GL_PIXEL_UNPACK_BUFFER_BINDING, GL_DISPATCH_INDIRECT_BUFFER_BINDING, GL_DRAW_INDIRECT_BUFFER_BINDING,
                   GL_ATOMIC_COUNTER_BUFFER_BINDING, GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, GL_ACTIVE_TEXTURE,
                   GL_TEXTURE_BINDING_2D, GL_FRAMEBUFFER_BINDING, GL_READ_FRAMEBUFFER_BINDING,
                   GL_TRANSFORM_FEEDBACK_BINDING, GL_DRAW_FRAMEBUFFER_BINDING, GL_RENDERBUFFER_BINDING}) {
    GLint v = -7;
    get(e, &v);
    s.values.push_back(v);
  }
  s.values.push_back(EglContext::load<PFNGLISENABLEDPROC>("glIsEnabled")(GL_RASTERIZER_DISCARD));
  s.values.push_back(EglContext::load<PFNGLISENABLEDPROC>("glIsEnabled")(GL_DEPTH_TEST));
  {
    GLint b = -7;
    get_i(GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, 0, &b);
    s.values.push_back(b);
  }
  GLint max_bindings = 0;
  get(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &max_bindings);
  for (GLint i = 0; i < std::min(max_bindings, 8); ++i) {
    GLint b = -7;
    GLint64 start = -7, size = -7;
    get_i(GL_SHADER_STORAGE_BUFFER_BINDING, GLuint(i), &b);
    get64_i(GL_SHADER_STORAGE_BUFFER_START, GLuint(i), &start);
    get64_i(GL_SHADER_STORAGE_BUFFER_SIZE, GLuint(i), &size);
    s.values.insert(s.values.end(), {b, start, size});
  }
  return s;
}

TEST(GlDeformer, host_gl_state_is_unchanged) {
  const Scene& s = scene();
  for (const ApiCase& api : kApis) {
    EglContext ctx(api.api, api.major, api.minor);
    SKIP_WITHOUT(ctx);
    auto gen_buffers = EglContext::load<PFNGLGENBUFFERSPROC>("glGenBuffers");
    auto bind_buffer = EglContext::load<PFNGLBINDBUFFERPROC>("glBindBuffer");
    auto buffer_data = EglContext::load<PFNGLBUFFERDATAPROC>("glBufferData");
    auto bind_range = EglContext::load<PFNGLBINDBUFFERRANGEPROC>("glBindBufferRange");
    auto bind_base = EglContext::load<PFNGLBINDBUFFERBASEPROC>("glBindBufferBase");
    auto gen_vao = EglContext::load<PFNGLGENVERTEXARRAYSPROC>("glGenVertexArrays");
    auto bind_vao = EglContext::load<PFNGLBINDVERTEXARRAYPROC>("glBindVertexArray");
    auto delete_buffers = EglContext::load<PFNGLDELETEBUFFERSPROC>("glDeleteBuffers");
    auto delete_vao = EglContext::load<PFNGLDELETEVERTEXARRAYSPROC>("glDeleteVertexArrays");
    auto create_program = EglContext::load<PFNGLCREATEPROGRAMPROC>("glCreateProgram");
    auto create_shader = EglContext::load<PFNGLCREATESHADERPROC>("glCreateShader");
    auto shader_source = EglContext::load<PFNGLSHADERSOURCEPROC>("glShaderSource");
    auto compile = EglContext::load<PFNGLCOMPILESHADERPROC>("glCompileShader");
    auto attach = EglContext::load<PFNGLATTACHSHADERPROC>("glAttachShader");
    auto link = EglContext::load<PFNGLLINKPROGRAMPROC>("glLinkProgram");
    auto use = EglContext::load<PFNGLUSEPROGRAMPROC>("glUseProgram");
    auto delete_program = EglContext::load<PFNGLDELETEPROGRAMPROC>("glDeleteProgram");
    auto delete_shader = EglContext::load<PFNGLDELETESHADERPROC>("glDeleteShader");
    auto get_error = EglContext::load<PFNGLGETERRORPROC>("glGetError");
    ASSERT_NE(gen_buffers, nullptr);
    // A host with something bound everywhere the deformer works: a VAO with an element buffer,
    // array / copy / storage buffers (indexed bindings by range and by base), its own program.
    GLuint buffers[8] = {};
    gen_buffers(8, buffers);
    for (GLuint b : buffers) {
      bind_buffer(GL_ARRAY_BUFFER, b);
      buffer_data(GL_ARRAY_BUFFER, 4096, nullptr, GL_STATIC_DRAW);
    }
    GLuint vao = 0;
    gen_vao(1, &vao);
    bind_vao(vao);
    bind_buffer(GL_ELEMENT_ARRAY_BUFFER, buffers[0]);
    bind_buffer(GL_ARRAY_BUFFER, buffers[1]);
    bind_buffer(GL_COPY_READ_BUFFER, buffers[2]);
    bind_buffer(GL_COPY_WRITE_BUFFER, buffers[3]);
    bind_range(GL_SHADER_STORAGE_BUFFER, 0, buffers[4], 256, 512);
    bind_base(GL_SHADER_STORAGE_BUFFER, 2, buffers[5]);
    bind_range(GL_SHADER_STORAGE_BUFFER, 3, buffers[6], 0, 1024);
    bind_buffer(GL_SHADER_STORAGE_BUFFER, buffers[7]);
    // ... and its own transform feedback object with a buffer, depth test on.
    GLuint feedback = 0;
    EglContext::load<PFNGLGENTRANSFORMFEEDBACKSPROC>("glGenTransformFeedbacks")(1, &feedback);
    EglContext::load<PFNGLBINDTRANSFORMFEEDBACKPROC>("glBindTransformFeedback")(GL_TRANSFORM_FEEDBACK, feedback);
    bind_base(GL_TRANSFORM_FEEDBACK_BUFFER, 0, buffers[5]);
    bind_buffer(GL_TRANSFORM_FEEDBACK_BUFFER, buffers[6]);
    EglContext::load<PFNGLENABLEPROC>("glEnable")(GL_DEPTH_TEST);
    const char* source = api.api == EglContext::Api::es
                             ? "#version 310 es\nlayout(local_size_x = 1) in;\nvoid main() {}\n"
                             : "#version 430 core\nlayout(local_size_x = 1) in;\nvoid main() {}\n";
    const GLuint shader = create_shader(GL_COMPUTE_SHADER);
    shader_source(shader, 1, &source, nullptr);
    compile(shader);
    const GLuint program = create_program();
    attach(program, shader);
    link(program);
    use(program);
    ASSERT_EQ(get_error(), GLenum(GL_NO_ERROR));
    const HostState before = query_state();
    ASSERT_EQ(before.values[0], GLint64(program));

    cagekit_binding binding = s.bind(CAGEKIT_DISPLACEMENT_LOCAL_FRAME);
    cagekit_gl_deformer gpu = nullptr;
    ASSERT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, nullptr, &gpu),
              CAGEKIT_SUCCESS)
        << cagekit_last_error_message(s.context);
    EXPECT_TRUE(query_state() == before) << api.name << ": create changed the host's state";
    const std::vector<double> control = edited_control(s.cage_positions);
    ASSERT_EQ(cagekit_gl_deformer_deform(gpu, control.data(), uint32_t(control.size() / 3), CAGEKIT_NORMALS_APPROXIMATE),
              CAGEKIT_SUCCESS);
    EXPECT_TRUE(query_state() == before) << api.name << ": deform changed the host's state";
    std::vector<double> p(3 * 4098);
    uint32_t written = 0;
    ASSERT_EQ(cagekit_gl_deformer_read_back(gpu, 4098, &written, p.data(), nullptr), CAGEKIT_SUCCESS);
    EXPECT_TRUE(query_state() == before) << api.name << ": read_back changed the host's state";
    cagekit_binding normal_binding = s.bind(CAGEKIT_DISPLACEMENT_NORMAL);
    cagekit_gl_deformer reference = nullptr;
    ASSERT_EQ(cagekit_gl_deformer_create(normal_binding, s.scan, EglContext::get_proc_address, nullptr, nullptr, &reference),
              CAGEKIT_SUCCESS);
    const uint32_t edited[4] = {0, 5, 9, 17};
    ASSERT_EQ(cagekit_gl_deformer_set_reference_set(reference, edited, 4, s.cage_positions.data(),
                                                    uint32_t(s.cage_positions.size() / 3)),
              CAGEKIT_SUCCESS) << cagekit_last_error_message(s.context);
    EXPECT_TRUE(query_state() == before) << api.name << ": set_reference_set changed the host's state";
    ASSERT_EQ(cagekit_gl_deformer_deform_reference(reference, s.cage_positions.data(),
                                                   uint32_t(s.cage_positions.size() / 3)),
              CAGEKIT_SUCCESS);
    EXPECT_TRUE(query_state() == before) << api.name << ": deform_reference changed the host's state";
    cagekit_gl_deformer_release(reference);
    cagekit_binding_release(normal_binding);
    cagekit_gl_deformer_release(gpu);
    EXPECT_TRUE(query_state() == before) << api.name << ": release changed the host's state";
    EXPECT_EQ(get_error(), GLenum(GL_NO_ERROR));
    cagekit_binding_release(binding);
    use(0);
    delete_program(program);
    delete_shader(shader);
    bind_vao(0);
    delete_vao(1, &vao);
    EglContext::load<PFNGLBINDTRANSFORMFEEDBACKPROC>("glBindTransformFeedback")(GL_TRANSFORM_FEEDBACK, 0);
    EglContext::load<PFNGLDELETETRANSFORMFEEDBACKSPROC>("glDeleteTransformFeedbacks")(1, &feedback);
    delete_buffers(8, buffers);
  }
}

// A loader that hides one entry point, as a host with an incomplete GL would.
struct Hiding {
  const char* hidden;
};
void (*hiding_get_proc_address(const char* name, void* user))(void) {
  if (std::strcmp(name, static_cast<Hiding*>(user)->hidden) == 0) return nullptr;
  return eglGetProcAddress(name);
}

// A loader whose glGetString reports g_fake_version for GL_VERSION.
const char* g_fake_version = "";
const GLubyte* APIENTRY fake_get_string(GLenum name) {
  if (name == GL_VERSION) return reinterpret_cast<const GLubyte*>(g_fake_version);
  return EglContext::load<PFNGLGETSTRINGPROC>("glGetString")(name);
}
void (*old_get_proc_address(const char* name, void*))(void) {
  if (std::strcmp(name, "glGetString") == 0) return reinterpret_cast<void (*)(void)>(&fake_get_string);
  return eglGetProcAddress(name);
}

// A loader whose glGetIntegerv reports g_fake_limit.second for the limit g_fake_limit.first.
std::pair<GLenum, GLint> g_fake_limit;
void APIENTRY fake_get_integerv(GLenum name, GLint* value) {
  EglContext::load<PFNGLGETINTEGERVPROC>("glGetIntegerv")(name, value);
  if (name == g_fake_limit.first) *value = g_fake_limit.second;
}
void (*limited_get_proc_address(const char* name, void*))(void) {
  if (std::strcmp(name, "glGetIntegerv") == 0) return reinterpret_cast<void (*)(void)>(&fake_get_integerv);
  return eglGetProcAddress(name);
}

TEST(GlDeformer, missing_features_are_an_error_not_a_crash) {
  const Scene& s = scene();
  cagekit_binding binding = s.bind(CAGEKIT_DISPLACEMENT_NORMAL);
  {
    EglContext ctx(EglContext::Api::desktop_core, 4, 3);
    SKIP_WITHOUT(ctx);
    Hiding hide{"glDispatchCompute"};
    cagekit_gl_deformer gpu = reinterpret_cast<cagekit_gl_deformer>(&hide);  // must be set to NULL
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, hiding_get_proc_address, &hide, nullptr, &gpu),
              CAGEKIT_ERROR_UNSUPPORTED_FEATURE);
    EXPECT_EQ(gpu, nullptr);
    const std::string message = cagekit_last_error_message(s.context);
    std::printf("hidden glDispatchCompute: %s\n", message.c_str());
    EXPECT_NE(message.find("glDispatchCompute"), std::string::npos);
    Hiding hide_version{"glGetString"};
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, hiding_get_proc_address, &hide_version, nullptr, &gpu),
              CAGEKIT_ERROR_INVALID_OPERATION);  // no glGetString: no context current
    EXPECT_NE(std::string(cagekit_last_error_message(s.context)).find("glGetString"), std::string::npos);
    // Arguments.
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, nullptr, nullptr, nullptr, &gpu), CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, nullptr, nullptr),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_create(nullptr, s.scan, EglContext::get_proc_address, nullptr, nullptr, &gpu),
              CAGEKIT_ERROR_INVALID_HANDLE);
    cagekit_gl_deformer_options bad = CAGEKIT_GL_DEFORMER_OPTIONS_INIT;
    bad.optimize_vertex_cache = 7;
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, &bad, &gpu),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    bad.optimize_vertex_cache = 0;
    bad.struct_size = 1;
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, &bad, &gpu),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    cagekit_cage_release(nullptr);
    // Wrong per-frame input on a good deformer; exact normals are not done on the GPU.
    cagekit_gl_deformer_options keep_order = CAGEKIT_GL_DEFORMER_OPTIONS_INIT;
    keep_order.optimize_vertex_cache = 0;
    ASSERT_EQ(cagekit_gl_deformer_create(binding, nullptr, EglContext::get_proc_address, nullptr, &keep_order, &gpu),
              CAGEKIT_SUCCESS);
    cagekit_gl_deformer_buffers buffers{};
    buffers.struct_size = sizeof(buffers);
    ASSERT_EQ(cagekit_gl_deformer_get_buffers(gpu, &buffers), CAGEKIT_SUCCESS);
    EXPECT_EQ(buffers.index_buffer, 0u);
    EXPECT_EQ(buffers.index_count, 0u);
    EXPECT_NE(buffers.position_buffer, 0u);
    EXPECT_EQ(buffers.position_stride, 24u);
    EXPECT_EQ(buffers.normal_offset, 12u);
    std::vector<double> control = s.cage_positions;
    const uint32_t m = uint32_t(control.size() / 3);
    EXPECT_EQ(cagekit_gl_deformer_deform(gpu, control.data(), m - 1, CAGEKIT_NORMALS_APPROXIMATE),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_deform(gpu, nullptr, m, CAGEKIT_NORMALS_APPROXIMATE), CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_deform(gpu, control.data(), m, CAGEKIT_NORMALS_EXACT), CAGEKIT_ERROR_UNSUPPORTED_FEATURE);
    EXPECT_EQ(cagekit_gl_deformer_deform(gpu, control.data(), m, cagekit_normal_mode(-1)), CAGEKIT_ERROR_INVALID_ARGUMENT);
    control[5] = NAN;
    EXPECT_EQ(cagekit_gl_deformer_deform(gpu, control.data(), m, CAGEKIT_NORMALS_APPROXIMATE),
              CAGEKIT_ERROR_INVALID_ARGUMENT);
    // read_back's two-call shape (cagekit.h, Buffers): the count is required, capacity 0 is a
    // query, a short capacity fails with the count written.
    std::vector<double> small(3);
    uint32_t count = 0;
    EXPECT_EQ(cagekit_gl_deformer_read_back(gpu, 1, nullptr, small.data(), nullptr), CAGEKIT_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(cagekit_gl_deformer_read_back(gpu, 0, &count, nullptr, nullptr), CAGEKIT_SUCCESS);
    EXPECT_EQ(count, buffers.vertex_count);
    count = 0;
    EXPECT_EQ(cagekit_gl_deformer_read_back(gpu, 1, &count, small.data(), nullptr), CAGEKIT_ERROR_SIZE_INSUFFICIENT);
    EXPECT_EQ(count, buffers.vertex_count);
    EXPECT_EQ(cagekit_gl_deformer_get_info(gpu, nullptr), CAGEKIT_ERROR_INVALID_ARGUMENT);
    cagekit_gl_deformer_release(gpu);
    EXPECT_EQ(cagekit_gl_deformer_deform(nullptr, control.data(), m, CAGEKIT_NORMALS_APPROXIMATE),
              CAGEKIT_ERROR_INVALID_HANDLE);
    cagekit_gl_deformer_release(nullptr);
  }
  {
    // Contexts older than GL 4.3 / GLES 3.1. Mesa hands out its newest compatible version
    // whatever is asked for, so the host's loader reports an older one through glGetString.
    EglContext ctx(EglContext::Api::desktop_core, 4, 3);
    SKIP_WITHOUT(ctx);
    for (const char* version : {"3.3 (Core Profile) Mesa 22.3.6", "4.2.0 NVIDIA 390.157", "OpenGL ES 3.0 Mesa 22.3.6",
                                "OpenGL ES-CM 1.1", "garbage"}) {
      g_fake_version = version;
      cagekit_gl_deformer gpu = reinterpret_cast<cagekit_gl_deformer>(&ctx);
      EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, old_get_proc_address, nullptr, nullptr, &gpu),
                CAGEKIT_ERROR_UNSUPPORTED_FEATURE) << version;
      EXPECT_EQ(gpu, nullptr);
      const std::string message = cagekit_last_error_message(s.context);
      std::printf("context \"%s\": %s\n", version, message.c_str());
      EXPECT_NE(message.find(version), std::string::npos);
    }
    // A version that is new enough passes the same loader.
    g_fake_version = "4.6 (Compatibility Profile) Mesa 22.3.6";
    cagekit_gl_deformer gpu = nullptr;
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, old_get_proc_address, nullptr, nullptr, &gpu), CAGEKIT_SUCCESS);
    cagekit_gl_deformer_release(gpu);
  }
  {
    // Limits below what the deformer needs: too few storage blocks, too small a block size.
    EglContext ctx(EglContext::Api::es, 3, 1);
    SKIP_WITHOUT(ctx);
    const struct {
      GLenum limit;
      GLint value;
      cagekit_status expected;
      const char* message;
    } cases[] = {{GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, 2, CAGEKIT_ERROR_UNSUPPORTED_FEATURE, "4 shader storage blocks"},
                 {GL_MAX_SHADER_STORAGE_BLOCK_SIZE, 4096, CAGEKIT_ERROR_LIMIT_EXCEEDED, "GL_MAX_SHADER_STORAGE_BLOCK_SIZE"}};
    for (const auto& c : cases) {
      g_fake_limit = {c.limit, c.value};
      cagekit_gl_deformer gpu = nullptr;
      EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, limited_get_proc_address, nullptr, nullptr, &gpu), c.expected);
      EXPECT_EQ(gpu, nullptr);
      const std::string message = cagekit_last_error_message(s.context);
      std::printf("limit 0x%04x = %d: %s\n", unsigned(c.limit), c.value, message.c_str());
      EXPECT_NE(message.find(c.message), std::string::npos);
    }
  }
  {
    // No context current at all.
    cagekit_gl_deformer gpu = nullptr;
    EXPECT_EQ(cagekit_gl_deformer_create(binding, s.scan, EglContext::get_proc_address, nullptr, nullptr, &gpu),
              CAGEKIT_ERROR_INVALID_OPERATION);
    std::printf("no current context: %s\n", cagekit_last_error_message(s.context));
  }
  cagekit_binding_release(binding);
}

class ReleaseScene : public ::testing::Environment {
 public:
  void TearDown() override { delete &scene(); }
};
const auto* const kReleaseScene = ::testing::AddGlobalTestEnvironment(new ReleaseScene);

}  // namespace
