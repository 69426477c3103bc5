/* Which sanitizer this translation unit is compiled with, for GCC and Clang alike (C and C++).
 *
 * GCC defines __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__; Clang 14 defines neither and answers
 * __has_feature(address_sanitizer) / __has_feature(thread_sanitizer) instead. Tests that shrink or
 * skip heavy cases under the sanitizers test these macros, never the compiler's own:
 *   CAGEKIT_ASAN_BUILD       1 under AddressSanitizer, else 0
 *   CAGEKIT_TSAN_BUILD       1 under ThreadSanitizer, else 0
 *   CAGEKIT_SANITIZED_BUILD  1 under either, else 0 */
#ifndef CAGEKIT_TESTS_SANITIZED_BUILD_H
#define CAGEKIT_TESTS_SANITIZED_BUILD_H

#if defined(__SANITIZE_ADDRESS__)
#define CAGEKIT_ASAN_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CAGEKIT_ASAN_BUILD 1
#endif
#endif
#ifndef CAGEKIT_ASAN_BUILD
#define CAGEKIT_ASAN_BUILD 0
#endif

#if defined(__SANITIZE_THREAD__)
#define CAGEKIT_TSAN_BUILD 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define CAGEKIT_TSAN_BUILD 1
#endif
#endif
#ifndef CAGEKIT_TSAN_BUILD
#define CAGEKIT_TSAN_BUILD 0
#endif

#define CAGEKIT_SANITIZED_BUILD (CAGEKIT_ASAN_BUILD || CAGEKIT_TSAN_BUILD)

#endif
