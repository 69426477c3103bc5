// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Defensive checks of a cage before any of it reaches OpenSubdiv, whose factories assume
// well-formed input (out-of-range indices or malformed offsets would read out of bounds).
#include "core/cage.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

// Throws Error(Status::invalid_mesh) when the cage cannot be subdivided: malformed face
// offsets, no faces, a face with fewer than 3 vertices or a repeated vertex, a vertex index out
// of range, a non-finite position, a crease that is not an edge of the mesh, a corner or hole
// index out of range, a negative or NaN sharpness, an unknown boundary rule.
// Throws Error(Status::limit_exceeded) when counts exceed OpenSubdiv's int indices or its
// valence limit. Non-manifold edges and vertices are accepted (OpenSubdiv 3.x handles them).
void check_cage_for_subdivision(const Cage& cage);

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
