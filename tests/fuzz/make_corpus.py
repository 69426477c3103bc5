#!/usr/bin/env python3
# Regenerates the seed corpora under tests/fuzz/corpus/ (small synthetic files only).
# usage: make_corpus.py CAGEKIT_CLI   (the `cagekit` CLI of any build, used for PLY/OFF/DRC)
import os, shutil, struct, subprocess, sys, tempfile

here = os.path.dirname(os.path.abspath(__file__))
cli = sys.argv[1]
corpus = os.path.join(here, "corpus")

CUBE_V = [(0,0,0),(1,0,0),(0,1,0),(1,1,0),(0,0,1),(1,0,1),(0,1,1),(1,1,1)]
CUBE_F = [(1,3,4,2),(5,6,8,7),(1,2,6,5),(3,7,8,4),(1,5,7,3),(2,4,8,6)]
TAGS = """t crease 2/1/0 0 1 10
t crease 2/1/0 2 3 10
t crease 2/1/0 0 4 10
t crease 2/1/0 3 7 2.5
t corner 1/1/0 0 10
t corner 1/1/0 7 3
t hole 1/0/0 5
"""

def obj(vs, fs, tags=""):
    s = "".join("v %g %g %g\n" % v for v in vs)
    s += "".join("f " + " ".join(str(i) for i in f) + "\n" for f in fs)
    return s + tags

def tri_fan(fs):
    return [(f[0], f[i], f[i+1]) for f in fs for i in range(1, len(f) - 1)]

def put(harness, name, data):
    d = os.path.join(corpus, harness); os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as fh:
        fh.write(data.encode() if isinstance(data, str) else data)

def main():
    shutil.rmtree(corpus, ignore_errors=True)
    tmp = tempfile.mkdtemp()
    sources = {
        "cube_tags": obj(CUBE_V, CUBE_F, TAGS),
        "cube": obj(CUBE_V, CUBE_F),
        "cube_tri": obj(CUBE_V, tri_fan(CUBE_F)),
        "open_quad": obj(CUBE_V[:4], [(1,2,4,3)]),
    }
    for name, text in sources.items():
        put("fuzz_obj", name + ".obj", text)
        with open(os.path.join(tmp, name + ".obj"), "w") as fh: fh.write(text)
    # OBJ variants: negative indices, v/vt/vn faces, comments, groups, bad input
    put("fuzz_obj", "slashes.obj", "# c\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng a\nf 1/1/1 2/1/1 3/1/1\n")
    put("fuzz_obj", "negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n")
    put("fuzz_obj", "bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    put("fuzz_obj", "bad_tag.obj", obj(CUBE_V, CUBE_F, "t crease 2/1/0 0 7 10\nt corner 1/1/0 99 1\nt hole 1/0/0 -1\n"))
    put("fuzz_obj", "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    # PLY / OFF / DRC via the CLI writers
    for name in sources:
        src = os.path.join(tmp, name + ".obj")
        for ext, extra, harness, out in ((".ply", [], "fuzz_ply", name + "_bin.ply"),
                                          (".ply", ["--ascii"], "fuzz_ply", name + "_ascii.ply"),
                                          (".off", [], "fuzz_off", name + ".off"),
                                          (".drc", [], "fuzz_draco", name + ".drc"),
                                          (".drc", ["--bits", "8"], "fuzz_draco", name + "_8bit.drc")):
            dst = os.path.join(tmp, out)
            subprocess.run([cli, "convert", src, dst, "--quiet"] + extra, check=True)
            with open(dst, "rb") as fh: put(harness, out, fh.read())
    # hand-written PLY: big endian binary, extra properties, list of uchar/int, bad counts
    hdr = ("ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n")
    body = b"".join(struct.pack(">fffB", *v, 7) for v in CUBE_V[:3]) + struct.pack(">Biii", 3, 0, 1, 2)
    put("fuzz_ply", "be_color.ply", hdr.encode() + body)
    put("fuzz_ply", "huge_count.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\n"
        "property float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n")
    # hand-written PLY triangle strips (tristrips element, -1 restarts, a degenerate swap), ascii
    # and binary with unsigned indices (-1 stored as 0xFFFFFFFF) next to a face element
    grid = [(x, y, 0) for y in range(3) for x in range(3)]
    strips = [3, 0, 4, 1, 1, 4, 4, 1, 5, 2, -1, 6, 3, 7, 4, 8, 5]
    put("fuzz_ply", "tristrips_ascii.ply",
        "ply\nformat ascii 1.0\nelement vertex 9\nproperty float x\nproperty float y\nproperty float z\n"
        "element tristrips 1\nproperty list int int vertex_indices\nend_header\n" +
        "".join("%d %d %d\n" % v for v in grid) + " ".join(str(i) for i in [len(strips)] + strips) + "\n")
    hdr = ("ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
           "element tristrips 1\nproperty list int uint vertex_indices\nend_header\n")
    body = b"".join(struct.pack("<fff", *v) for v in grid + [(3, 0, 0)]) + struct.pack("<Biii", 3, 2, 9, 5)
    body += struct.pack("<i", len(strips)) + b"".join(struct.pack("<I", i & 0xFFFFFFFF) for i in strips)
    put("fuzz_ply", "tristrips_bin.ply", hdr.encode() + body)
    # STL: binary (one with a header starting with "solid", as many exporters write), ascii, and
    # a binary whose triangle count does not match its size
    def stl_binary(header, tris):
        out = header.ljust(80, b" ")[:80] + struct.pack("<I", len(tris))
        for t in tris:
            out += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *CUBE_V[i - 1]) for i in t)
            out += struct.pack("<H", 0)
        return out
    def stl_ascii(tris):
        s = "solid cube\n"
        for t in tris:
            s += "facet normal 0 0 0\n outer loop\n"
            s += "".join("  vertex %g %g %g\n" % CUBE_V[i - 1] for i in t)
            s += " endloop\nendfacet\n"
        return s + "endsolid cube\n"
    cube_tris = tri_fan(CUBE_F)
    put("fuzz_stl", "cube_bin.stl", stl_binary(b"binary STL of a unit cube", cube_tris))
    put("fuzz_stl", "cube_solid_header.stl", stl_binary(b"solid cube", cube_tris))
    put("fuzz_stl", "cube_ascii.stl", stl_ascii(cube_tris))
    put("fuzz_stl", "open_quad_ascii.stl", stl_ascii(tri_fan([(1, 2, 4, 3)])))
    put("fuzz_stl", "bad_count.stl", stl_binary(b"", cube_tris)[:84 + 50 * 3])
    put("fuzz_off", "coff.off", "COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n")
    put("fuzz_off", "bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n")
    put("fuzz_draco", "truncated.drc", open(os.path.join(corpus, "fuzz_draco", "cube_tags.drc"), "rb").read()[:40])
    # fuzz_mesh_api: [nv][nf][flags][weld] positions(3*nv codes) faces(size code + indices) tags
    def code(x): return int(x * 16) + 124
    def mesh_seed(vs, fs, flags, weld, tail=b""):
        b = bytes([len(vs), len(fs), flags, weld]) + bytes(code(c) for v in vs for c in v)
        size_code = {3: 0, 4: 4, 5: 8, 6: 9, 8: 15}
        for f in fs: b += bytes([size_code[len(f)]] + [i - 1 for i in f])
        return b + tail
    put("fuzz_mesh_api", "cube_quads", mesh_seed(CUBE_V, CUBE_F, 0x00, 0))
    put("fuzz_mesh_api", "cube_quads_tags", mesh_seed(CUBE_V, CUBE_F, 0xe1, 0, bytes([2, 1, 1, 0, 1, 20, 3, 7, 5, 7, 2])))
    put("fuzz_mesh_api", "cube_tris_weld", mesh_seed(CUBE_V, tri_fan(CUBE_F), 0x14, 0xff))
    put("fuzz_mesh_api", "nan_vertex", bytes([3, 1, 0, 0, 255, 124, 124, 140, 124, 124, 124, 140, 124, 0, 0, 1, 2]))
    # Known finding (see ubsan.supp): kept as a regression input, not in the smoke corpus.
    reg = os.path.join(here, "regressions", "fuzz_mesh_api"); os.makedirs(reg, exist_ok=True)
    with open(os.path.join(reg, "edge_map_null_offset"), "wb") as fh:
        fh.write(bytes([3, 1, 2, 0, 124, 124, 124, 140, 124, 124, 124, 140, 124, 0, 0, 1, 255]))
    shutil.rmtree(tmp)

main()
