"""Draws tests/inputs/dxf/bracket.dxf with ezdxf (pip install ezdxf), as a CAD
program would: a bracket outline made of LINEs, an ARC and an LWPOLYLINE
with a bulge, on several layers; a round hole (CIRCLE), a slot (a closed
POLYLINE with bulges), an open weld line (LWPOLYLINE) inside, and a TEXT
label. tests/inputs/dxf/bracket.json is the same domain typed by hand.

    python3 tests/inputs/dxf/bracket.py tests/inputs/dxf/bracket.dxf
"""
import math
import sys

import ezdxf

doc = ezdxf.new("R2010")
for name in ["fixed", "edge", "load", "bore", "slot", "weld"]:
    doc.layers.add(name)
msp = doc.modelspace()
# the outline, counter-clockwise from the origin, drawn in pieces
msp.add_line((0, 0), (40, 0), dxfattribs={"layer": "fixed"})
# bottom right, the right side and a rounded corner (a quarter circle)
msp.add_lwpolyline(
    [(40, 0, 0), (80, 0, 0), (80, 30, math.tan(math.pi / 8)), (60, 50, 0)],
    format="xyb",
    dxfattribs={"layer": "edge"},
)
# the top: a half circle round (30, 50)
msp.add_arc((30, 50), 30, 0, 180, dxfattribs={"layer": "load"})
# the left side, drawn downward
msp.add_line((0, 50), (0, 0), dxfattribs={"layer": "fixed"})
# a bore
msp.add_circle((30, 50), 8, dxfattribs={"layer": "bore"})
# a slot with round ends, as an old-style 2D POLYLINE
slot = msp.add_polyline2d(
    [(55, 12), (70, 12), (70, 20), (55, 20)], close=True, dxfattribs={"layer": "slot"}
)
for v, b in zip(slot.vertices, [0, 1, 0, 1]):
    v.dxf.bulge = b
# an open line inside
msp.add_lwpolyline([(10, 10), (25, 10), (25, 25)], dxfattribs={"layer": "weld"})
msp.add_text("bracket", dxfattribs={"layer": "0", "insert": (5, 40)})
doc.saveas(sys.argv[1])
