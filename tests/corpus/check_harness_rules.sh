#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The harness's classification and its baseline rules (README.md), on fake_cagekit.sh: each status
# class is recognised, a baseline written from a run passes against the same results (known
# problems only warn), a result worse than the baseline fails, and the crease figures and mesh
# classes come out as expected on cube cages.
# usage: check_harness_rules.sh CORPUS_HARNESS FAKE_CLI SCRATCH_DIR
set -u
harness=$1
cli=$2
dir=$3
rm -rf "$dir"
mkdir -p "$dir/meshes"
fail() { echo "check_harness_rules: $*" >&2; exit 1; }
cube() {
  printf 'OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n' > "$1"
  printf '3 0 2 1\n3 0 3 2\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n3 4 5 6\n3 4 6 7\n' >> "$1"
}
for name in good crash error throw oom holes nodeform hang; do cube "$dir/meshes/${name}_cube.off"; done
status_of() {  # status_of RESULTS.json MESH-PREFIX (results.json holds one record per line)
  grep "{\"mesh\": \"[^\"]*/$2_cube.off\"" "$1" | sed 's/.*"status": "\([^"]*\)".*/\1/'
}

# 1. Every class, with a 2 s limit for the hang.
"$harness" --cli "$cli" --out "$dir/all" --methods simplify --timeout 2 --jobs 3 --summary-only "$dir/meshes" \
  > "$dir/all.log" 2>&1 || { cat "$dir/all.log"; fail "a run without baseline must exit 0"; }
for pair in good:good crash:crash error:"clean error" throw:crash oom:"out of memory" holes:bad-but-OK \
            nodeform:bad-but-OK hang:timeout; do
  mesh=${pair%%:*}
  want=${pair#*:}
  got=$(status_of "$dir/all/results.json" "$mesh")
  [ "$got" = "$want" ] || fail "$mesh: status '$got', expected '$want'"
done
grep -q 'simplify: 1 good, 1 clean errors, 2 bad-but-OK, 2 crashes, 1 timeouts, 1 oom (good rate 14.3 % of 7 meshes with a surface)' \
  "$dir/all.log" || { cat "$dir/all.log"; fail "wrong summary line"; }
grep -q '"digest": "[0-9a-f]\{16\}"' "$dir/all/results.json" || fail "no digest in results.json"
grep -q '^| good_cube.off\|meshes/good_cube.off' "$dir/all/results.md" || grep -q 'good_cube.off | good |' "$dir/all/results.md" ||
  fail "results.md lacks the good record"
rm -f "$dir/meshes/hang_cube.off"

# 2. A baseline from a run; the same results against it pass, with a warning for known problems.
"$harness" --cli "$cli" --out "$dir/base" --methods simplify --summary-only --write-baseline "$dir/baseline.json" \
  "$dir/meshes" > "$dir/base.log" 2>&1 || { cat "$dir/base.log"; fail "writing the baseline failed"; }
"$harness" --cli "$cli" --out "$dir/same" --methods simplify --summary-only --baseline "$dir/baseline.json" \
  "$dir/meshes" > "$dir/same.log" 2>&1 || { cat "$dir/same.log"; fail "unchanged results must pass the baseline"; }
grep -q 'WARNING' "$dir/same.log" || fail "known problems must be warned about"
grep -q 'KNOWN .*crash_cube.off simplify: crash' "$dir/same.log" || fail "the known crash is not listed"

# 3. Worse than the baseline fails: a good mesh that now crashes ...
sed -e 's/"mesh": "\([^"]*\)crash_cube.off", "method": "simplify", "status": "crash"/"mesh": "\1crash_cube.off", "method": "simplify", "status": "good"/' \
    -e 's/"min_good": 1,/"min_good": 2,/' "$dir/baseline.json" > "$dir/was_good.json"
cmp -s "$dir/baseline.json" "$dir/was_good.json" && fail "could not edit the baseline"
if "$harness" --cli "$cli" --out "$dir/regressed" --methods simplify --summary-only --baseline "$dir/was_good.json" \
     "$dir/meshes" > "$dir/regressed.log" 2>&1; then
  cat "$dir/regressed.log"; fail "a good mesh that now crashes must fail"
fi
grep -q 'regression: .*crash_cube.off simplify: crash' "$dir/regressed.log" || { cat "$dir/regressed.log"; fail "no regression line"; }
grep -q 'below the baseline' "$dir/regressed.log" || fail "the good count below the baseline must be reported"
# ... a new bad-but-OK where the baseline had a clean error ...
sed 's/"mesh": "\([^"]*\)holes_cube.off", "method": "simplify", "status": "bad-but-OK"/"mesh": "\1holes_cube.off", "method": "simplify", "status": "clean error"/' \
  "$dir/baseline.json" > "$dir/was_error.json"
cmp -s "$dir/baseline.json" "$dir/was_error.json" && fail "could not edit the baseline"
if "$harness" --cli "$cli" --out "$dir/new_bad" --methods simplify --summary-only --baseline "$dir/was_error.json" \
     "$dir/meshes" > "$dir/new_bad.log" 2>&1; then
  cat "$dir/new_bad.log"; fail "a new bad-but-OK result must fail"
fi
grep -q 'new .*holes_cube.off simplify: bad-but-OK' "$dir/new_bad.log" || { cat "$dir/new_bad.log"; fail "no 'new' line"; }
# ... and a crash on a mesh the baseline does not have.
cube "$dir/meshes/crash2_cube.off"
if "$harness" --cli "$cli" --out "$dir/unknown" --methods simplify --summary-only --baseline "$dir/baseline.json" \
     "$dir/meshes" > "$dir/unknown.log" 2>&1; then
  cat "$dir/unknown.log"; fail "a crash on a mesh outside the baseline must fail"
fi
grep -q 'new .*crash2_cube.off simplify: crash (signal 11' "$dir/unknown.log" || { cat "$dir/unknown.log"; fail "no line for the unknown crash"; }
grep -q 'simplify: 3 crashes, more than the baseline.s 2' "$dir/unknown.log" || { cat "$dir/unknown.log"; fail "no line for the crash count"; }
# 4. Crease figures and classes (README "Crease figures"). The fake's cube cage has no crease
# tags and no limit.obj: figures from cage.obj (noted), recall 0 against the cube scan's 12 sharp
# edges, precision n/a. A wrapper that tags all 12 cube edges and writes the cage as limit.obj too
# gives precision, recall and crease density 100 %, from limit.obj; on the open cage (holes*)
# the 4 tags on its boundary are left out of precision and recall.
rm -f "$dir/meshes/crash2_cube.off"
mkdir -p "$dir/creased"
cube "$dir/creased/creased_cube.off"
cube "$dir/creased/holes_creased_cube.off"
cat > "$dir/creasing_cagekit.sh" <<EOF
#!/bin/sh
sh "$cli" "\$@" || exit \$?
if [ "\$1" = pipeline ]; then
  for e in "0 1" "1 2" "2 3" "3 0" "4 5" "5 6" "6 7" "7 4" "0 4" "1 5" "2 6" "3 7"; do
    echo "t crease 2/1/0 \$e 10" >> "\$3/cage.obj"
  done
  cp "\$3/cage.obj" "\$3/limit.obj"
fi
EOF
chmod +x "$dir/creasing_cagekit.sh"
printf '# test classes\ncad %s\norganic %s # comment\n' "$dir/meshes/good_cube.off" "$dir/creased/creased_cube.off" \
  > "$dir/classes.txt"
"$harness" --cli "$cli" --out "$dir/classes" --methods simplify --classes "$dir/classes.txt" --summary-only \
  "$dir/meshes" > "$dir/classes.log" 2>&1 || { cat "$dir/classes.log"; fail "the run with --classes failed"; }
record_of() { grep "{\"mesh\": \"[^\"]*/$2_cube.off\"" "$1"; }
record_of "$dir/classes/results.json" good | grep -q '"class": "cad", "crease_precision_pct": null, "crease_recall_pct": 0.00, "crease_density_pct": 0.00, "crease_source": "cage.obj", "crease_note": "no limit.obj: creases of cage.obj", "crease_edges": 0, "boundary_crease_edges": 0, "sharp_input_edges": 12,' ||
  { record_of "$dir/classes/results.json" good; fail "wrong crease figures for the untagged cube"; }
record_of "$dir/classes/results.json" crash | grep -q '"class": "", "crease_precision_pct": null, "crease_recall_pct": null, "crease_density_pct": null, "crease_source": null' ||
  fail "a crash must have no crease figures"
grep -q '^simplify creases, CAD: 1 meshes (1 measured): precision n/a recall 0.0 % (length-weighted; medians n/a / 0.0 %), crease density median 0.0 % (max 0.0 %), fit two-sided median 2.00 % (1 good)$' \
  "$dir/classes.log" || { cat "$dir/classes.log"; fail "wrong CAD crease line"; }
"$harness" --cli "$dir/creasing_cagekit.sh" --out "$dir/creased_run" --methods simplify --classes "$dir/classes.txt" \
  --summary-only "$dir/creased" > "$dir/creased.log" 2>&1 || { cat "$dir/creased.log"; fail "the creased run failed"; }
record_of "$dir/creased_run/results.json" creased | grep -q '"status": "good".*"class": "organic", "crease_precision_pct": 100.00, "crease_recall_pct": 100.00, "crease_density_pct": 100.00, "crease_source": "limit.obj", "crease_note": null, "crease_edges": 12, "boundary_crease_edges": 0, "sharp_input_edges": 12,' ||
  { record_of "$dir/creased_run/results.json" creased; fail "wrong crease figures for the creased cube"; }
record_of "$dir/creased_run/results.json" holes_creased | grep -q '"class": "", "crease_precision_pct": 100.00, .*"crease_edges": 8, "boundary_crease_edges": 4, "sharp_input_edges": 12,' ||
  { record_of "$dir/creased_run/results.json" holes_creased; fail "wrong crease figures for the open creased cube"; }
grep -q '^simplify creases, organic: 1 meshes (1 measured): precision 100.0 % recall 100.0 %' "$dir/creased.log" ||
  { cat "$dir/creased.log"; fail "wrong organic crease line"; }
grep -q 'creased_cube.off | good | organic |' "$dir/creased_run/results.md" || fail "results.md lacks the class column"
printf 'round cgal/bunny00.off\n' > "$dir/bad_classes.txt"
if "$harness" --cli "$cli" --out "$dir/bad_classes" --classes "$dir/bad_classes.txt" "$dir/creased" \
     > "$dir/bad_classes.log" 2>&1; then
  fail "a malformed classes file must fail"
fi
grep -q "bad_classes.txt:1: expected 'cad PATH' or 'organic PATH'" "$dir/bad_classes.log" ||
  { cat "$dir/bad_classes.log"; fail "no message for the bad classes file"; }
echo "check_harness_rules: all rules hold"
