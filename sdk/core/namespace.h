// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Versioned inline namespace (as OpenSubdiv's OPENSUBDIV_VERSION): two builds of CageKit
// loaded into one host process (Blender + a plugin) never share C++ symbols.
#define CAGEKIT_NAMESPACE_BEGIN namespace cagekit { inline namespace v0 {
#define CAGEKIT_NAMESPACE_END } }
