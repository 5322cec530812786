#!/usr/bin/env python3
"""Writes the pentagonal prism of tests/unit_mesh_files.cpp in every mesh format vktg reads.

The prism stands on the pentagon (1, 0), (0.5, 1), (-0.5, 1), (-1, 0), (0, -1.25) (counter-clockwise
seen from +z), from z = -0.5 to z = 0.75: vertices 0-4 at the bottom, 5-9 at the top, all
coordinates exact in binary. Faces in this order, every one counter-clockwise seen from outside:
top pentagon, bottom pentagon, then the five side quads. OBJ and PLY keep the polygons; glTF holds
their fans (v0, vi, vi+1), which is what the readers must produce. The PLY files carry properties
and elements the reader skips (colours, normals, an edge list, face flags, texture coordinates, a
trailing material element) in a different arrangement per file.
Run it from this directory; the output is committed, so tests do not need Python.
"""
import base64
import json
import struct

RING = [(1.0, 0.0), (0.5, 1.0), (-0.5, 1.0), (-1.0, 0.0), (0.0, -1.25)]
POSITIONS = [(x, y, -0.5) for x, y in RING] + [(x, y, 0.75) for x, y in RING]
FACES = [[5, 6, 7, 8, 9], [0, 4, 3, 2, 1]] + [[i, (i + 1) % 5, 5 + (i + 1) % 5, 5 + i] for i in range(5)]


def fans():
    return [(f[0], f[k], f[k + 1]) for f in FACES for k in range(1, len(f) - 1)]


def fmt(v):
    return "%g" % v


def write_obj():
    with open("prism.obj", "w", newline="\n") as out:
        out.write("# pentagonal prism (tests/data/meshes/make_prism.py)\nmtllib prism.mtl\no prism\n")
        for p in POSITIONS:
            out.write("v %s %s %s\n" % tuple(fmt(c) for c in p))
        out.write("vn 0 0 1\nvt 0 0\n")
        # The top as absolute indices with texture and normal; the bottom with relative indices.
        out.write("usemtl stone\nf %s\n" % " ".join("%d/1/1" % (i + 1) for i in FACES[0]))
        out.write("g bottom\nf %s\n" % " ".join(str(i - len(POSITIONS)) for i in FACES[1]))
        out.write("g sides\n")
        for f in FACES[2:]:
            out.write("f %s\n" % " ".join("%d//1" % (i + 1) for i in f))


def write_ascii_ply():
    with open("prism_ascii.ply", "w", newline="") as out:
        header = ["ply", "format ascii 1.0", "comment pentagonal prism (make_prism.py)", "obj_info CRLF header",
                  "element vertex 10", "property float x", "property uchar red", "property float y",
                  "property float z", "property float nx", "element edge 2", "property int vertex1",
                  "property int vertex2", "element face 7", "property uchar flags",
                  "property list uchar int vertex_indices", "property list uchar float texcoord", "end_header"]
        out.write("\r\n".join(header) + "\r\n")
        for i, (x, y, z) in enumerate(POSITIONS):
            out.write("%s %d %s %s 0.5\n" % (fmt(x), 10 * i, fmt(y), fmt(z)))
        out.write("0 1\n1 2\n")
        for f in FACES:
            out.write("1 %d %s 2 0.25 0.75\n" % (len(f), " ".join(map(str, f))))


def write_binary_ply(name, endian, coordinate, count_type, index_type):
    codes = {"float": "f", "double": "d", "uchar": "B", "ushort": "H", "int": "i", "uint": "I", "char": "b"}
    header = ["ply", "format %s 1.0" % ("binary_little_endian" if endian == "<" else "binary_big_endian"),
              "comment pentagonal prism (make_prism.py)", "element vertex 10",
              "property %s x" % coordinate, "property %s y" % coordinate, "property %s z" % coordinate,
              "property list uchar float weights", "element face 7",
              "property list %s %s vertex_index" % (count_type, index_type), "property char flag",
              "element material 1", "property float albedo", "end_header"]
    body = b""
    for i, p in enumerate(POSITIONS):
        body += struct.pack(endian + 3 * codes[coordinate], *p)
        body += struct.pack(endian + "B" + "f" * (i % 3), i % 3, *([0.5] * (i % 3)))
    for f in FACES:
        body += struct.pack(endian + codes[count_type] + codes[index_type] * len(f), len(f), *f)
        body += struct.pack(endian + "b", -1)
    body += struct.pack(endian + "f", 0.8)
    with open(name, "wb") as out:
        out.write(("\n".join(header) + "\n").encode("ascii") + body)


def write_gltf():
    triangles = fans()
    positions = b"".join(struct.pack("<3f", *p) for p in POSITIONS)
    indices = b"".join(struct.pack("<3H", *t) for t in triangles)
    data = positions + indices
    lo = [min(p[k] for p in POSITIONS) for k in range(3)]
    hi = [max(p[k] for p in POSITIONS) for k in range(3)]
    gltf = {
        "asset": {"version": "2.0", "generator": "tests/data/meshes/make_prism.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "prism"}],
        "meshes": [{"name": "prism", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(POSITIONS), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5123, "count": 3 * len(triangles), "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(positions)},
                        {"buffer": 0, "byteOffset": len(positions), "byteLength": len(indices)}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")}],
    }
    with open("prism.gltf", "w") as out:
        json.dump(gltf, out, indent=1)
        out.write("\n")


write_obj()
write_ascii_ply()
write_binary_ply("prism_le.ply", "<", "float", "uchar", "int")
write_binary_ply("prism_be.ply", ">", "double", "ushort", "uint")
write_gltf()
