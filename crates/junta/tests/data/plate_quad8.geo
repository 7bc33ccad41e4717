// a 4 x 2 plate, 8 x 4 quadrilaterals of second order (serendipity), for
// crates/junta/tests/readers.rs (2D Gmsh meshes); gmsh -2 plate_quad8.geo -o plate_quad8.msh (Gmsh 4.8.4)
Point(1) = {0, 0, 0};
Point(2) = {4, 0, 0};
Point(3) = {4, 2, 0};
Point(4) = {0, 2, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 9;
Transfinite Curve{2, 4} = 5;
Transfinite Surface{1};
Recombine Surface{1};
Physical Surface("plate") = {1};
Physical Curve("left") = {4};
Physical Curve("right") = {2};
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
