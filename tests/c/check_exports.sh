#!/bin/sh
# Fails when the shared library exports any dynamic symbol outside cagekit_*.
set -eu
lib="$1"
exported=$(nm -D --defined-only "$lib" | awk '$2 ~ /[TDBRVWiu]/ {print $3}' | sed 's/@.*//' |
           grep -v -E '^(_init|_fini|_edata|_end|__bss_start)$' || true)
bad=$(printf '%s\n' "$exported" | grep -v '^cagekit_' | grep -v '^$' || true)
count=$(printf '%s\n' "$exported" | grep -c '^cagekit_' || true)
if [ -n "$bad" ]; then
  echo "exported symbols outside cagekit_*:"; printf '%s\n' "$bad" | head -20; exit 1
fi
if [ "$count" -lt 40 ]; then echo "only $count cagekit_* symbols exported"; exit 1; fi
echo "$count symbols exported, all cagekit_*"
