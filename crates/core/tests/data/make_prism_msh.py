#!/usr/bin/env python3
"""Write prism_stack_o1.msh and prism_stack_o2.msh (MSH 4.1 ASCII) with the
Gmsh Python API (`pip install gmsh`; files in the repo made with gmsh
4.15.2): the unit square meshed with triangles and extruded in z into two
volumes of wedges (z 0..0.5 "lower", 0.5..1 "upper", one layer each).
Physical surfaces: "bottom" (z = 0) and "top" (z = 1), triangles; "sides"
(the four lateral faces of both volumes), quadrangles; "mid" (z = 0.5),
triangles. Order 2 is the incomplete (serendipity) one: prism15, tri6,
quad8."""
import sys
import gmsh

for order in (1, 2):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("prism_stack")
    occ = gmsh.model.geo
    p = [occ.addPoint(x, y, 0, 0.5) for x, y in ((0, 0), (1, 0), (1, 1), (0, 1))]
    l = [occ.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]
    s = occ.addPlaneSurface([occ.addCurveLoop(l)])
    low = occ.extrude([(2, s)], 0, 0, 0.5, numElements=[1], recombine=True)
    # low: [top surface, volume, 4 lateral surfaces]
    up = occ.extrude([low[0]], 0, 0, 0.5, numElements=[1], recombine=True)
    occ.synchronize()
    gmsh.model.addPhysicalGroup(3, [low[1][1]], name="lower")
    gmsh.model.addPhysicalGroup(3, [up[1][1]], name="upper")
    gmsh.model.addPhysicalGroup(2, [s], name="bottom")
    gmsh.model.addPhysicalGroup(2, [up[0][1]], name="top")
    gmsh.model.addPhysicalGroup(2, [low[0][1]], name="mid")
    gmsh.model.addPhysicalGroup(2, [e[1] for e in low[2:] + up[2:]], name="sides")
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
    gmsh.model.mesh.generate(3)
    if order == 2:
        gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.write(f"prism_stack_o{order}.msh")
    gmsh.finalize()
