// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/principal_alignment.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// Angle between two lines (0..90°); 0 when either direction is zero.
double line_angle_deg(const Vec3& a, const Vec3& b) {
  const double la = norm(a), lb = norm(b);
  if (!(la > 0.0) || !(lb > 0.0)) return 0.0;
  return degrees_from_radians(std::acos(std::min(1.0, std::fabs(dot(a, b)) / (la * lb))));
}

}  // namespace

PrincipalAlignment measure_principal_alignment(const CurvatureField& field, const std::vector<AlignmentSample>& samples) {
  const double lambda_min = std::cos(kPi / 6.0);
  const size_t nf = field.face_confidence.size();
  PrincipalAlignment r;
  r.samples = samples.size();
  double sum = 0.0;
  for (const AlignmentSample& s : samples) {
    if (s.face_a >= nf || s.face_b >= nf) continue;
    if (field.face_confidence[s.face_a] < lambda_min || field.face_confidence[s.face_b] < lambda_min) continue;
    const Vec3& d = s.chord;
    auto nearer = [&](uint32_t g) {
      const Vec3 t1 = field.face_t_min[g], t2 = field.face_t_max[g];
      return line_angle_deg(d, t1) <= line_angle_deg(d, t2) ? t1 : t2;
    };
    const Vec3 pa = nearer(s.face_a), pb = nearer(s.face_b);
    sum += line_angle_deg(d, pa + (dot(pa, pb) < 0.0 ? -1.0 : 1.0) * pb);
    ++r.measured;
  }
  r.mean_deg = r.measured ? sum / double(r.measured) : 0.0;
  return r;
}

CAGEKIT_NAMESPACE_END
