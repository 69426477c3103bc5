#!/bin/sh
# samples/egl_host renders the dragged scan headless (EGL surfaceless): the run succeeds, prints
# CPU and GPU frames per second, and the PNG it writes is a real image of a shaded surface
# (valid PNG, mostly not background, many distinct shades). Exit 77 (skip) without EGL.
set -u
host="$1"; out="$2"
mkdir -p "$out"
for api in "" "--es"; do
  rm -f "$out/egl_host.png"
  "$host" --frames 8 --size 256 $api --out "$out/egl_host.png" > "$out/log" 2>&1
  status=$?
  cat "$out/log"
  [ $status -eq 77 ] && exit 77
  [ $status -eq 0 ] || { echo "egl_host $api failed ($status)"; exit 1; }
  grep -q "CPU path .* fps .* GPU path .* fps" "$out/log" || { echo "no fps line"; exit 1; }
  python3 - "$out/egl_host.png" <<'PY' || exit 1
import struct, sys, zlib
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
pos, idat, size = 8, b"", None
while pos < len(data):
    length, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + length]
    assert zlib.crc32(kind + body) == struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])[0], "bad CRC"
    if kind == b"IHDR": size = struct.unpack(">II", body[:8])
    if kind == b"IDAT": idat += body
    pos += 12 + length
w, h = size
raw = zlib.decompress(idat)  # checks the Adler-32 too
assert len(raw) == h * (1 + 3 * w), "wrong image size"
pixels = [raw[y * (1 + 3 * w) + 1 + 3 * x: y * (1 + 3 * w) + 4 + 3 * x] for y in range(h) for x in range(w)]
background = pixels[0]
lit = sum(p != background for p in pixels) / len(pixels)
shades = len(set(pixels))
print("png %dx%d: %.1f%% of the pixels show the scan, %d distinct colours" % (w, h, 100 * lit, shades))
assert lit > 0.12, "the image is mostly background"
assert shades > 200, "too few shades for a lit surface"
PY
done
echo "egl_host: both APIs render"
