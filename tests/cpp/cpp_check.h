// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The C++ layer's tests count failed checks and go on (each test's main returns the count):
// CHECK(condition) prints the file, line and condition of a failure.
#include <cstdio>

namespace {

int g_failures = 0;

#define CHECK(condition)                                                                   \
  do {                                                                                     \
    if (!(condition)) {                                                                    \
      std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #condition); \
      ++g_failures;                                                                        \
    }                                                                                      \
  } while (0)

}  // namespace
