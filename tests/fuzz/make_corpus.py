#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes the committed seed corpus of the fuzz targets (tests/fuzz/corpus).

Hand-made edge cases of every format (deterministic), plus a few small real
meshes copied from ../shared/meshes when it is there (see corpus/README.md
for their sources and licences). Run from anywhere:

    python3 tests/fuzz/make_corpus.py [SHARED_MESHES_DIR]

The targets: obj, off, stl, ply (whole files), ply_le and ply_be (the file
after the "ply" and "format binary_*_endian 1.0" lines, which the target
prepends).
"""
import os
import shutil
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")
SHARED = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "..", "shared",
                                                             "meshes")


def put(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


TRI = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
CUBE_V = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
          (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
CUBE_F = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
CUBE_T = [t for q in CUBE_F for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]

# ------------------------------------------------------------------- OBJ
put("obj", "tri.obj", TRI + "f 1 2 3\n")
put("obj", "cube.obj", "".join("v %d %d %d\n" % v for v in CUBE_V) +
    "".join("f %d %d %d %d\n" % tuple(i + 1 for i in q) for q in CUBE_F))
put("obj", "forms.obj", TRI + "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
    "f 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/3/1\nf -3 -2 -1\n")
put("obj", "records.obj", "# comment\nmtllib x.mtl\no thing\ng group\ns off\nusemtl m\n" + TRI +
    "l 1 2\np 1\nt corner 1/0/0 1 1\nf 1 2 3\nfoo bar\n")
put("obj", "continuation.obj", "v 0 0 \\\n 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 3\n")
put("obj", "crlf.obj", TRI.replace("\n", "\r\n") + "f 1 2 3\r\n")
put("obj", "colors_w.obj", "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\nf 1 2 3\n")
put("obj", "forward_ref.obj", "f 1 2 3\n" + TRI)
put("obj", "repeat.obj", TRI + "v 1 1 0\nf 1 2 2 3\nf 1 2 1 4 3 4\nf 2 4 2\n")
put("obj", "duplicate.obj", TRI + "v 1 1 0\nf 1 2 3\nf 2 3 1\nf 3 2 1\nf 2 4 3\n")
put("obj", "nonmanifold.obj", TRI + "v 0 0 1\nv 0 0 -1\nf 1 2 3\nf 1 2 4\nf 2 1 5\n")
put("obj", "bad_index.obj", TRI + "f 1 2 4\n")
put("obj", "zero_index.obj", TRI + "f 0 1 2\n")
put("obj", "neg_index.obj", TRI + "f -1 -2 -4\n")
put("obj", "huge_index.obj", TRI + "f 1 2 99999999999\n")
put("obj", "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
put("obj", "inf.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n")
put("obj", "short_face.obj", TRI + "f 1 2\n")
put("obj", "points.obj", TRI)
put("obj", "empty_lines.obj", "\n\n   \n# only\n")
put("obj", "big_face.obj", "".join("v %d %d 0\n" % (i, i * i % 7) for i in range(40)) +
    "f " + " ".join(str(i + 1) for i in range(40)) + "\n")

# ------------------------------------------------------------------- OFF
put("off", "tri.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("off", "cube.off", "OFF\n8 6 12\n" + "".join("%d %d %d\n" % v for v in CUBE_V) +
    "".join("4 %d %d %d %d\n" % q for q in CUBE_F))
put("off", "coff.off", "COFF 3 1 # counts here\n0 0 0 255 0 0 255\n1 0 0 0 0 0 0\n\n"
    "0 1 0 1 1 1 1\n3 0 1 2 0.5 0.5 0.5\n")
put("off", "noff.off", "NOFF\n3 1\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n")
put("off", "stoff.off", "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n")
put("off", "crlf.off", "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n")
put("off", "trailing.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\nextra stuff\n")
put("off", "truncated.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n")
put("off", "huge_counts.off", "OFF\n100000000 100000000 0\n0 0 0\n")
put("off", "negative.off", "OFF\n-3 1 0\n")
put("off", "zero.off", "OFF\n0 0 0\n")
put("off", "bad_index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")
put("off", "repeat.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n4 0 1 1 2\n3 1 3 1\n")
put("off", "nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n")
put("off", "4off.off", "4OFF\n1 0 0\n0 0 0 0\n")

# ------------------------------------------------------------------- STL
def stl_ascii(tris, verts, name="seed", upper=False):
    out = ["solid %s" % name]
    for t in tris:
        out.append("  facet normal 0 0 0")
        out.append("    outer loop")
        for i in t:
            out.append("      vertex %g %g %g" % verts[i])
        out.append("    endloop")
        out.append("  endfacet")
    out.append("endsolid %s" % name)
    s = "\n".join(out) + "\n"
    return s.upper() if upper else s


def stl_binary(tris, verts, header=b"binary seed", count=None, extra=b""):
    b = header.ljust(80, b" ")[:80]
    b += struct.pack("<I", len(tris) if count is None else count)
    for t in tris:
        b += struct.pack("<3f", 0, 0, 0)
        for i in t:
            b += struct.pack("<3f", *verts[i])
        b += struct.pack("<H", 0)
    return b + extra


put("stl", "tri_ascii.stl", stl_ascii([(0, 1, 2)], [(0, 0, 0), (1, 0, 0), (0, 1, 0)]))
put("stl", "cube_ascii.stl", stl_ascii(CUBE_T, CUBE_V))
put("stl", "cube_upper.stl", stl_ascii(CUBE_T, CUBE_V, upper=True))
put("stl", "two_solids.stl", stl_ascii(CUBE_T[:6], CUBE_V, "a") + stl_ascii(CUBE_T[6:], CUBE_V, "b"))
put("stl", "quad_loop.stl", "solid q\nfacet normal nan nan nan\nouter loop\nvertex 0 0 0\n"
    "vertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid q\n")
put("stl", "no_normal.stl", "solid n\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
    "vertex 0 1 0\nendloop\nendfacet\nendsolid\n")
put("stl", "truncated_ascii.stl", stl_ascii(CUBE_T, CUBE_V)[:300])
put("stl", "no_endsolid.stl", stl_ascii(CUBE_T[:2], CUBE_V).replace("endsolid seed\n", ""))
put("stl", "cube_binary.stl", stl_binary(CUBE_T, CUBE_V))
put("stl", "cube_binary_solid.stl", stl_binary(CUBE_T, CUBE_V, header=b"solid but binary"))
put("stl", "binary_trailing.stl", stl_binary(CUBE_T, CUBE_V, extra=b"\0" * 7))
put("stl", "binary_truncated.stl", stl_binary(CUBE_T, CUBE_V)[:84 + 50 * 5 + 17])
put("stl", "binary_huge_count.stl", stl_binary(CUBE_T[:1], CUBE_V, count=0xfffffff0))
put("stl", "binary_zero.stl", stl_binary([], CUBE_V))
put("stl", "binary_degenerate.stl",
    stl_binary([(0, 1, 1), (0, 1, 2)], [(0, 0, 0), (1, 0, 0), (0, 1, 0)]))
put("stl", "binary_nan.stl", stl_binary([(0, 1, 2)], [(0, 0, 0), (float("nan"), 0, 0), (0, 1, 0)]))
put("stl", "binary_negzero.stl",
    stl_binary([(0, 1, 2), (3, 2, 1)], [(0.0, 0, 0), (1, 0, 0), (0, 1, 0), (-0.0, 1, 0)]))

# ------------------------------------------------------------------- PLY
XYZ = "property float x\nproperty float y\nproperty float z\n"
FACE = "element face %d\nproperty list uchar int vertex_indices\n"


def ply_ascii_cube(extra=""):
    return ("ply\nformat ascii 1.0\ncomment seed\nelement vertex 8\n" + XYZ + extra +
            FACE % 6 + "end_header\n" +
            "".join("%d %d %d%s\n" % (v + (" 0.5" if extra else "",)) for v in CUBE_V) +
            "".join("4 %d %d %d %d\n" % q for q in CUBE_F))


def ply_binary_body(big, props="float", count_type="uchar", index_type="int", colors=False,
                    strips=False, other=False):
    e = ">" if big else "<"
    fmt = {"float": "f", "double": "d", "int": "i", "short": "h", "uchar": "B", "char": "b",
           "uint": "I", "ushort": "H"}
    head = "element vertex 8\n" + "".join("property %s %s\n" % (props, c) for c in "xyz")
    if colors:
        head += "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    body = b""
    for v in CUBE_V:
        body += struct.pack(e + "3" + fmt[props], *v)
        if colors:
            body += bytes([200, 100, 50])
    if other:
        head += "element material 2\nproperty float shine\nproperty list uchar uchar tags\n"
        body += struct.pack(e + "fB", 0.5, 2) + bytes([1, 2]) + struct.pack(e + "fB", 1, 0)
    if strips:
        head += "element tristrips 1\nproperty list %s %s vertex_indices\n" % (count_type,
                                                                               index_type)
        strip = [0, 1, 3, 2, -1, 4, 5, 7, 6]
        body += struct.pack(e + fmt[count_type], len(strip))
        body += struct.pack(e + "%d%s" % (len(strip), fmt[index_type]), *strip)
    else:
        head += "element face 6\nproperty list %s %s vertex_indices\n" % (count_type, index_type)
        for q in CUBE_F:
            body += struct.pack(e + fmt[count_type], 4)
            body += struct.pack(e + "4" + fmt[index_type], *q)
    return (head + "end_header\n").encode() + body


put("ply", "cube_ascii.ply", ply_ascii_cube())
put("ply", "cube_ascii_extra.ply", ply_ascii_cube("property float confidence\n"))
put("ply", "ascii_colors.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + XYZ +
    "property uchar red\nproperty uchar green\nproperty uchar blue\n" + FACE % 1 +
    "end_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n")
put("ply", "ascii_tristrips.ply", "ply\nformat ascii 1.0\nelement vertex 4\n" + XYZ +
    "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n1 1 0\n6 0 1 2 3 -1 0\n")
put("ply", "ascii_truncated.ply", ply_ascii_cube()[:250])
put("ply", "ascii_huge.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\n" + XYZ +
    "end_header\n0 0 0\n")
put("ply", "header_only.ply", "ply\nformat ascii 1.0\nelement vertex 0\n" + XYZ + "end_header\n")
put("ply", "binary_le.ply", b"ply\nformat binary_little_endian 1.0\n" + ply_binary_body(False))
put("ply", "binary_be.ply", b"ply\nformat binary_big_endian 1.0\n" + ply_binary_body(True))
put("ply", "binary_le_names.ply", (b"ply\nformat binary_little_endian 1.0\n" +
    ply_binary_body(False).replace(b"property float", b"property float32")
    .replace(b"list uchar int", b"list uint8 int32")))
for big, target in ((False, "ply_le"), (True, "ply_be")):
    put(target, "cube.bin", ply_binary_body(big))
    put(target, "cube_double_uint.bin", ply_binary_body(big, "double", "uint", "uint"))
    put(target, "cube_colors.bin", ply_binary_body(big, colors=True))
    put(target, "cube_strips.bin", ply_binary_body(big, strips=True, count_type="int"))
    put(target, "cube_other.bin", ply_binary_body(big, "short", "ushort", "short", other=True))
    put(target, "truncated.bin", ply_binary_body(big)[:-9])
    put(target, "huge_face_count.bin", ply_binary_body(big).replace(b"element face 6",
                                                                    b"element face 9999999999"))

# ------------------------------------------- issues 11.4 and 18: odd text
BOM = "\ufeff"
put("obj", "bom.obj", BOM + TRI + "f 1 2 3\n")
put("obj", "cr_only.obj", (TRI + "f 1 2 3\n").replace("\n", "\r"))
put("obj", "cr_mixed.obj", "v 0 0 0\rv 1 0 0\r\nv 0 1 0\nf 1 2 3\r")
put("obj", "nul.obj", b"v 0 0 0\nv 1 0\x00 0\nv 0 1 0\nf 1 2 3\n")
put("obj", "zeros.obj", bytes(4096))
put("off", "bom.off", BOM + "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("off", "cr_only.off", "OFF\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r")
put("off", "ncoff_meshlab.off", "NCOFF\n3 1 0\n0 0 0 255 0 0 255 0 0 1 \n"
    "1 0 0 0 255 0 255 0 0 1 \n0 1 0 0 0 255 255 0 0 1 \n3 0 1 2 \n")
put("off", "stcnoff.off", "STCNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 1 0 0\n"
    "1 0 0 0 0 1 0 1 0 1 1 0\n0 1 0 0 0 1 0 0 1 1 0 1\n3 0 1 2\n")
put("off", "noff_dim3.off", "nOFF\n3\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
put("off", "noff_dim4.off", "nOFF\n4\n1 0 0\n0 0 0 0\n")
put("off", "two_faces_one_line.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
    "3 0 1 2 3 0 2 3\n")
put("off", "zeros.off", bytes(4096))
put("stl", "bom_ascii.stl", BOM + "solid b\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
    "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid b\n")
put("stl", "cr_only_ascii.stl", "solid c\rfacet normal 0 0 1\router loop\rvertex 0 0 0\r"
    "vertex 1 0 0\rvertex 0 1 0\rendloop\rendfacet\rendsolid c\r")
put("stl", "bom_binary.stl", stl_binary([(0, 1, 2)], [(0, 0, 0), (1, 0, 0), (0, 1, 0)],
                                        header=b"\xef\xbb\xbfsolid binary with a BOM"))
put("ply", "bom.ply", BOM + ply_ascii_cube())
put("ply", "cr_only.ply", ply_ascii_cube().replace("\n", "\r"))
put("ply", "dropped_props.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"
    "property float x\nproperty float y\nproperty float z\nproperty float confidence\n"
    "property float intensity\nproperty float nx\nproperty float u\nelement face 1\n"
    "property list uchar int vertex_indices\nend_header\n0 0 0 1 2 0 0\n1 0 0 1 2 0 0\n"
    "0 1 0 1 2 0 0\n3 0 1 2\n")

# ------------------------------------------------------------ shared meshes
REAL = [
    ("obj", "opensubdiv/catmark_cube.obj"),
    ("obj", "opensubdiv/catmark_nonman_edges.obj"),
    ("obj", "opensubdiv/loop_nonman_edges.obj"),
    ("obj", "opensubdiv/catmark_nonman_verts.obj"),
    ("obj", "small/spot_control_mesh.obj"),
    ("ply", "small/bun_zipper_res4.ply"),
    ("off", "small/decimated-knight.off"),
]
if os.path.isdir(SHARED):
    for target, rel in REAL:
        src = os.path.join(SHARED, rel)
        if os.path.exists(src):
            shutil.copyfile(src, os.path.join(CORPUS, target, "real_" + os.path.basename(rel)))
else:
    print("make_corpus: %s not found; real meshes not copied" % SHARED, file=sys.stderr)


def read_obj(path):
    verts, faces = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == "v":
            verts.append(tuple(float(x) for x in w[1:4]))
        elif w and w[0] == "f":
            faces.append([int(x.split("/")[0]) - 1 for x in w[1:]])
    return verts, faces


spot = os.path.join(SHARED, "small/spot_control_mesh.obj")
if os.path.exists(spot):
    verts, faces = read_obj(spot)
    tris = [(f[0], f[k], f[k + 1]) for f in faces for k in range(1, len(f) - 1)]
    put("stl", "real_spot_binary.stl", stl_binary(tris, verts, header=b"solid spot (binary)"))
    put("stl", "real_spot_ascii.stl", stl_ascii(tris, verts, "spot"))
