#!/bin/sh
# The sdk/ folders form a DAG of layers: a folder may include itself and folders of lower layers
# only; folders of the same layer are siblings and never include each other. Layers, lowest first
# (siblings joined by '|'):
#   core -> core/io | subdiv -> layout/common -> layout/simplify | layout/anisotropic | layout/quad
#   -> fit -> pipeline -> multires -> gpu | render -> capi
# Fails on any include that goes upward, sideways, or into a folder not listed here.
set -u
sdk="$1"
layers="core core/io|subdiv layout/common layout/simplify|layout/anisotropic|layout/quad fit pipeline multires gpu|render capi"
status=0
rank() {
  i=0
  for layer in $layers; do
    case "|$layer|" in *"|$1|"*) echo $i; return ;; esac
    i=$((i + 1))
  done
  echo 99
}
folders=$(echo "$layers" | tr ' |' '\n\n')
for folder in $folders; do
  mine=$(rank "$folder")
  [ -d "$sdk/$folder" ] || { echo "missing folder $sdk/$folder"; status=1; continue; }
  for file in $(find "$sdk/$folder" -maxdepth 1 -name '*.h' -o -maxdepth 1 -name '*.cpp'); do
    for inc in $(sed -n 's/^#include "\([a-z_/]*\)\/[a-z0-9_]*\.h"/\1/p' "$file"); do
      [ "$inc" = "$folder" ] && continue
      theirs=$(rank "$inc")
      if [ "$theirs" -ge "$mine" ]; then
        if [ "$theirs" -eq "$mine" ]; then
          echo "$file includes $inc/, a sibling of $folder/"
        else
          echo "$file includes $inc/, which is not below $folder/"
        fi
        status=1
      fi
    done
  done
done
# Every source file lies in a listed folder.
for file in $(find "$sdk" -name '*.h' -o -name '*.cpp'); do
  dir=$(dirname "${file#"$sdk"/}")
  if [ "$(rank "$dir")" -eq 99 ]; then echo "$file is in $dir/, which is not a listed layer"; status=1; fi
done
[ $status -eq 0 ] && echo "layering respected: $layers"
exit $status
