#!/usr/bin/env python3
"""Writes the small stand-in meshes (and the Fetch-like robot) of this test workspace.

Every mesh referenced by a URDF below this folder (`package://NAME/...`, NAME found by its
package.xml) is written as a small tetrahedron: binary STL for .stl/.STL, COLLADA for .dae (two
<geometry> elements placed by two <node>s, one with <translate>, one with <matrix>, to exercise
multi-mesh documents). Run from this folder: python3 make_test_data.py
"""
import os, re, struct

HERE = os.path.dirname(os.path.abspath(__file__))

def box_tris(h, c=(0.0, 0.0, 0.0)):
    x, y, z = h
    v = [(sx * x + c[0], sy * y + c[1], sz * z + c[2]) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
             (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    return v, faces

def tetra(h):
    x, y, z = h
    return [(-x, -y, -z), (x, -y, -z), (0, y, -z), (0, 0, z)], [(0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3)]

def stl(h):
    v, f = tetra(h)
    out = b"stand-in box".ljust(80, b" ") + struct.pack("<I", len(f))
    for t in f:
        out += struct.pack("<3f", 0, 0, 0)
        for i in t:
            out += struct.pack("<3f", *v[i])
        out += b"\0\0"
    return out

def dae_geometry(gid, h):
    v, f = tetra(h)
    pos = " ".join("%g %g %g" % p for p in v)
    idx = " ".join("%d %d %d" % t for t in f)
    return f"""<geometry id="{gid}"><mesh>
<source id="{gid}-p"><float_array id="{gid}-a" count="12">{pos}</float_array>
<technique_common><accessor source="#{gid}-a" count="4" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="{gid}-v"><input semantic="POSITION" source="#{gid}-p"/></vertices>
<triangles count="4"><input semantic="VERTEX" source="#{gid}-v" offset="0"/><p>{idx}</p></triangles>
</mesh></geometry>"""

def dae(h, unit=1.0):
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="meter" meter="{unit}"/><up_axis>Z_UP</up_axis></asset>
<library_geometries>{dae_geometry("body", h)}{dae_geometry("cap", (h[0] / 2, h[1] / 2, h[2] / 4))}</library_geometries>
<library_visual_scenes><visual_scene id="scene">
<node id="n_body"><translate>0 0 0</translate><instance_geometry url="#body"/></node>
<node id="n_cap"><matrix>1 0 0 0 0 1 0 0 0 0 1 {h[2] * 1.25:g} 0 0 0 1</matrix><instance_geometry url="#cap"/></node>
</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
""".encode()

def packages():
    found = {}
    for root, dirs, files in os.walk(HERE):
        if "package.xml" in files:
            name = re.search(r"<name>\s*([^<\s]+)\s*</name>", open(os.path.join(root, "package.xml")).read()).group(1)
            found[name] = root
    return found

def main():
    pk = packages()
    refs = set()
    for root, _, files in os.walk(HERE):
        for f in files:
            if f.endswith((".urdf", ".xml")) and f != "package.xml":
                refs |= set(re.findall(r'filename="package://([^/"]+)/([^"]+)"', open(os.path.join(root, f)).read()))
    for name, rest in sorted(refs):
        if name not in pk:
            continue
        path = os.path.join(pk[name], rest)
        ext = os.path.splitext(path)[1].lower()
        if ext not in (".stl", ".dae"):
            continue
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as out:
            out.write(stl((0.02, 0.02, 0.02)) if ext == ".stl" else dae((0.02, 0.02, 0.02)))

if __name__ == "__main__":
    main()
