// Box [0,2]x[0,1]x[0,1], 2x1x1 hex20 (serendipity) elements: gmsh -3 box_hex20.geo -o box_hex20.msh -format msh41
SetFactory("Built-in");
Point(1) = {0,0,0,1};
l[] = Extrude {2,0,0} { Point{1}; Layers{2}; };
s[] = Extrude {0,1,0} { Line{l[1]}; Layers{1}; Recombine; };
v[] = Extrude {0,0,1} { Surface{s[1]}; Layers{1}; Recombine; };
Physical Volume("solid") = {v[1]};
Physical Surface("bottom") = {s[1]};
Physical Surface("top") = {v[0]};
Physical Point("origin") = {1};
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
