// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// How well a remeshed output follows the input's principal curvature directions (thesis ch. 5,
// confident faces only), for the anisotropic remesher's report and tests/bench/bench_remesh (one
// definition for CageKit's and a peer's output). The other quality figures: remesh_quality.h.
#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "layout/anisotropic/curvature_tensor_field.h"

CAGEKIT_NAMESPACE_BEGIN

// One output edge to score: its chord and the input faces whose principal directions it is
// compared with (the remesher: the faces its two ends lie on; a peer's output: the face its
// midpoint projects to, twice).
struct AlignmentSample {
  Vec3 chord;
  uint32_t face_a = 0, face_b = 0;
};

struct PrincipalAlignment {
  double mean_deg = 0.0;   // mean over the measured samples; 0 when none
  uint64_t measured = 0;   // samples whose two faces are confident (Λ(f) >= cos π/6)
  uint64_t samples = 0;    // all samples given
};

// For each sample whose two faces are confident: the angle (0..90°) between the chord and the
// sign-aligned mean of the nearer principal direction (t_min or t_max, whichever makes the
// smaller angle with the chord) of each face — the tangent at the middle of a curved edge when the
// faces are its ends', the direction at the midpoint when both are the midpoint's face. Faces out
// of range are skipped (not measured).
PrincipalAlignment measure_principal_alignment(const CurvatureField& field, const std::vector<AlignmentSample>& samples);

CAGEKIT_NAMESPACE_END
