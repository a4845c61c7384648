// slope-gmsh: a 10 m high 2H:1V slope of soft cohesive soil on a stiff, strong
// foundation layer, meshed by Gmsh in quadrangles only. Regenerate slope.msh with
//
//   gmsh slope.geo -2 -format msh41 -o slope.msh
//
// (cases/slope-gmsh/README.md: the physical groups the case file names, and why these
// mesh options). Lengths in m; x to the right, y up, the base at y = 0.
//
//   15 4------------3
//      |  "soil"      \  2H:1V face
//    5 5---------------2----------------------------- 7
//      |  "foundation"                                |
//    0 1--------------------------------------------- 6
//      0           (20)  40                          100

h = 2.0;  // the target size of Gmsh's triangles; the last subdivision halves it to 1 m

Point(1) = {0, 0, 0, h};
Point(2) = {40, 5, 0, h};   // the toe
Point(3) = {20, 15, 0, h};  // the crest's edge
Point(4) = {0, 15, 0, h};
Point(5) = {0, 5, 0, h};
Point(6) = {100, 0, 0, h};
Point(7) = {100, 5, 0, h};

Line(1) = {5, 2};   // the interface soil / foundation
Line(2) = {2, 3};   // the slope face
Line(3) = {3, 4};   // the crest
Line(4) = {4, 5};   // the wall, in the soil
Line(5) = {1, 6};   // the base
Line(6) = {6, 7};   // the foundation's far end
Line(7) = {7, 2};   // the foundation's free top
Line(8) = {5, 1};   // the wall, in the foundation

// Both loops counter-clockwise, so that Gmsh orients the elements as the solver does.
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -1, 8};
Plane Surface(2) = {2};

// One 2-D group per material, named as in case.toml's [[materials]].
Physical Surface("soil") = {1};
Physical Surface("foundation") = {2};
// One 1-D group per boundary the case's boundary tables name; each straight (one
// outward normal), the wall's two pieces together.
Physical Curve("left") = {4, 8};
Physical Curve("right") = {6};
Physical Curve("base") = {5};

// Quadrangles only (cases/README.md, "Meshes from Gmsh"): Gmsh's default triangulation
// (Frontal-Delaunay), the recombination of its triangles in pairs, then one subdivision
// that splits every element left, quadrangle or triangle, into quadrangles. (Not
// Mesh.Algorithm = 8, Frontal-Delaunay for quads: Debian 12's Gmsh 4.8.4 crashes on it.)
Mesh.RecombineAll = 1;
Mesh.SubdivisionAlgorithm = 1;
