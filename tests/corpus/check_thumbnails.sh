#!/bin/sh
# corpus_harness --thumbnails (issue 24) on three generated inputs (a triangulated box, a sphere,
# a corrupt OBJ), method simplify: exit 0; OUT/index.html has one table row per record, every
# row's links resolve to a valid PNG (its 240 x 200 thumbnail and its page); drawn thumbnails
# cover a plausible share of the tile and carry the error map's colours; the corrupt input's row
# links to a placeholder. Runs without the corpus. Exit 77 when no thumbnail can be drawn here
# (no headless EGL) after checking the placeholders and links.
# usage: check_thumbnails.sh CORPUS_HARNESS CAGEKIT PNG_CHECK_PY
set -u
harness="$1"; cli="$2"; png="$3"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/env python3 - "$tmp" <<'PY'
import math, sys
out = sys.argv[1]
def write(name, pts, tris):
    with open("%s/%s" % (out, name), "w") as f:
        f.writelines("v %.6f %.6f %.6f\n" % p for p in pts)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in tris)
# A 2 x 1.4 x 1 box, each side a grid of 0.2 cells, two triangles each, welded, outward.
index, pts, tris = {}, [], []
def v(p):
    key = tuple(round(c * 10) for c in p)
    if key not in index:
        index[key] = len(pts); pts.append(p)
    return index[key]
size = (2.0, 1.4, 1.0)
for axis in range(3):
    a, b = (axis + 1) % 3, (axis + 2) % 3
    na, nb = round(size[a] / 0.2), round(size[b] / 0.2)
    for side in (0, 1):
        for i in range(na):
            for j in range(nb):
                q = []
                for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    p = [0.0, 0.0, 0.0]
                    p[axis] = size[axis] * side; p[a] = size[a] * (i + di) / na; p[b] = size[b] * (j + dj) / nb
                    q.append(v(tuple(p)))
                tris += [(q[0], q[1], q[2]), (q[0], q[2], q[3])] if side else [(q[0], q[2], q[1]), (q[0], q[3], q[2])]
write("box.obj", pts, tris)
# A lat-long sphere.
rings, segs = 16, 32
pts = [(0.0, 0.0, 1.0)] + [(math.sin(math.pi * r / rings) * math.cos(2 * math.pi * k / segs),
                            math.sin(math.pi * r / rings) * math.sin(2 * math.pi * k / segs),
                            math.cos(math.pi * r / rings)) for r in range(1, rings) for k in range(segs)] + [(0.0, 0.0, -1.0)]
tris = [(0, 1 + k, 1 + (k + 1) % segs) for k in range(segs)]
for r in range(rings - 2):
    for k in range(segs):
        a, b = 1 + r * segs + k, 1 + r * segs + (k + 1) % segs
        tris += [(a, a + segs, b + segs), (a, b + segs, b)]
last = len(pts) - 1
tris += [(last, 1 + (rings - 2) * segs + (k + 1) % segs, 1 + (rings - 2) * segs + k) for k in range(segs)]
write("sphere.obj", pts, tris)
open("%s/corrupt.obj" % out, "w").write("v 0 0 0\nf 1 2 oops\n")
PY

"$harness" --cli "$cli" --out "$tmp/out" --methods simplify --jobs 2 --thumbnails --summary-only \
  "$tmp/box.obj" "$tmp/sphere.obj" "$tmp/corrupt.obj" >"$tmp/log" 2>&1
code=$?
cat "$tmp/log"
[ "$code" -eq 0 ] || { echo "FAIL: corpus_harness --thumbnails exited $code"; exit 1; }

/usr/bin/env python3 - "$png" "$tmp/out" <<'PY'
import os, re, sys
sys.path.insert(0, os.path.dirname(sys.argv[1]))
from png_check import read_png, share_not_background, count_color
out = sys.argv[2]
failures = []
def check(ok, what):
    print("[ %s ] %s" % ("OK  " if ok else "FAIL", what))
    if not ok:
        failures.append(what)
html = open(os.path.join(out, "index.html"), encoding="utf-8").read()
rows = re.findall(r'<tr id="r\d+">(.*?)</tr>', html, re.S)
check(len(rows) == 3, "index.html: one table row per record (%d)" % len(rows))
drawn, cache = 0, {}
def png_of(path):
    if path not in cache:
        cache[path] = read_png(path)
    return cache[path]
for row in rows:
    cells = re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)
    mesh, status = cells[1], cells[3]
    links = re.findall(r'href="([^"]+)"', row)
    check(len(links) == 2, "%s: a picture link and a page link" % mesh)
    for link in links:
        path = os.path.join(out, link)
        try:
            w, h, px = png_of(path)
        except Exception as e:  # noqa: BLE001
            check(False, "%s: %s is a valid PNG (%s)" % (mesh, link, e)); continue
        if "page-" in link:
            check((w, h) == (1200, 1200), "%s: its page %s is a 1200 x 1200 PNG" % (mesh, link))
            continue
        check((w, h) == (240, 200), "%s: %s is a 240 x 200 PNG" % (mesh, link))
        placeholder = ">placeholder<" in row
        if mesh.endswith("corrupt.obj"):
            check(status == "clean error" and placeholder, "corrupt input: clean error, placeholder picture")
        elif not placeholder:
            drawn += 1
            share = share_not_background(w, h, px)
            check(0.05 < share < 0.8, "%s: %.1f %% of the thumbnail drawn" % (mesh, 100 * share))
            check(count_color(w, px, (253, 231, 37)) > 0, "%s: the error map's legend (viridis yellow)" % mesh)
check(html.count('<img src="thumbnails/page-') == 1, "index.html shows the page")
if failures:
    print("%d failed" % len(failures)); sys.exit(1)
if drawn == 0:
    print("SKIP: no thumbnail could be drawn here (placeholders checked)"); sys.exit(77)
print("all passed (%d thumbnails drawn)" % drawn)
PY
