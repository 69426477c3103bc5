// SPDX-License-Identifier: GPL-3.0-or-later
#include "multires/sparse_row_deformer.h"

#include <cmath>

#include "core/parallel_for.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

SparseRowDeformer::SparseRowDeformer(const ScanBinding& binding, int threads)
    : b_(binding), threads_(resolve_threads(threads)) {
  const size_t n = b_.num_vertices(), m = b_.num_control_vertices;
  support_offsets_.assign(m + 1, 0);
  for (uint32_t j : b_.control_index) {
    if (j >= m) fail(Status::invalid_argument, "deformer: binding refers to a control vertex out of range");
    ++support_offsets_[j + 1];
  }
  for (size_t j = 0; j < m; ++j) support_offsets_[j + 1] += support_offsets_[j];
  support_vertex_.resize(b_.num_entries());
  support_entry_.resize(b_.num_entries());
  std::vector<uint32_t> fill(support_offsets_.begin(), support_offsets_.end() - 1);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t e = b_.row_offsets[i]; e < b_.row_offsets[i + 1]; ++e) {
      const uint32_t slot = fill[b_.control_index[e]]++;
      support_vertex_[slot] = uint32_t(i);
      support_entry_[slot] = e;
    }
  touched_stamp_.assign(n, 0);
}

void SparseRowDeformer::finish_vertex(size_t i, Vec3* positions, Vec3* normals, NormalMode mode) const {
  const Vec3 &s = s_[i], &su = su_[i], &sv = sv_[i];
  const Vec3 cr = cross(su, sv);
  const double cl = norm(cr);
  const Vec3 ns = cl > 0 ? cr * (1.0 / cl) : Vec3{0, 0, 1};
  const double D = b_.displacement[i];
  if (positions) {
    if (b_.mode == DisplacementMode::normal) {
      positions[i] = s + D * ns;
    } else {
      const Vec3 t1 = normalized(su), t2 = cross(ns, t1);
      positions[i] = s + b_.tangent_offset[2 * i] * t1 + b_.tangent_offset[2 * i + 1] * t2 + D * ns;
    }
  }
  if (!normals) return;
  if (mode == NormalMode::exact) {
    auto dn = [&](const Vec3& d) { return cl > 0 ? (d - dot(d, ns) * ns) * (1.0 / cl) : Vec3(); };
    const Vec3 nu = dn(cross(suu_[i], sv) + cross(su, suv_[i])), nv = dn(cross(suv_[i], sv) + cross(su, svv_[i]));
    const Vec3 gu = su + D * nu + b_.displacement_gradient[2 * i] * ns;
    const Vec3 gv = sv + D * nv + b_.displacement_gradient[2 * i + 1] * ns;
    normals[i] = normalized(cross(gu, gv));
    return;
  }
  const double* k = &b_.normal_coefficients[6 * i];
  const Vec3 gu = k[0] * su + k[1] * sv + k[2] * ns, gv = k[3] * su + k[4] * sv + k[5] * ns;
  normals[i] = normalized(cross(gu, gv));
}

void SparseRowDeformer::deform(const std::vector<Vec3>& control, Vec3* positions, Vec3* normals, NormalMode mode) {
  if (control.size() != b_.num_control_vertices)
    fail(Status::invalid_argument, "deformer: expected " + std::to_string(b_.num_control_vertices) +
                                       " control points, got " + std::to_string(control.size()));
  const bool exact = mode == NormalMode::exact;
  if (exact && (b_.phi_uu.size() != b_.num_entries() || b_.displacement_gradient.size() != 2 * b_.num_vertices()))
    fail(Status::invalid_operation, "deformer: exact normals need a binding made with exact_normals");
  if (mode != NormalMode::approximate && !exact) fail(Status::invalid_argument, "deformer: unknown normal mode");
  const size_t n = b_.num_vertices();
  control_ = control;
  s_.resize(n), su_.resize(n), sv_.resize(n);
  if (exact) suu_.resize(n), suv_.resize(n), svv_.resize(n);
  have_second_ = exact;
  parallel_ranges(n, threads_, [&](size_t begin, size_t end) {
   for (size_t i = begin; i < end; ++i) {
    Vec3 s, su, sv, suu, suv, svv;
    for (uint32_t e = b_.row_offsets[i]; e < b_.row_offsets[i + 1]; ++e) {
      const Vec3& c = control[b_.control_index[e]];
      s += b_.phi[e] * c, su += b_.phi_u[e] * c, sv += b_.phi_v[e] * c;
      if (exact) suu += b_.phi_uu[e] * c, suv += b_.phi_uv[e] * c, svv += b_.phi_vv[e] * c;
    }
    s_[i] = s, su_[i] = su, sv_[i] = sv;
    if (exact) suu_[i] = suu, suv_[i] = suv, svv_[i] = svv;
    finish_vertex(i, positions, normals, mode);
   }
  });
}

void check_update_control(size_t last_count, size_t bound_count, size_t given_count) {
  if (last_count != bound_count) fail(Status::invalid_operation, "deformer: update() before a first deform()");
  if (given_count != last_count)
    fail(Status::invalid_argument, "deformer: expected " + std::to_string(last_count) + " control points");
}

void check_moved_control(const std::vector<uint32_t>& moved, size_t control_count) {
  for (uint32_t j : moved)
    if (j >= control_count) fail(Status::invalid_argument, "deformer: moved control vertex out of range");
}

size_t SparseRowDeformer::update(const std::vector<Vec3>& control, const std::vector<uint32_t>& moved, Vec3* positions,
                           Vec3* normals, NormalMode mode) {
  check_update_control(control_.size(), b_.num_control_vertices, control.size());
  const bool exact = mode == NormalMode::exact;
  if (exact && !have_second_) fail(Status::invalid_operation, "deformer: exact normals need a deform() in exact mode first");
  check_moved_control(moved, control.size());
  if (++stamp_ == 0) {  // wrapped: reset the stamps
    std::fill(touched_stamp_.begin(), touched_stamp_.end(), 0);
    stamp_ = 1;
  }
  std::vector<uint32_t>& touched = touched_;
  touched.clear();
  for (uint32_t j : moved) {
    const Vec3 delta = control[j] - control_[j];
    control_[j] = control[j];
    if (delta == Vec3()) continue;
    for (uint32_t k = support_offsets_[j]; k < support_offsets_[j + 1]; ++k) {
      const uint32_t i = support_vertex_[k], e = support_entry_[k];
      s_[i] += b_.phi[e] * delta, su_[i] += b_.phi_u[e] * delta, sv_[i] += b_.phi_v[e] * delta;
      if (exact) suu_[i] += b_.phi_uu[e] * delta, suv_[i] += b_.phi_uv[e] * delta, svv_[i] += b_.phi_vv[e] * delta;
      if (touched_stamp_[i] != stamp_) touched_stamp_[i] = stamp_, touched.push_back(i);
    }
  }
  parallel_ranges(touched.size(), threads_, [&](size_t begin, size_t end) {
    for (size_t k = begin; k < end; ++k) finish_vertex(touched[k], positions, normals, mode);
  });
  return touched.size();
}

CAGEKIT_NAMESPACE_END
