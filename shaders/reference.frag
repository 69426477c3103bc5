// SPDX-License-Identifier: GPL-3.0-or-later
// The reference mode's program needs a fragment stage to link on GLES; nothing is rasterised.
out vec4 color;
void main() { color = vec4(1.0); }
