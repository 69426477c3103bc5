# SPDX-License-Identifier: GPL-3.0-or-later
"""How much the quad remesher's Table 6.1 figures move when the input is turned slightly.

The thesis reports one run per mesh (Table 6.1: fandisk 185 faces, 94 % quads, 76 % valence-4
vertices; rocker arm 431, 84 %, 86 %). The remesher's selection depends on the last digits of its
bending fits and element energies, so one run is one draw. This runs the Table 6.1 settings on the
mesh as given and on N - 1 copies turned by a random rotation of 0.1-2 degrees (fixed seed, the same
rotations every run) and prints each run and the mean / min / max of faces, quads % and valence-4 %,
and how many runs reach the thesis's shares.

Usage (library and bindings of a build):
    CAGEKIT_LIBRARY=build/sdk/capi/libcagekit.so PYTHONPATH=bindings/python \\
        /usr/bin/python3 tests/bench/table_six_one_spread.py [--runs N] [--passes P] MESH.obj...
Meshes are matched by file name: fandisk, rocker-arm (the shared meshes).
"""
import argparse
import math
import os
import statistics
import sys

import numpy as np

import cagekit

# Table 6.1 settings (regions, δ as a fraction of the diagonal, triangle / pentagon / T-joint
# weights) and the thesis's figures (faces, quads %, valence-4 %).
SETTINGS = {
    "fandisk": (dict(regions=30, edge_length=0.10, weights=(500, 500, 500)), (185, 94.0, 76.0)),
    "rocker-arm": (dict(regions=41, edge_length=0.06, weights=(20, 70, 70)), (431, 84.0, 86.0)),
}


def rotation(rng: np.random.Generator) -> np.ndarray:
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = math.radians(rng.uniform(0.1, 2.0))
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--passes", type=int, default=1, help="sample-count refinement passes (the default: 1)")
    parser.add_argument("meshes", nargs="+")
    args = parser.parse_args()
    for path in args.meshes:
        name = os.path.splitext(os.path.basename(path))[0]
        if name not in SETTINGS:
            print(f"{path}: no Table 6.1 settings for '{name}'", file=sys.stderr)
            return 2
        options, (faces, quads, valence4) = SETTINGS[name]
        mesh = cagekit.Mesh.read(path)
        positions = np.asarray(mesh.positions, dtype=float)
        face_list = [list(f) for f in mesh.faces]
        rng = np.random.default_rng(20261207)
        runs = []
        for k in range(args.runs):
            turn = np.eye(3) if k == 0 else rotation(rng)
            _, report = cagekit.remesh_quad(cagekit.Mesh.from_arrays(positions @ turn.T, face_list),
                                            refinement_passes=args.passes, **options)
            q = 100.0 * report.quads / report.faces
            v = 100.0 * report.valence4_vertices / report.interior_vertices
            runs.append((report.faces, q, v))
            print(f"{name} run {k}{' (as given)' if k == 0 else ''}: {report.faces} faces, quads {q:.1f} %, "
                  f"valence-4 {v:.1f} %", flush=True)
        for i, label, thesis in ((0, "faces", faces), (1, "quads %", quads), (2, "valence-4 %", valence4)):
            values = [r[i] for r in runs]
            reach = "" if i == 0 else f", >= the thesis's {thesis:.0f} in {sum(x >= thesis for x in values)} of {len(values)}"
            print(f"{name} {label}: mean {statistics.mean(values):.2f}, min {min(values):.2f}, "
                  f"max {max(values):.2f}{reach}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
