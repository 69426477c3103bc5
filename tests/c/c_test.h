/* SPDX-License-Identifier: GPL-3.0-or-later
 * A minimal C99 test harness for the ABI tests: each TEST is a function, CHECK records a failure
 * with file and line and carries on, and run_tests() prints "N passed, N failed". */
#ifndef CAGEKIT_C_TEST_H
#define CAGEKIT_C_TEST_H

#include <stdio.h>
#include <string.h>

typedef void (*c_test_fn)(void);
static int c_test_failures_in_current = 0;

#define CHECK(cond)                                                                 \
  do {                                                                              \
    if (!(cond)) {                                                                  \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);      \
      ++c_test_failures_in_current;                                                 \
    }                                                                               \
  } while (0)

#define CHECK_STATUS(expr, expected)                                                 \
  do {                                                                               \
    cagekit_status c_test_s_ = (expr);                                               \
    if (c_test_s_ != (expected)) {                                                   \
      fprintf(stderr, "%s:%d: %s returned %d (%s), expected %d\n", __FILE__, __LINE__, \
              #expr, (int)c_test_s_, cagekit_status_string(c_test_s_), (int)(expected)); \
      ++c_test_failures_in_current;                                                  \
    }                                                                                \
  } while (0)

#define CHECK_OK(expr) CHECK_STATUS(expr, CAGEKIT_SUCCESS)

typedef struct c_test_case {
  const char* name;
  c_test_fn fn;
} c_test_case;

static int run_tests(const c_test_case* tests, int count) {
  int passed = 0, failed = 0, i;
  for (i = 0; i < count; ++i) {
    c_test_failures_in_current = 0;
    tests[i].fn();
    if (c_test_failures_in_current == 0) {
      ++passed;
      printf("[ OK   ] %s\n", tests[i].name);
    } else {
      ++failed;
      printf("[ FAIL ] %s\n", tests[i].name);
    }
  }
  printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}

#endif
