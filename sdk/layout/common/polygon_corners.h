// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Corner angles and normals of polygon loops on a surface, shared by the anisotropic remesher's
// convex partition (thesis §5.6.2.1), the quad remesher's fold checks and the remesh quality
// figures (scaled Jacobian).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN

// Interior angle in (0, 2π) at loop[i] about the surface normal there (> π: concave). The
// normal is normals[loop[i]], unless face_normal is non-zero and the vertex normal deviates from
// it by more than 60° (a vertex on a crease, whose normal belongs to the other side): then
// face_normal [J].
double corner_angle(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                    const std::vector<uint32_t>& loop, size_t i, const Vec3& face_normal = Vec3{});

// Unit Newell normal of a loop (zero when degenerate).
Vec3 loop_normal(const std::vector<Vec3>& positions, const std::vector<uint32_t>& loop);

CAGEKIT_NAMESPACE_END
