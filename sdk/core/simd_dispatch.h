// SPDX-License-Identifier: GPL-3.0-or-later
// Run-time choice of a wider vector unit for a hot numeric loop.
//
// CAGEKIT_VECTOR_CLONES before a function definition makes the compiler emit an AVX2 copy next to
// the baseline (SSE2) one and pick between them once, at load time (GNU ifunc), on x86-64
// GCC/Clang builds for glibc; elsewhere it expands to nothing. AVX2 without FMA: the clone does
// the same IEEE operations in the same order, only four doubles at a time instead of two, so its
// results are bit for bit those of the baseline (no contraction into fused multiply-adds, which
// the "avx2" target alone does not allow). Use it only on loops the compiler vectorises and whose
// callers do not depend on the choice; it is measured in tests/bench/RESULTS.md.
//
// Not under ThreadSanitizer: the ifunc resolver runs while the dynamic loader relocates the
// library, before TSan's runtime is set up, and its instrumented code crashed every TSan program
// that loaded libcagekit (SIGSEGV in _dl_relocate_object, test-all.sh's TSan pass).
#pragma once

#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define CAGEKIT_THREAD_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_THREAD__)
#define CAGEKIT_THREAD_SANITIZER 1
#endif

#if defined(__x86_64__) && defined(__GNUC__) && defined(__gnu_linux__) && !defined(CAGEKIT_NO_VECTOR_CLONES) && \
    !defined(CAGEKIT_THREAD_SANITIZER)
#define CAGEKIT_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define CAGEKIT_VECTOR_CLONES
#endif
