// SPDX-License-Identifier: GPL-3.0-or-later
#include "multires/basis_rows.h"

#include "core/parallel_for.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

std::vector<BasisWeights> evaluate_basis_rows(const SubdivisionSurface& surface, const std::vector<FootPoint>& feet,
                                              int threads, const TaskMonitor& monitor, double f0, double f1) {
  std::vector<BasisWeights> rows(feet.size());
  parallel_for(feet.size(), threads, monitor, "bind", f0, f1, [&](size_t i) {
    const FootPoint& t = feet[i];
    rows[i] = surface.basis(t.ptex_face, t.u, t.v);
  });
  return rows;
}

void store_basis_rows(ScanBinding& b, const std::vector<BasisWeights>& rows, bool second_derivatives) {
  const size_t n = rows.size();
  b.row_offsets.assign(n + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    if (uint64_t(b.row_offsets[i]) + rows[i].indices.size() > UINT32_MAX)
      fail(Status::limit_exceeded, "binding: more than 2^32 basis entries");
    b.row_offsets[i + 1] = b.row_offsets[i] + uint32_t(rows[i].indices.size());
  }
  const size_t entries = b.row_offsets[n];
  b.control_index.clear(), b.phi.clear(), b.phi_u.clear(), b.phi_v.clear();
  b.phi_uu.clear(), b.phi_uv.clear(), b.phi_vv.clear();
  b.control_index.reserve(entries);
  b.phi.reserve(entries), b.phi_u.reserve(entries), b.phi_v.reserve(entries);
  for (const BasisWeights& w : rows) {
    b.control_index.insert(b.control_index.end(), w.indices.begin(), w.indices.end());
    b.phi.insert(b.phi.end(), w.w.begin(), w.w.end());
    b.phi_u.insert(b.phi_u.end(), w.wu.begin(), w.wu.end());
    b.phi_v.insert(b.phi_v.end(), w.wv.begin(), w.wv.end());
    if (second_derivatives) {
      b.phi_uu.insert(b.phi_uu.end(), w.wuu.begin(), w.wuu.end());
      b.phi_uv.insert(b.phi_uv.end(), w.wuv.begin(), w.wuv.end());
      b.phi_vv.insert(b.phi_vv.end(), w.wvv.begin(), w.wvv.end());
    }
  }
}

CAGEKIT_NAMESPACE_END
