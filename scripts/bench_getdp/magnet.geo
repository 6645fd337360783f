// GetDP benchmark (scripts/bench_getdp.sh): the magenc default magnet
// (docs/physics.md: R = 2 mm, L = 4 mm, centred at 0, axis z) in an air sphere of
// radius 60 mm, meshed by gmsh with curved second-order tetrahedra. Sizes (mm)
// come from the command line: gmsh -setnumber h_zone 0.3 ... (defaults below).
// Regions: 1 magnet, 2 air, 3 outer sphere surface.
SetFactory("OpenCASCADE");
DefineConstant[ R = 2, L = 4, Rout = 60, zs = 4.55 ];
DefineConstant[ h_magnet = 0.5, h_zone = 0.5, h_air = 12, zone_half = 7, zone_half_height = 1.3 ];
Cylinder(1) = {0, 0, -L / 2, 0, 0, L, R};
Sphere(2) = {0, 0, 0, Rout};
BooleanFragments{ Volume{2}; Delete; }{ Volume{1}; Delete; }
// After the fragments: the magnet keeps tag 1, the air (sphere minus magnet) is the other volume.
vols[] = Volume{:};
air[] = {};
For i In {0 : #vols[] - 1}
  If (vols[i] != 1)
    air[] += vols[i];
  EndIf
EndFor
Physical Volume(1) = {1};
Physical Volume(2) = {air[]};
outer[] = Boundary{ Volume{air[]}; };
sph[] = {};
For i In {0 : #outer[] - 1}
  bb[] = BoundingBox Surface{Abs(outer[i])};
  If (bb[3] - bb[0] > Rout)
    sph[] += Abs(outer[i]);
  EndIf
EndFor
Physical Surface(3) = {sph[]};
// Sizes: h_zone in the sensing-plane box, h_magnet in the magnet, growing to h_air.
Field[1] = Box;
Field[1].VIn = h_zone;  Field[1].VOut = h_air;
Field[1].XMin = -zone_half; Field[1].XMax = zone_half;
Field[1].YMin = -zone_half; Field[1].YMax = zone_half;
Field[1].ZMin = zs - zone_half_height; Field[1].ZMax = zs + zone_half_height;
Field[1].Thickness = 4;
Field[2] = Cylinder;
Field[2].Radius = R * 1.05; Field[2].ZAxis = L * 1.05; Field[2].ZCenter = 0;
Field[2].VIn = h_magnet; Field[2].VOut = h_air;
Field[3] = Min; Field[3].FieldsList = {1, 2};
Background Field = 3;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeMax = h_air;
Mesh.Algorithm3D = 1;       // Delaunay (HXT ignores the size field inside the air volume)
Mesh.ElementOrder = 2;      // curved P2: mid-edge nodes on the true surfaces
Mesh.SecondOrderLinear = 0;
Mesh.Binary = 1;
Mesh.MshFileVersion = 2.2;  // GetDP 3.2 without gmsh linked reads msh 2
