#!/usr/bin/env python3
"""Vendors the small MotionBenchMaker subset the problem-set tests use.

Source: the `vamp-planner` source package on PyPI (0.6.4, Apache-2.0), `resources/panda/`
(Panda URDF + SRDF + OBJ collision meshes, from robowflex_resources / franka_ros) and
`resources/panda/problems.tar.bz2` (MotionBenchMaker's Panda problems).

    pip download --no-deps --no-binary :all: vamp-planner -d /tmp/vamp   # or fetch the sdist
    tar xzf /tmp/vamp/vamp_planner-0.6.4.tar.gz -C /tmp/vamp
    python3 tools/vendor_mbm_subset.py /tmp/vamp/vamp_planner-0.6.4 opengrasp-motion/tests/data/mbm

Writes `panda/panda.urdf`, `panda/panda.srdf`, `panda/meshes/collision/*.obj` (vertices
deduplicated and rounded to 0.01 mm, normals, texture coordinates and materials dropped: the
same triangles in about a third of the bytes) and the first `COUNT` problems of each set in
`SETS` as MoveIt YAML, unchanged. Standard library only.
"""
import shutil
import sys
import tarfile
from pathlib import Path

SETS = ["table_pick_panda", "cage_panda"]
COUNT = 5


def simplify_obj(src: Path, dst: Path) -> None:
    verts, index_of, remap, faces = [], {}, [], []
    for line in src.read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            key = tuple(f"{float(x):.5f}" for x in parts[1:4])
            if key not in index_of:
                index_of[key] = len(verts)
                verts.append(key)
            remap.append(index_of[key])
        elif parts[0] == "f":
            idx = [remap[int(p.split("/")[0]) - 1] for p in parts[1:]]
            for k in range(1, len(idx) - 1):
                tri = (idx[0], idx[k], idx[k + 1])
                if len(set(tri)) == 3:
                    faces.append(tri)
    out = [f"# {src.name} simplified by tools/vendor_mbm_subset.py"]
    out += ["v " + " ".join(v) for v in verts]
    out += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    dst.write_text("\n".join(out) + "\n")


def main(root: str, out: str) -> None:
    res, out = Path(root) / "resources" / "panda", Path(out)
    (out / "panda" / "meshes" / "collision").mkdir(parents=True, exist_ok=True)
    for name in ["panda.urdf", "panda.srdf"]:
        shutil.copy(res / name, out / "panda" / name)
    shutil.copy(Path(root) / "LICENSE.txt", out / "LICENSE-vamp.txt")
    for obj in sorted((res / "meshes" / "collision").glob("*.obj")):
        simplify_obj(obj, out / "panda" / "meshes" / "collision" / obj.name)
    with tarfile.open(res / "problems.tar.bz2", "r:bz2") as tar:
        for member in tar.getmembers():
            parts = member.name.split("/")
            if len(parts) != 3 or parts[1] not in SETS or not member.isfile():
                continue
            digits = "".join(c for c in parts[2] if c.isdigit())
            if not digits or not 1 <= int(digits) <= COUNT:
                continue
            dst = out / "panda" / "problems" / parts[1] / parts[2]
            dst.parent.mkdir(parents=True, exist_ok=True)
            dst.write_bytes(tar.extractfile(member).read())


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
