// SPDX-License-Identifier: GPL-3.0-or-later
// The thesis's own GPU path (§8.6 (a)-(c)), kept as a reference mode for the benchmark: all data
// as vertex attributes, 16 + 3|Q| floats per vertex for the set Q of edited control points, a
// vertex program specialised for |Q| (the library prepends the #version line and
//   #define REFERENCE_Q       |Q|
//   #define REFERENCE_INPUTS  layout(location = 5) in vec3 a_w0; ... (one per point of Q)
//   #define REFERENCE_SUM     s += a_w0.x * u_q[0]; su += a_w0.y * u_q[0]; sv += ... (unrolled)
// so that there is no loop or branch over Q, as in the thesis). Position (8.1) and approximate
// normal (8.11)-(8.12) go to transform feedback (interleaved, the compute path's layout).

layout(location = 0) in vec4 a_coef0;  // D, alpha_u, beta_u, gamma_u
layout(location = 1) in vec3 a_coef1;  // alpha_v, beta_v, gamma_v
layout(location = 2) in vec3 a_s;      // sum over the control points not in Q of phi_j c_j
layout(location = 3) in vec3 a_su;     // ... of dphi_j/du c_j
layout(location = 4) in vec3 a_sv;     // ... of dphi_j/dv c_j
REFERENCE_INPUTS                       // (phi_j, dphi_j/du, dphi_j/dv) per point j of Q

uniform vec3 u_q[REFERENCE_Q];  // the positions of Q: 3|Q| floats per frame

out vec3 v_position;
out vec3 v_normal;

void main() {
  vec3 s = a_s, su = a_su, sv = a_sv;
  REFERENCE_SUM
  vec3 cr = cross(su, sv);
  float cl = length(cr);
  vec3 ns = cl > 0.0 ? cr / cl : vec3(0.0, 0.0, 1.0);
  v_position = s + a_coef0.x * ns;
  vec3 gu = a_coef0.y * su + a_coef0.z * sv + a_coef0.w * ns;
  vec3 gv = a_coef1.x * su + a_coef1.y * sv + a_coef1.z * ns;
  vec3 g = cross(gu, gv);
  float glen = length(g);
  v_normal = glen > 0.0 ? g / glen : vec3(0.0);
  gl_Position = vec4(0.0);  // nothing is rasterised (GL_RASTERIZER_DISCARD)
}
