#!/usr/bin/env bash
# README command (b), also run by CI (.ci/run): installs the dependencies, builds CageKit and
# runs every test twice — in a Release build, and in a build with AddressSanitizer +
# UndefinedBehaviorSanitizer (no leaks, no undefined behaviour allowed).
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

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build and tests"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAGEKIT_SANITIZE=ON
cmake --build build-asan -j "$jobs"
# intercept_tls_get_addr=0: GCC 12's sanitizer runtime can mistake a malloc'd dynamic-TLS block
# (Mesa's llvmpipe, loaded with dlopen by the render and GPU tests) for a pre-2.25 glibc header
# and LeakSanitizer's tracer then dies with "Tracer caught signal 11" at exit, at random and
# with no leak (google/sanitizers#1322; fixed in GCC 14 / LLVM 17). Leak checking stays on.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:detect_stack_use_after_return=1:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizer/lsan.supp"
ctest --test-dir build-asan --output-on-failure -j "$jobs"

echo "== libFuzzer smoke (clang, ASan + UBSan): each harness over its seed corpus, then 15 s of fuzzing"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCAGEKIT_BUILD_FUZZERS=ON -DCAGEKIT_BUILD_TESTS=ON
cmake --build build-fuzz -j "$jobs" --target cagekit_fuzzers
# Known findings would be suppressed in tests/fuzz/ubsan.supp (empty: every finding so far is fixed).
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$root/tests/fuzz/ubsan.supp"
for harness in fuzz_obj fuzz_ply fuzz_off fuzz_draco fuzz_stl fuzz_mesh_api fuzz_binding; do
  # Regression inputs of fixed findings must run clean.
  if [ -d "tests/fuzz/regressions/$harness" ]; then
    build-fuzz/tests/fuzz/$harness tests/fuzz/regressions/$harness/* >/dev/null 2>&1 ||
      { build-fuzz/tests/fuzz/$harness tests/fuzz/regressions/$harness/* 2>&1 | tail -n 40;
        echo "test-all: $harness fails on a regression input" >&2; exit 1; }
  fi
done
for harness in fuzz_obj fuzz_ply fuzz_off fuzz_draco fuzz_stl fuzz_mesh_api fuzz_binding; do
  scratch=$(mktemp -d)  # new inputs and any crash reproducer go here, not into the repo
  echo "-- $harness"
  if ! build-fuzz/tests/fuzz/$harness "$scratch" "tests/fuzz/corpus/$harness" -max_total_time=15 \
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
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAGEKIT_SANITIZE_THREAD=ON
cmake --build build-tsan -j "$jobs" --target stress_concurrency hostile_sizes test_capi
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"
# Kernels with high mmap randomisation (vm.mmap_rnd_bits > 28) break older TSan runtimes
# ("unexpected memory mapping"); running without address randomisation avoids that.
tsan_run() { if setarch "$(uname -m)" -R true 2>/dev/null; then setarch "$(uname -m)" -R "$@"; else "$@"; fi; }
tsan_run build-tsan/tests/stress/stress_concurrency 3 6
tsan_run build-tsan/tests/c/test_capi >/dev/null
tsan_run build-tsan/tests/stress/hostile_sizes >/dev/null
echo "test-all: ThreadSanitizer pass clean"
