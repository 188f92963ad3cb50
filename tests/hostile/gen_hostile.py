#!/usr/bin/env python3
"""Writes the hostile model files of tests/hostile/README.md into OUTDIR.

    python3 tests/hostile/gen_hostile.py OUTDIR

Each case is one file NN-short-name.ext (a model, or a JSON scene naming
one; plus the side files it names) and a line of OUTDIR/cases.tsv: file,
formats_needed (common: read with persp's default formats; all: only with
--formats all / PERSP_MODEL_FORMATS_ALL),
class (crash, memory, hang, leak, asan, noise, special) and what it does.
Python 3 standard library only; deterministic (the same bytes on every run);
about 30 MB in all, 10 MB of it the buffer of the shared-buffer case,
written here and never committed. The FIFO cases cannot live in a folder
git holds: tests/cli/test_hostile_models.sh makes them at run time.
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

CASES = []  # (file, formats, class, description)


def write(outdir, name, data):
    if isinstance(data, str):
        data = data.encode("ascii")
    path = os.path.join(outdir, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)


def case(outdir, name, data, formats, klass, description, side=()):
    """One case: the file, its side files [(name, bytes)], its manifest line."""
    assert "\t" not in description and "\n" not in description
    write(outdir, name, data)
    for side_name, side_data in side:
        write(outdir, side_name, side_data)
    CASES.append((name, formats, klass, description))


def gltf(doc):
    return json.dumps(doc, separators=(",", ":"), sort_keys=True)


def data_uri(raw):
    return "data:application/octet-stream;base64," + base64.b64encode(raw).decode("ascii")


TRIANGLE = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)


def gltf_triangle_parts():
    """A buffer, view, accessor and mesh of one triangle, embedded."""
    return {
        "buffers": [{"byteLength": len(TRIANGLE), "uri": data_uri(TRIANGLE)}],
        "bufferViews": [{"buffer": 0, "byteLength": len(TRIANGLE)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    }


COLLADA_HEAD = ('<?xml version="1.0" encoding="utf-8"?>\n'
                '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">\n'
                '<asset><unit meter="1"/><up_axis>Y_UP</up_axis></asset>\n')
COLLADA_TAIL = '<scene><instance_visual_scene url="#scene"/></scene>\n</COLLADA>\n'

# a triangle the COLLADA cases draw
COLLADA_TRIANGLE = (
    '<library_geometries><geometry id="tri"><mesh>\n'
    '<source id="pos"><float_array id="pos-array" count="9">0 0 0 1 0 0 0 1 0</float_array>\n'
    '<technique_common><accessor source="#pos-array" count="3" stride="%s">'
    '<param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>'
    '</accessor></technique_common></source>\n'
    '<vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>\n'
    '<triangles count="1"><input semantic="VERTEX" source="#verts" offset="0"/>'
    '<p>0 1 2</p></triangles>\n'
    '</mesh></geometry></library_geometries>\n')

FBX_ASCII_HEAD = ('; FBX 7.4.0 project file\n'
                  'FBXHeaderExtension:  {\n\tFBXHeaderVersion: 1003\n\tFBXVersion: 7400\n}\n'
                  'GlobalSettings:  {\n\tVersion: 1000\n}\n')


def fbx_model(uid, name):
    return '\tModel: %d, "Model::%s", "Null" {\n\t\tVersion: 232\n\t}\n' % (uid, name)


# ------------------------------------------------------------ binary writers

def fbx_binary(nodes):
    """A binary FBX 7.4 file of nodes [(name, [props], [children])]; a prop is
    (type char, value)."""
    out = bytearray(b"Kaydara FBX Binary  \x00\x1a\x00" + struct.pack("<I", 7400))

    def prop(t, v):
        if t == "I":
            return b"I" + struct.pack("<i", v)
        if t == "L":
            return b"L" + struct.pack("<q", v)
        if t == "D":
            return b"D" + struct.pack("<d", v)
        if t == "S":
            raw = v.encode("ascii") if isinstance(v, str) else v
            return b"S" + struct.pack("<I", len(raw)) + raw
        if t == "zi":  # int32s, deflated: (declared count, zlib bytes)
            count, raw = v
            return b"i" + struct.pack("<III", count, 1, len(raw)) + raw
        if t == "z":  # doubles, deflated: (declared count, zlib bytes)
            count, raw = v
            return b"d" + struct.pack("<III", count, 1, len(raw)) + raw
        if t in "di":
            fmt = "<%d%s" % (len(v), "d" if t == "d" else "i")
            raw = struct.pack(fmt, *v)
            return t.encode() + struct.pack("<III", len(v), 0, len(raw)) + raw
        raise ValueError(t)

    def node(start, name, props, children):
        body = b"".join(prop(t, v) for t, v in props)
        head_len = 13 + len(name)
        rec = bytearray()
        pos = start + head_len + len(body)
        kids = bytearray()
        for c in children:
            k = node(pos, *c)
            kids += k
            pos += len(k)
        if children:
            kids += b"\0" * 13
        end = start + head_len + len(body) + len(kids)
        rec += struct.pack("<IIIB", end, len(props), len(body), len(name)) + name.encode()
        rec += body + kids
        return rec

    for n in nodes:
        out += node(len(out), *n)
    out += b"\0" * 13
    return bytes(out)


def fbx_binary_triangle(vertices=None, indices=None):
    """A binary FBX of 40 copies of a triangle; vertices and indices replace
    the Vertices and PolygonVertexIndex properties, (type, value)."""
    vertices = vertices or ("d", [0.0, 0, 0, 1, 0, 0, 0, 1, 0] * 40)
    indices = indices or ("i", [0, 1, -3] * 40)
    return fbx_binary([
        ("FBXHeaderExtension", [], [("FBXHeaderVersion", [("I", 1003)], []),
                                    ("FBXVersion", [("I", 7400)], [])]),
        ("GlobalSettings", [], [("Version", [("I", 1000)], [])]),
        ("Objects", [], [
            ("Geometry", [("L", 100), ("S", b"tri\x00\x01Geometry"), ("S", "Mesh")],
             [("Vertices", [vertices], []),
              ("PolygonVertexIndex", [indices], [])]),
            ("Model", [("L", 200), ("S", b"tri\x00\x01Model"), ("S", "Mesh")],
             [("Version", [("I", 232)], [])]),
        ]),
        ("Connections", [], [("C", [("S", "OO"), ("L", 100), ("L", 200)], []),
                             ("C", [("S", "OO"), ("L", 200), ("L", 0)], [])]),
    ])


def png_header_only(width, height):
    """A PNG of the given size whose pixels are all zero: a few hundred bytes
    of deflate for 4 * width * height bytes of image."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    rows = zlib.compressobj(9)
    row = b"\0" * (1 + 4 * width)
    idat = b"".join(rows.compress(row) for _ in range(height)) + rows.flush()
    head = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head) + chunk(b"IDAT", idat) +
            chunk(b"IEND", b""))


# Assimp's SpatialSort direction, which persp's OBJ normals follow
# (src/model/obj_vertices.c): positions in a plane across it all sort
# together.
SORT_DIRECTION = (0.8523, 0.34321, 0.5736)


def grid_across_sort(k):
    """OBJ text: k*k positions 10 apart in the plane across SORT_DIRECTION,
    one triangle for every three, no normals."""
    n = SORT_DIRECTION
    length = math.sqrt(sum(c * c for c in n))
    n = [c / length for c in n]
    u = [n[1], -n[0], 0.0]
    length = math.sqrt(u[0] ** 2 + u[1] ** 2)
    u = [c / length for c in u]
    v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
    out = ["v %.4f %.4f %.4f\n" % tuple(10 * i * u[c] + 10 * j * v[c] for c in range(3))
           for i in range(k) for j in range(k)]
    out += ["f %d %d %d\n" % (t + 1, t + 2, t + 3) for t in range(0, k * k - 2, 3)]
    return "".join(out)


def chunk3ds(cid, *payload):
    body = b"".join(payload)
    return struct.pack("<HI", cid, 6 + len(body)) + body


def three_ds_quads(n):
    """A 3DS file of one mesh of n quads (2n triangles)."""
    verts = b"".join(struct.pack("<3f", i, y, 0) for i in range(n + 1) for y in (0, 1))
    faces = b"".join(struct.pack("<4H", 2 * i, 2 * i + 2, 2 * i + 1, 0) +
                     struct.pack("<4H", 2 * i + 1, 2 * i + 2, 2 * i + 3, 0) for i in range(n))
    mesh = chunk3ds(0x4100,
                    chunk3ds(0x4110, struct.pack("<H", 2 * (n + 1)), verts),
                    chunk3ds(0x4120, struct.pack("<H", 2 * n), faces))
    return chunk3ds(0x4D4D, chunk3ds(0x0002, struct.pack("<I", 3)),
                    chunk3ds(0x3D3D, chunk3ds(0x4000, b"strip\0", mesh)))


def glb(json_text, bin_data):
    j = json_text.encode("ascii")
    j += b" " * (-len(j) % 4)
    b = bin_data + b"\0" * (-len(bin_data) % 4)
    body = struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(b), b"BIN\0") + b
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


# ----------------------------------------------------------------- the cases

DEPTH = 20000
# Assimp 5.2's DirectX reader takes 40 000 nested frames on an 8 MiB stack
# (persp then refused the hierarchy as deeper than 256); 100 000 do not fit.
DEPTH_X = 100000


def generate(out):
    # --- deep nesting: every reader recurses once per level (stack) --------
    nodes = [{"children": [i + 1]} for i in range(DEPTH)] + [{"mesh": 0}]
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes}
    doc.update(gltf_triangle_parts())
    case(out, "01-deep-nodes.gltf", gltf(doc), "common", "crash",
         "glTF: a chain of %d nodes, each the only child of the one before" % DEPTH)

    body = "".join('<node id="n%d">' % i for i in range(DEPTH))
    body += '<instance_geometry url="#tri"/>' + "</node>" * DEPTH
    case(out, "02-deep-nodes.dae",
         COLLADA_HEAD + COLLADA_TRIANGLE % "3" +
         '<library_visual_scenes><visual_scene id="scene">\n' + body +
         '\n</visual_scene></library_visual_scenes>\n' + COLLADA_TAIL,
         "common", "crash", "COLLADA: <node> elements nested %d deep" % DEPTH)

    x = "xof 0303txt 0032\n" + "".join("Frame f%d {\n" % i for i in range(DEPTH_X))
    x += "Mesh m {\n3;\n0;0;0;,\n1;0;0;,\n0;1;0;;\n1;\n3;0,1,2;;\n}\n" + "}\n" * DEPTH_X
    case(out, "03-deep-frames.x", x, "all", "crash",
         "DirectX: Frame templates nested %d deep" % DEPTH_X)

    ac = ['AC3Db\nMATERIAL "m" rgb 1 1 1  amb 0.2 0.2 0.2  emis 0 0 0  spec 0 0 0  shi 10  '
          'trans 0\n'
          "OBJECT world\nkids 1\n"]
    ac += ["OBJECT group\nname \"g%d\"\nkids 1\n" % i for i in range(DEPTH)]
    ac.append("OBJECT poly\nnumvert 3\n0 0 0\n1 0 0\n0 1 0\nnumsurf 1\nSURF 0x10\nmat 0\nrefs 3\n"
              "0 0 0\n1 1 0\n2 0 1\nkids 0\n")
    case(out, "04-deep-kids.ac", "".join(ac), "all", "crash",
         "AC3D: OBJECTs nested %d deep through 'kids 1'" % DEPTH)

    fbx = [FBX_ASCII_HEAD, "Objects:  {\n"]
    fbx += [fbx_model(1000 + i, "m%d" % i) for i in range(DEPTH)]
    fbx.append("}\nConnections:  {\n\tC: \"OO\",1000,0\n")
    fbx += ['\tC: "OO",%d,%d\n' % (1001 + i, 1000 + i) for i in range(DEPTH - 1)]
    fbx.append("}\n")
    case(out, "05-deep-models.fbx", "".join(fbx), "common", "crash",
         "ASCII FBX: %d Models, each parented to the one before by an OO connection" % DEPTH)

    # --- cycles -------------------------------------------------------------
    case(out, "06-self-instance.dae",
         COLLADA_HEAD + COLLADA_TRIANGLE % "3" +
         '<library_nodes><node id="self" name="self"><instance_geometry url="#tri"/>'
         '<instance_node url="#self"/></node></library_nodes>\n'
         '<library_visual_scenes><visual_scene id="scene"><node id="top">'
         '<instance_node url="#self"/></node></visual_scene></library_visual_scenes>\n' +
         COLLADA_TAIL,
         "common", "crash",
         "COLLADA: a node that instances itself (<instance_node url=\"#self\"/>)")

    case(out, "07-self-parent.fbx",
         FBX_ASCII_HEAD + "Objects:  {\n" + fbx_model(1000, "self") + "}\n"
         'Connections:  {\n\tC: "OO",1000,0\n\tC: "OO",1000,1000\n}\n',
         "common", "crash", "ASCII FBX: a Model connected (OO) to the root and to itself")

    # --- out of range -------------------------------------------------------
    case(out, "08-huge-stride.dae",
         COLLADA_HEAD + COLLADA_TRIANGLE % "4000000000" +
         '<library_visual_scenes><visual_scene id="scene"><node id="n">'
         '<instance_geometry url="#tri"/></node></visual_scene></library_visual_scenes>\n' +
         COLLADA_TAIL,
         "common", "crash", "COLLADA: a position accessor with stride 4000000000 over 9 floats")

    ase_head = ('*3DSMAX_ASCIIEXPORT 200\n*SCENE {\n*SCENE_FILENAME "x"\n}\n'
                '*GEOMOBJECT {\n*NODE_NAME "m"\n*MESH {\n')
    case(out, "09-bad-index.ase",
         ase_head + "*MESH_NUMVERTEX 3\n*MESH_NUMFACES 1\n*MESH_VERTEX_LIST {\n"
         "*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 1 1 0 0\n*MESH_VERTEX 2 0 1 0\n}\n"
         "*MESH_FACE_LIST {\n*MESH_FACE 0: A: 0 B: 1 C: 1000000000 AB: 1 BC: 1 CA: 1\n}\n}\n}\n",
         "all", "crash", "ASE: a *MESH_FACE naming vertex 1000000000 of 3")

    md5_head = ('MD5Version 10\ncommandline ""\n\nnumJoints 1\nnumMeshes 1\n\n'
                'joints {\n\t"origin" -1 ( 0 0 0 ) ( 0 0 0 )\n}\n\n')
    case(out, "10-bad-index.md5mesh",
         md5_head + 'mesh {\n\tshader "s"\n\tnumverts 3\n'
         "\tvert 0 ( 0 0 ) 0 1\n\tvert 1 ( 0 0 ) 1 1\n\tvert 2 ( 0 0 ) 1000000000 1\n"
         "\tnumtris 1\n\ttri 0 0 1 2\n\tnumweights 2\n"
         "\tweight 0 0 1.0 ( 0 0 0 )\n\tweight 1 7 1.0 ( 1 0 0 )\n}\n",
         "all", "crash",
         "MD5 mesh: a vertex whose weights start at 1000000000 of 2, a weight on joint 7 of 1")

    ogex_mesh = ('Metric (key = "distance") {float {1.0}}\n'
                 'GeometryNode $node1 {Name {string {"n"}} ObjectRef {ref {$geometry1}}}\n'
                 'GeometryObject $geometry1 {\nMesh (primitive = "triangles") {\n'
                 'VertexArray (attrib = "position") '
                 '{float[3] {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}\n')
    case(out, "11-bad-index.ogex",
         ogex_mesh + "IndexArray {unsigned_int32[3] {{0, 1, 1000000000}}}\n}\n}\n",
         "all", "crash", "OpenGEX: an IndexArray naming vertex 1000000000 of 3")

    # --- tiny and truncated files ------------------------------------------
    # The scene's first line after the magic is taken for the version and
    # then read as an item: a Channel before any object is added to the
    # last object of an empty list.
    case(out, "12-tiny.lws", "LWSC\nChannel", "all", "crash",
         "LightWave scene: 12 bytes, a Channel before any object")
    full = ogex_mesh + "IndexArray {unsigned_int32[3] {{0, 1, 2}}}\n}\n}\n"
    cut = full.index("IndexArray") + len("IndexA")
    case(out, "13-truncated.ogex", full[:cut], "all", "hang",
         "OpenGEX: a mesh cut off after its vertex array, inside the word IndexArray "
         "(%d of %d bytes)" % (cut, len(full)))
    case(out, "14-tiny.ogex", 'Metric (key = "x") {', "all", "hang",
         "OpenGEX: 20 bytes, a Metric structure left open")

    # --- a few bytes declaring huge counts ----------------------------------
    case(out, "15-huge-mesh.x",
         "xof 0303txt 0032\nMesh m {\n1000000000;\n0;0;0;,\n1;0;0;,\n0;1;0;;\n1;\n3;0,1,2;;\n}\n",
         "all", "memory", "DirectX: a mesh declaring 10^9 vertices in a few bytes")
    case(out, "16-huge.nff", "tess 16\ns 0 0 0 1\n", "all", "memory",
         "NFF: a sphere tessellated 16 times (20*4^16 triangles)")
    case(out, "17-huge.ase",
         ase_head + "*MESH_NUMVERTEX 1000000000\n*MESH_NUMFACES 1000000000\n"
         "*MESH_NUMTVERTEX 1000000000\n*MESH_VERTEX_LIST {\n*MESH_VERTEX 0 0 0 0\n}\n}\n}\n",
         "all", "memory", "ASE: a mesh declaring 10^9 vertices, faces and texture coordinates")
    case(out, "18-huge-count.ply",
         "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "common", "memory", "PLY: element vertex 1000000000 in a few bytes")
    # 85899346 * 50 is 4 in 32 bits: Assimp's binary test (84 + 50n == size)
    # and its size check both pass for an 88-byte file
    case(out, "19-huge-count.stl",
         b"hostile".ljust(80, b" ") + struct.pack("<I", 85899346) + b"\0\0\0\0",
         "common", "memory",
         "binary STL: 88 bytes whose header says 85899346 triangles (x50 wraps to 4)")
    case(out, "20-huge-count.off", "OFF\n1000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "common", "memory", "OFF: a header declaring 10^9 vertices in a few bytes")
    case(out, "21-absurd-index.obj",
         "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4000000000\nf -99999999999 1 2\nf 1 2 0\n",
         "common", "noise",
         "OBJ (persp's reader): faces naming vertices 4000000000, -99999999999 and 0")

    # --- glTF amplification --------------------------------------------------
    nodes = [{"children": [i + 1, i + 1]} for i in range(24)] + [{"mesh": 0}]
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes}
    doc.update(gltf_triangle_parts())
    case(out, "22-dag-2pow24.gltf", gltf(doc), "common", "memory",
         "glTF: 24 nodes each naming the next twice as a child (2^24 instances)")

    n = 200000
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": list(range(n))}],
           "nodes": [{"mesh": 0, "name": "n%d" % i} for i in range(n)]}
    doc.update(gltf_triangle_parts())
    case(out, "23-many-nodes.gltf", gltf(doc), "common", "memory",
         "glTF: %d nodes, each drawing the mesh" % n)

    tris = 291271  # 10 MB of float positions, three vertices a triangle
    tri = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    big = tri * tris
    big += b"\0" * (10 * 2**20 - len(big))
    k = 300
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": list(range(k))}],
           "buffers": [{"uri": "24-shared-buffer.bin", "byteLength": len(big)}],
           "bufferViews": [{"buffer": 0, "byteLength": len(big)}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3 * tris,
                          "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]} for _ in range(k)],
           "meshes": [{"primitives": [{"attributes": {"POSITION": i}}]} for i in range(k)],
           "nodes": [{"mesh": i} for i in range(k)]}
    case(out, "24-shared-buffer.gltf", gltf(doc), "common", "memory",
         "glTF: one 10 MB buffer (24-shared-buffer.bin) read through %d accessors and meshes" % k,
         side=[("24-shared-buffer.bin", big)])

    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0}]}
    doc.update(gltf_triangle_parts())
    doc["buffers"] = [{"uri": "25-short-buffer.bin", "byteLength": len(TRIANGLE) + 1}]
    case(out, "25-short-buffer.gltf", gltf(doc), "common", "leak",
         "glTF: a buffer whose byteLength is one byte more than its file 25-short-buffer.bin",
         side=[("25-short-buffer.bin", TRIANGLE)])

    sparse = struct.pack("<3I", 0, 1, 2) + TRIANGLE
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0}],
           "buffers": [{"byteLength": len(sparse), "uri": data_uri(sparse)}],
           "bufferViews": [{"buffer": 0, "byteLength": 12},
                           {"buffer": 0, "byteOffset": 12, "byteLength": 36}],
           "accessors": [{"componentType": 5126, "count": 100000000, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0],
                          "sparse": {"count": 100000000,
                                     "indices": {"bufferView": 0, "componentType": 5125},
                                     "values": {"bufferView": 1}}}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]}
    case(out, "26-sparse-huge.gltf", gltf(doc), "common", "memory",
         "glTF: a sparse accessor of count 10^8 over 3 stored indices and values")

    # --- blame ----------------------------------------------------------------
    case(out, "27-no-anim.md5mesh", md5_head + "mesh {\n\tshader \"s\"\n\tnumverts 0\n}\n",
         "all", "noise",
         "MD5 mesh: broken (no vertices), with no .md5anim beside it: the mesh is to blame")

    # --- truncated binary files ---------------------------------------------
    tri_doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
               "nodes": [{"mesh": 0}], "buffers": [{"byteLength": len(TRIANGLE)}],
               "bufferViews": [{"buffer": 0, "byteLength": len(TRIANGLE)}],
               "accessors": gltf_triangle_parts()["accessors"],
               "meshes": gltf_triangle_parts()["meshes"]}
    whole = glb(gltf(tri_doc), TRIANGLE)
    json_len = struct.unpack("<I", whole[12:16])[0]
    case(out, "28-cut-json.glb", whole[:20 + json_len // 2], "common", "noise",
         "binary glTF cut in the middle of its JSON chunk")
    case(out, "29-cut-bin.glb", whole[:20 + json_len + 8 + 18], "common", "noise",
         "binary glTF cut in the middle of its BIN chunk")
    # Cut where Assimp 5.2 reads it: a file cut anywhere is refused by its
    # tokenizer (every record's end offset is checked against the file), so
    # the records stay whole and the cut is inside the deflated data of the
    # Vertices array, whose header declares 3 * 2^26 doubles (1.5 GiB): a
    # zlib stream of one stored block, written by hand (the same bytes with
    # any zlib), cut in the middle of its data.
    raw = struct.pack("<9d", 0, 0, 0, 1, 0, 0, 0, 1, 0) * 40
    stream = b"\x78\x01\x00" + struct.pack("<HH", len(raw), len(raw) ^ 0xFFFF)
    stream += raw[:len(raw) // 2]
    case(out, "30-cut.fbx", fbx_binary_triangle(("z", (3 << 26, stream))), "common", "memory",
         "binary FBX whose deflated Vertices array is cut short and declares 3*2^26 doubles "
         "(1.5 GiB)")
    ply = (b"ply\nformat binary_little_endian 1.0\nelement vertex 300\nproperty float x\n"
           b"property float y\nproperty float z\nelement face 299\n"
           b"property list uchar int vertex_indices\nend_header\n")
    ply += b"".join(struct.pack("<3f", i, i % 2, 0) for i in range(300))
    ply += b"".join(struct.pack("<B3i", 3, i, i + 1, i + 2) for i in range(298))
    ply += struct.pack("<B", 3)
    case(out, "31-cut.ply", ply, "common", "noise",
         "binary PLY cut inside its last face")
    tds = three_ds_quads(200)
    case(out, "32-cut.3ds", tds[:len(tds) * 2 // 3], "common", "noise",
         "3DS cut two thirds of the way through its vertex list")

    # --- work that grows with the square of the file (persp's own code) ----
    n = 100000
    case(out, "33-fan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + "f 1 2 3\n" * n, "common", "hang",
         "OBJ (persp's reader): %d copies of one triangle without normals: the normal of each "
         "corner sums the faces of every other at its place" % n)
    k = 300
    case(out, "34-grid-across.obj", grid_across_sort(k), "common", "hang",
         "OBJ (persp's reader): %dx%d positions in the plane across the direction the normals' "
         "scan sorts by, so that each scans all" % (k, k))
    n = 100000
    mtl = "".join("newmtl m%d\nKd 1 1 1\n" % i for i in range(n))
    case(out, "35-many-materials.obj",
         "mtllib 35-many-materials.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
         "usemtl m%d\nf 1 2 3\nf 1 2 4\n" % (n - 1),
         "common", "hang",
         "OBJ (persp's reader): a material library of %d materials, each looked up among those "
         "before it, then a face out of range" % n,
         side=[("35-many-materials.mtl", mtl)])
    n = 1000
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0}]}
    doc.update(gltf_triangle_parts())
    scene = {"camera": {"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 60},
             "objects": [{"name": "o%d" % i, "mesh": {"file": "36-one.gltf"}} for i in range(n)]}
    case(out, "36-scene-1000.json", json.dumps(scene), "common", "hang",
         "a JSON scene naming a one-triangle glTF (36-one.gltf) %d times: an import each" % n,
         side=[("36-one.gltf", gltf(doc))])

    # --- memory: refused, saying how much ------------------------------------
    n = 700000
    faces = zlib.compress(struct.pack("<3i", 0, 1, -3) * n, 9)
    one_triangle = ("d", [0.0, 0, 0, 1, 0, 0, 0, 1, 0])
    case(out, "37-tiny-huge-mesh.fbx", fbx_binary_triangle(one_triangle, ("zi", (3 * n, faces))),
         "common", "memory",
         "binary FBX of %d KB whose deflated PolygonVertexIndex makes %d triangles without "
         "normals, which persp makes under the budget" % (len(faces) // 1024 + 1, n))
    case(out, "38-png-bomb.obj", "mtllib 38-png-bomb.mtl\n" + "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
         "vt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n", "common", "memory",
         "OBJ whose texture 38-png-bomb.png is 8192x8192 (256 MiB decoded) in 260 KB",
         side=[("38-png-bomb.mtl", "newmtl m\nmap_Kd 38-png-bomb.png\n"),
               ("38-png-bomb.png", png_header_only(8192, 8192))])
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0}]}
    doc.update(gltf_triangle_parts())
    doc["buffers"] = [{"uri": "/etc/passwd", "byteLength": len(TRIANGLE)}]
    case(out, "39-buffer-abs.gltf", gltf(doc), "common", "special",
         "glTF whose buffer uri is an absolute path outside its folder (/etc/passwd)")
    whole = glb(gltf(tri_doc), TRIANGLE)
    at = 20 + struct.unpack("<I", whole[12:16])[0]
    case(out, "40-glb-chunk-past-end.glb",
         whole[:at] + struct.pack("<I", 0x7FFFFFF0) + whole[at + 4:], "common", "noise",
         "binary glTF whose BIN chunk declares 2 GiB, the header the file's true length")

    # --- warnings of a load that then fails; folders read whole -------------
    t, f = 20000, 5000
    obj = ["mtllib 41-many-textures.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n"]
    obj += ["usemtl m%d\nf 1/1 2/1 3/1\n" % i for i in range(t)]
    obj.append("f 1 2 9\n")
    case(out, "41-many-textures.obj", "".join(obj), "common", "hang",
         "OBJ whose %d materials name textures missing from 41-folder/, which holds %d empty "
         "files, then a face out of range" % (t, f),
         side=[("41-many-textures.mtl",
                "".join("newmtl m%d\nmap_Kd 41-folder/missing%d.png\n" % (i, i)
                        for i in range(t)))] +
              [("41-folder/f%04d" % i, b"") for i in range(f)])
    case(out, "42-warned-then-bad.obj",
         "mtllib 42-missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n", "common", "noise",
         "OBJ naming a material library that is not there (a warning), then a face out of range")


def main():
    if len(sys.argv) != 2:
        sys.stderr.write("usage: gen_hostile.py OUTDIR\n")
        return 2
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    generate(out)
    with open(os.path.join(out, "cases.tsv"), "w") as f:
        f.write("file\tformats_needed\tclass\tdescription\n")
        for row in CASES:
            f.write("\t".join(row) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
