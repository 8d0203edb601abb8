"""Reads freemesh's outputs (.msh, .vtk, .inp) with meshio and prints what
it finds: points, cells by type, point and cell sets. A check by hand of
what the Rust tests cannot run (they do not depend on Python):

    pip install meshio
    freemesh mesh tests/inputs/dxf/bracket.dxf --size 2.5 --order 2 -o b.msh -o b.inp
    python3 tests/outside/read_with_meshio.py b.msh b.inp

meshio 5.3.5's Abaqus table has CPS4, S8R and S9R5 but no CPS8: the 8-node
plane stress type is added to it here (as quad8) so that the 8-node deck
reads too.
"""
import sys

import meshio
from meshio.abaqus import _abaqus

_abaqus.abaqus_to_meshio_type.setdefault("CPS8", "quad8")

for path in sys.argv[1:]:
    m = meshio.read(path)
    cells = ", ".join(f"{c.type} x{len(c.data)}" for c in m.cells)
    print(f"{path}: {len(m.points)} points; cells: {cells}")
    if m.point_sets:
        print("  point sets:", ", ".join(f"{k} ({len(v)})" for k, v in m.point_sets.items()))
    if m.cell_sets:
        sets = {k: sum(len(x) for x in v) for k, v in m.cell_sets.items()}
        print("  cell sets:", ", ".join(f"{k} ({n})" for k, n in sets.items() if not k.startswith("gmsh:")))
