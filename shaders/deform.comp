// SPDX-License-Identifier: GPL-3.0-or-later
// GPU deformer of CageKit (thesis §8.5-8.6, modern SSBO path of spec §3.2): one invocation per
// scan vertex rebuilds S, S_u, S_v from the sparse basis rows (8.3) and the current control
// points, the position (8.1) or the local-frame offset, and the approximate normal
// (8.11)-(8.12). The library prepends "#version 430 core" or "#version 310 es" + precision.
// Same arithmetic as sdk/multires/cpu_deformer.cpp (finish_vertex), in float32.
//
// Buffers (std430; 4 storage blocks = the GLES 3.1 minimum per compute shader):
//   0 control:  3 floats per control point, updated every frame
//   1 entries:  4 words per basis entry: control index, then phi, phi_u, phi_v as float bits
//   2 vertices: 12 words per vertex: row begin, row end, then D, a, b, alpha_u, beta_u,
//               gamma_u, alpha_v, beta_v, gamma_v as float bits, 1 pad word
//   3 output:   6 floats per vertex: position xyz, normal xyz (interleaved vertex attributes)

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Control { float control[]; };
layout(std430, binding = 1) readonly buffer Entries { uint entries[]; };
layout(std430, binding = 2) readonly buffer Vertices { uint vertices[]; };
layout(std430, binding = 3) writeonly buffer Output { float outputs[]; };

uniform uint u_vertex_count;
uniform int u_local_frame;  // 0: D along N_S (8.1); 1: a T1 + b T2 + c N_S

vec3 control_point(uint j) { return vec3(control[3u * j], control[3u * j + 1u], control[3u * j + 2u]); }
float word(uint i) { return uintBitsToFloat(vertices[i]); }

void main() {
  uint i = gl_WorkGroupID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (i >= u_vertex_count) return;
  uint base = 12u * i;
  uint begin = vertices[base], end = vertices[base + 1u];
  vec3 s = vec3(0.0), su = vec3(0.0), sv = vec3(0.0);
  for (uint e = begin; e < end; ++e) {
    uint k = 4u * e;
    vec3 c = control_point(entries[k]);
    s += uintBitsToFloat(entries[k + 1u]) * c;
    su += uintBitsToFloat(entries[k + 2u]) * c;
    sv += uintBitsToFloat(entries[k + 3u]) * c;
  }
  vec3 cr = cross(su, sv);
  float cl = length(cr);
  vec3 ns = cl > 0.0 ? cr / cl : vec3(0.0, 0.0, 1.0);
  float d = word(base + 2u);
  vec3 p;
  if (u_local_frame != 0) {
    float lu = length(su);
    vec3 t1 = lu > 0.0 ? su / lu : vec3(0.0);
    vec3 t2 = cross(ns, t1);
    p = s + word(base + 3u) * t1 + word(base + 4u) * t2 + d * ns;
  } else {
    p = s + d * ns;
  }
  vec3 gu = word(base + 5u) * su + word(base + 6u) * sv + word(base + 7u) * ns;
  vec3 gv = word(base + 8u) * su + word(base + 9u) * sv + word(base + 10u) * ns;
  vec3 g = cross(gu, gv);
  float gl = length(g);
  vec3 n = gl > 0.0 ? g / gl : vec3(0.0);
  uint o = 6u * i;
  outputs[o] = p.x; outputs[o + 1u] = p.y; outputs[o + 2u] = p.z;
  outputs[o + 3u] = n.x; outputs[o + 4u] = n.y; outputs[o + 5u] = n.z;
}
