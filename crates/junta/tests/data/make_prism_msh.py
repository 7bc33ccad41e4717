#!/usr/bin/env python3
"""Write prism_stack_o1.msh, prism_stack_o2.msh, mixed_stack_o1.msh and
mixed_stack_o2.msh (MSH 4.1 ASCII) with the
Gmsh Python API (`pip install gmsh`; files in the repo made with gmsh
4.15.2): the unit square meshed with triangles and extruded in z into two
volumes of wedges (z 0..0.5 "lower", 0.5..1 "upper", one layer each).
Physical surfaces: "bottom" (z = 0) and "top" (z = 1), triangles; "sides"
(the four lateral faces of both volumes), quadrangles; "mid" (z = 0.5),
triangles. Order 2 is the incomplete (serendipity) one: prism15, tri6,
quad8. The mixed_stack files: the same, but the square's left half
(x < 0.5) in quadrangles, so each volume holds hexahedra (hex8 / hex20)
and wedges side by side and the surfaces mix quadrangles and
triangles."""
import sys
import gmsh

def build(order, mixed):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("prism_stack")
    occ = gmsh.model.geo
    if mixed:
        xs = ((0, 0), (0.5, 0), (1, 0), (1, 1), (0.5, 1), (0, 1))
        p = [occ.addPoint(x, y, 0, 0.5) for x, y in xs]
        l = [occ.addLine(p[i], p[(i + 1) % 6]) for i in range(6)]
        cut = occ.addLine(p[1], p[4])
        left = occ.addPlaneSurface([occ.addCurveLoop([l[0], cut, l[4], l[5]])])
        right = occ.addPlaneSurface([occ.addCurveLoop([l[1], l[2], l[3], -cut])])
        occ.mesh.setRecombine(2, left)
        surfaces = [left, right]
    else:
        p = [occ.addPoint(x, y, 0, 0.5) for x, y in ((0, 0), (1, 0), (1, 1), (0, 1))]
        l = [occ.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
        surfaces = [occ.addPlaneSurface([occ.addCurveLoop(l)])]
    lows, ups = [], []
    for s in surfaces:
        low = occ.extrude([(2, s)], 0, 0, 0.5, numElements=[1], recombine=True)
        # low: [top surface, volume, lateral surfaces]
        up = occ.extrude([low[0]], 0, 0, 0.5, numElements=[1], recombine=True)
        lows.append(low)
        ups.append(up)
    occ.synchronize()
    gmsh.model.addPhysicalGroup(3, [x[1][1] for x in lows], name="lower")
    gmsh.model.addPhysicalGroup(3, [x[1][1] for x in ups], name="upper")
    gmsh.model.addPhysicalGroup(2, surfaces, name="bottom")
    gmsh.model.addPhysicalGroup(2, [x[0][1] for x in ups], name="top")
    gmsh.model.addPhysicalGroup(2, [x[0][1] for x in lows], name="mid")
    # lateral faces on the outer boundary (not the internal cut x = 0.5)
    sides = []
    for x in lows + ups:
        for e in x[2:]:
            lo, hi = gmsh.model.getBoundingBox(2, e[1])[:3], gmsh.model.getBoundingBox(2, e[1])[3:]
            if not (abs(lo[0] - 0.5) < 1e-9 and abs(hi[0] - 0.5) < 1e-9):
                sides.append(e[1])
    gmsh.model.addPhysicalGroup(2, sides, name="sides")
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
    gmsh.model.mesh.generate(3)
    if order == 2:
        gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(f"{'mixed' if mixed else 'prism'}_stack_o{order}.msh")
    gmsh.finalize()


for mixed in (False, True):
    for order in (1, 2):
        build(order, mixed)
