#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Reads a PNG (8-bit greyscale, RGB or RGBA, grey + alpha; not interlaced) with the standard
library only (zlib), and checks what the picture tests assert about it.

    png_check.py FILE [--size WxH] [--min-share F] [--max-share F] [--color R,G,B[,N]]... [--no-color R,G,B]...

--size: the image is W x H pixels; --min-share / --max-share: the share of pixels that are not the
background (the top-left pixel's colour) lies in [F_min, F_max]; --color R,G,B[,N]: at least N
(default 1) pixels have that colour (each channel within 1); --no-color R,G,B: no pixel has it. Prints one line of figures; exit 0
when every check holds, 1 when one fails (the line says which), 2 when the file is no valid PNG.
Also imported (read_png) by the other picture tests.
"""
import struct
import sys
import zlib

SIGNATURE = b"\x89PNG\r\n\x1a\n"


class PngError(Exception):
    pass


def read_png(path):
    """(width, height, rows): rows is a list of bytes objects of 4 * width RGBA bytes each."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(SIGNATURE):
        raise PngError("%s: not a PNG (signature)" % path)
    pos, idat, header, ended = 8, [], None, False
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        crc = data[pos + 8 + length:pos + 12 + length]
        if len(body) != length or len(crc) != 4 or struct.unpack(">I", crc)[0] != zlib.crc32(kind + body):
            raise PngError("%s: chunk %r truncated or with a bad CRC" % (path, kind))
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            ended = True
            break
        pos += 12 + length
    if header is None or not ended:
        raise PngError("%s: no IHDR or no IEND" % path)
    width, height, depth, color, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(color)
    if depth != 8 or channels is None or interlace != 0 or width == 0 or height == 0:
        raise PngError("%s: unsupported PNG (depth %d, colour type %d, interlace %d)" % (path, depth, color, interlace))
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    if len(raw) != height * (stride + 1):
        raise PngError("%s: image data of %d bytes, expected %d" % (path, len(raw), height * (stride + 1)))
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        bpp = channels
        if kind == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif kind == 2:
            line = bytearray((a + b) & 255 for a, b in zip(line, previous))
        elif kind == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 255
        elif kind == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = previous[i]
                c = previous[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        elif kind != 0:
            raise PngError("%s: unknown filter %d in row %d" % (path, kind, y))
        previous = line
        if channels == 4:
            rows.append(bytes(line))
        else:
            out = bytearray()
            for x in range(width):
                px = line[x * channels:(x + 1) * channels]
                if channels == 1:
                    out += bytes((px[0], px[0], px[0], 255))
                elif channels == 2:
                    out += bytes((px[0], px[0], px[0], px[1]))
                else:
                    out += bytes(px) + b"\xff"
            rows.append(bytes(out))
    return width, height, rows


def share_not_background(width, height, rows):
    """Share of pixels whose RGB differs from the top-left pixel's."""
    bg = rows[0][0:3]
    other = 0
    for row in rows:
        for x in range(width):
            if row[4 * x:4 * x + 3] != bg:
                other += 1
    return other / float(width * height)


def count_color(width, rows, rgb):
    n = 0
    for row in rows:
        for x in range(width):
            if all(abs(row[4 * x + k] - rgb[k]) <= 1 for k in range(3)):
                n += 1
    return n


def main(argv):
    if not argv:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 64
    path, args = argv[0], argv[1:]
    try:
        width, height, rows = read_png(path)
    except (OSError, PngError, zlib.error, struct.error) as e:
        print("png_check: %s" % e)
        return 2
    share = share_not_background(width, height, rows)
    problems, i = [], 0
    figures = "%s: %d x %d, %.1f %% not background" % (path, width, height, 100 * share)
    while i < len(args):
        option, value = args[i], args[i + 1] if i + 1 < len(args) else ""
        i += 2
        if option == "--size":
            w, h = (int(v) for v in value.lower().split("x"))
            if (width, height) != (w, h):
                problems.append("size %d x %d, not %d x %d" % (width, height, w, h))
        elif option == "--min-share":
            if share < float(value):
                problems.append("%.3f of the pixels not background, below %s" % (share, value))
        elif option == "--max-share":
            if share > float(value):
                problems.append("%.3f of the pixels not background, above %s" % (share, value))
        elif option == "--color":
            parts = [int(v) for v in value.split(",")]
            need = parts[3] if len(parts) > 3 else 1
            n = count_color(width, rows, parts[:3])
            figures += ", %d px of %s" % (n, ",".join(map(str, parts[:3])))
            if n < need:
                problems.append("%d pixels of colour %s, fewer than %d" % (n, parts[:3], need))
        elif option == "--no-color":
            parts = [int(v) for v in value.split(",")]
            n = count_color(width, rows, parts[:3])
            figures += ", %d px of %s" % (n, ",".join(map(str, parts[:3])))
            if n:
                problems.append("%d pixels of colour %s, expected none" % (n, parts[:3]))
        else:
            print("png_check: unknown option %s" % option)
            return 64
    print(figures + ("; " + "; ".join(problems) if problems else ""))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
