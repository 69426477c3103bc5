#!/bin/sh
# The sdk/ folders are layered: each may include only itself and the folders below it.
# Order, lowest first: core -> subdiv -> layout -> fit -> pipeline -> multires -> gpu -> capi. Fails on any include that goes upward.
set -u
sdk="$1"
order="core subdiv layout fit pipeline multires gpu capi"
status=0
rank() { i=0; for l in $order; do [ "$l" = "$1" ] && { echo $i; return; }; i=$((i + 1)); done; echo 99; }
for layer in $order; do
  mine=$(rank "$layer")
  for file in $(find "$sdk/$layer" -name '*.h' -o -name '*.cpp'); do
    for inc in $(sed -n 's/^#include "\([a-z_]*\)\/.*"/\1/p' "$file"); do
      if [ "$(rank "$inc")" -gt "$mine" ]; then
        echo "$file includes $inc/ which is above $layer/"; status=1
      fi
    done
  done
done
[ $status -eq 0 ] && echo "layering respected: $order"
exit $status
