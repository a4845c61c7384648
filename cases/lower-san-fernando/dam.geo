// lower-san-fernando: the maximum section of the Lower San Fernando Dam before the
// earthquake of 9 February 1971, simplified to straight zone boundaries. Coordinates in
// m: x from the dam axis, positive upstream (the project's runout runs towards +x, and
// the slide of 1971 ran upstream into the reservoir; the source model's x is −x here),
// y the elevation. Outline and zones after J. Montgomery's FLAC2D model of the dam
// (cases/lower-san-fernando/README.md, "Sources"); the alluvium's top is taken level at
// El. 307.7 on both sides (the model has 305.8 downstream). Regenerate dam.msh with
//
//   gmsh dam.geo -2 -format msh41 -o dam.msh
//
// Zones (physical surfaces, named as the case's materials):
//   us-fill-1 … us-fill-5  the upstream hydraulic-fill shell, in five layers (El. 307.7,
//                          311, 315, 318, 321, top 329.5–332.6)
//   core                   the hydraulic-fill clay core
//   ds-fill                the downstream hydraulic-fill shell
//   dikes                  the upstream and downstream starter dikes
//   cap                    the rolled fill and ground shale of the later raises
//   berm                   the 1940 downstream berm
//   alluvium               the foundation, El. 298 (rock) to 307.7

h = 4.0;   // Gmsh's triangle size; recombination and one subdivision halve it to ~2 m
hf = 8.0;  // towards the far ends of the foundation

// Foundation
Point(1) = {220, 298, 0, hf};
Point(2) = {-280, 298, 0, hf};
Point(3) = {-280, 307.7, 0, hf};
Point(4) = {220, 307.7, 0, hf};
// The dam's base on the foundation's top, upstream to downstream
Point(10) = {101.7, 307.7, 0, h};  // upstream toe
Point(11) = {93.1, 307.7, 0, h};   // upstream dike, inner edge
Point(12) = {20.0, 307.7, 0, h};   // core, upstream edge
Point(13) = {-20.0, 307.7, 0, h};    // core, downstream edge
Point(14) = {-98.2, 307.7, 0, h};    // downstream dike, inner edge
Point(15) = {-108.5, 307.7, 0, h};   // berm, inner edge
Point(16) = {-176.4, 307.7, 0, h};   // berm toe
// Upstream shell layers: on the dike's inner edge (−93.1, 307.7)–(−34, 332.6) and on the
// core's upstream edge (−20, 307.7)–(−9, 329.5)
Point(21) = {85.27, 311, 0, h};
Point(22) = {75.77, 315, 0, h};
Point(23) = {68.65, 318, 0, h};
Point(24) = {61.53, 321, 0, h};
Point(25) = {34.0, 332.6, 0, h};   // top of the upstream shell at the dike
Point(31) = {18.335, 311, 0, h};
Point(32) = {16.317, 315, 0, h};
Point(33) = {14.80, 318, 0, h};
Point(34) = {13.29, 321, 0, h};
Point(35) = {9.0, 329.5, 0, h};    // core top, upstream
Point(36) = {-9.0, 329.5, 0, h};     // core top, downstream
Point(37) = {-34.0, 332.6, 0, h};    // top of the downstream shell at the dike
// The outline above the shells
Point(40) = {39.72, 333.5, 0, h};  // upstream face at the dike's top
Point(41) = {32.5, 336.5, 0, h};   // upstream face, slope break
Point(42) = {4.8, 349.5, 0, h};    // crest, upstream edge
Point(43) = {-2.3, 349.5, 0, h};     // crest, downstream edge
Point(44) = {-32.5, 336.5, 0, h};    // downstream face, slope break
Point(45) = {-40.0, 333.5, 0, h};    // berm top, upstream end
Point(46) = {-46.0, 333.5, 0, h};    // berm top, downstream end

// Foundation
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 16};
Line(4) = {16, 15};
Line(5) = {15, 14};
Line(6) = {14, 13};
Line(7) = {13, 12};
Line(8) = {12, 11};
Line(9) = {11, 10};
Line(10) = {10, 4};
Line(11) = {4, 1};
// Upstream dike's inner edge, bottom to top
Line(21) = {11, 21};
Line(22) = {21, 22};
Line(23) = {22, 23};
Line(24) = {23, 24};
Line(25) = {24, 25};
// Core's upstream edge
Line(31) = {12, 31};
Line(32) = {31, 32};
Line(33) = {32, 33};
Line(34) = {33, 34};
Line(35) = {34, 35};
// Layer tops across the upstream shell
Line(41) = {21, 31};
Line(42) = {22, 32};
Line(43) = {23, 33};
Line(44) = {24, 34};
Line(45) = {35, 25};  // top of us-fill-5 (under the cap)
// Core
Line(50) = {13, 36};
Line(51) = {36, 35};  // core top
// Downstream shell and dike
Line(52) = {14, 37};
Line(53) = {37, 36};  // top of ds-fill (under the cap)
Line(54) = {37, 45};  // top of the downstream dike (under the cap)
Line(55) = {15, 45};  // berm / dike
// Upstream face and cap
Line(60) = {10, 40};  // upstream face (dike)
Line(61) = {40, 25};  // top of the upstream dike (under the cap)
Line(62) = {40, 41};
Line(63) = {41, 42};
Line(64) = {42, 43};  // crest
Line(65) = {43, 44};
Line(66) = {44, 45};
Line(67) = {45, 46};  // berm top
Line(68) = {46, 16};  // berm face

Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
Plane Surface(1) = {1};                       // alluvium
Curve Loop(2) = {-8, 31, -41, -21};
Plane Surface(2) = {2};                       // us-fill-1
Curve Loop(3) = {41, 32, -42, -22};
Plane Surface(3) = {3};                       // us-fill-2
Curve Loop(4) = {42, 33, -43, -23};
Plane Surface(4) = {4};                       // us-fill-3
Curve Loop(5) = {43, 34, -44, -24};
Plane Surface(5) = {5};                       // us-fill-4
Curve Loop(6) = {44, 35, 45, -25};
Plane Surface(6) = {6};                       // us-fill-5
Curve Loop(7) = {-7, 50, 51, -35, -34, -33, -32, -31};
Plane Surface(7) = {7};                       // core
Curve Loop(8) = {-6, 52, 53, -50};
Plane Surface(8) = {8};                       // ds-fill
Curve Loop(9) = {-9, 21, 22, 23, 24, 25, -61, -60};
Plane Surface(9) = {9};                       // upstream dike
Curve Loop(10) = {-5, 55, -54, -52};
Plane Surface(10) = {10};                     // downstream dike
Curve Loop(11) = {61, -45, -51, -53, 54, -66, -65, -64, -63, -62};
Plane Surface(11) = {11};                     // cap
Curve Loop(12) = {-4, -68, -67, -55};
Plane Surface(12) = {12};                     // berm

Physical Surface("alluvium") = {1};
Physical Surface("us-fill-1") = {2};
Physical Surface("us-fill-2") = {3};
Physical Surface("us-fill-3") = {4};
Physical Surface("us-fill-4") = {5};
Physical Surface("us-fill-5") = {6};
Physical Surface("core") = {7};
Physical Surface("ds-fill") = {8};
Physical Surface("dikes") = {9, 10};
Physical Surface("cap") = {11};
Physical Surface("berm") = {12};
Physical Curve("left") = {2};
Physical Curve("right") = {11};
Physical Curve("base") = {1};

// The free-field sides pair their nodes by elevation: both carry the same points.
Transfinite Curve{2, 11} = 4;

Mesh.RecombineAll = 1;
Mesh.SubdivisionAlgorithm = 1;
