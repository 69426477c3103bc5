#!/usr/bin/env bash
# README command (b), also run by CI (.ci/run): installs the dependencies, builds CageKit and
# runs every test twice — in a Release build (GCC), and in a build with AddressSanitizer +
# UndefinedBehaviorSanitizer (Clang; no leaks, no undefined behaviour allowed) that also runs the
# libFuzzer harnesses — then the concurrency tests under ThreadSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
jobs=$(nproc 2>/dev/null || echo 2)

bash packaging/install-deps.sh

echo "== Release build and tests"
# Tests on and STEP export on explicitly: a build folder first configured by README command (a)
# (tests off, no OpenCASCADE installed then) keeps those cached settings otherwise.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCAGEKIT_BUILD_TESTS=ON -DCAGEKIT_WITH_OCCT=ON
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

echo "== AddressSanitizer + UndefinedBehaviorSanitizer (Clang, libFuzzer's coverage): every test, then the fuzzers"
# One sanitizer build serves both: the tree is compiled once with Clang and
# -fsanitize=address,undefined (CAGEKIT_BUILD_FUZZERS; libFuzzer's coverage only on the libraries
# the harnesses reach, tests/fuzz/CMakeLists.txt), the tests run on it, and the libFuzzer harnesses
# link the same libraries. Line tables only (-gline-tables-only): enough for
# the sanitizers' stack traces, and less to compile and link than full -g.
CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCAGEKIT_BUILD_FUZZERS=ON -DCAGEKIT_BUILD_TESTS=ON \
  "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG"
cmake --build build-asan -j "$jobs"
# intercept_tls_get_addr=0: the sanitizer runtimes before LLVM 17 / GCC 14 can mistake a malloc'd
# dynamic-TLS block (Mesa's llvmpipe, loaded with dlopen by the render and GPU tests) for a
# pre-2.25 glibc header and LeakSanitizer's tracer then dies with "Tracer caught signal 11" at
# exit, at random and with no leak (google/sanitizers#1322). Leak checking stays on.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:detect_stack_use_after_return=1:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizer/lsan.supp"
# Tests with heavy end-to-end cases shrink or skip them here (tests/sanitizer/sanitized_build.h
# tells GCC's and Clang's sanitizer builds apart from Release); those cases run in the Release pass.
ctest --test-dir build-asan --output-on-failure -j "$jobs"

echo "-- libFuzzer smoke: each harness over its regression inputs and seed corpus, then 15 s of fuzzing"
# Known findings would be suppressed in tests/fuzz/ubsan.supp (empty: every finding so far is fixed).
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$root/tests/fuzz/ubsan.supp"
for harness in fuzz_obj fuzz_ply fuzz_off fuzz_draco fuzz_stl fuzz_mesh_api fuzz_binding; do
  # Regression inputs of fixed findings must run clean.
  if [ -d "tests/fuzz/regressions/$harness" ]; then
    build-asan/tests/fuzz/$harness tests/fuzz/regressions/$harness/* >/dev/null 2>&1 ||
      { build-asan/tests/fuzz/$harness tests/fuzz/regressions/$harness/* 2>&1 | tail -n 40;
        echo "test-all: $harness fails on a regression input" >&2; exit 1; }
  fi
done
for harness in fuzz_obj fuzz_ply fuzz_off fuzz_draco fuzz_stl fuzz_mesh_api fuzz_binding; do
  scratch=$(mktemp -d)  # new inputs and any crash reproducer go here, not into the repo
  echo "-- $harness"
  if ! build-asan/tests/fuzz/$harness "$scratch" "tests/fuzz/corpus/$harness" -max_total_time=15 \
      -rss_limit_mb=2048 -max_len=65536 -timeout=30 -artifact_prefix="$scratch/" -print_final_stats=1 \
      >"$scratch/log" 2>&1; then
    tail -n 60 "$scratch/log"
    echo "test-all: $harness found a crash; reproducer(s): $(ls "$scratch"/crash-* "$scratch"/leak-* "$scratch"/timeout-* "$scratch"/oom-* 2>/dev/null)" >&2
    exit 1
  fi
  grep -E 'stat::number_of_executed_units|Done [0-9]+ runs' "$scratch/log" | tail -n 2
  rm -rf "$scratch"
done

echo "== ThreadSanitizer: the concurrency stress test and the C API tests (library + 3 programs only)"
# -g1: function names and line tables for the race reports, without full debug information.
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAGEKIT_SANITIZE_THREAD=ON \
  "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG"
cmake --build build-tsan -j "$jobs" --target stress_concurrency hostile_sizes test_capi
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
# Kernels with high mmap randomisation (vm.mmap_rnd_bits > 28) break older TSan runtimes
# ("unexpected memory mapping"); running without address randomisation avoids that.
tsan_run() { if setarch "$(uname -m)" -R true 2>/dev/null; then setarch "$(uname -m)" -R "$@"; else "$@"; fi; }
tsan_run build-tsan/tests/stress/stress_concurrency 3 6
tsan_run build-tsan/tests/c/test_capi >/dev/null
tsan_run build-tsan/tests/stress/hostile_sizes >/dev/null
echo "test-all: ThreadSanitizer pass clean"
