// GetDP steel-cup benchmark (scripts/bench_getdp.sh --case cup-linear | cup-bh): the magenc
// default magnet (R = 2 mm, L = 4 mm, centred at 0, axis z) in the steel cup of the steel_parts
// study (docs/studies/steel_parts.md): bore r = R on the magnet's curved face, wall and base
// w = 0.5 mm (r R..R+w, base z -L/2-w..-L/2), rim cup_top = 0.5 mm below the magnet's top face,
// touching the magnet; all in an air sphere of radius Rout (magenc's meshes/coarse.toml: 40 mm),
// meshed by gmsh with curved second-order tetrahedra. Sizes (mm) from the command line:
// gmsh -setnumber h_zone 0.4 -setnumber h_magnet 0.3 ... (defaults below).
// Regions: 1 magnet, 2 air, 3 outer sphere surface, 4 cup.
SetFactory("OpenCASCADE");
DefineConstant[ R = 2, L = 4, w = 0.5, cup_top = 0.5, Rout = 40, zs = 4.55 ];
DefineConstant[ h_magnet = 0.5, h_zone = 0.5, h_air = 12, zone_half = 7, zone_half_height = 1.3 ];
Cylinder(1) = {0, 0, -L / 2, 0, 0, L, R};
Cylinder(2) = {0, 0, -L / 2 - w, 0, 0, L + w - cup_top, R + w};
Cylinder(3) = {0, 0, -L / 2, 0, 0, L, R};           // the bore: the cup is (2) minus the magnet's volume
BooleanDifference(4) = { Volume{2}; Delete; }{ Volume{3}; Delete; };
Sphere(5) = {0, 0, 0, Rout};
BooleanFragments{ Volume{5}; Delete; }{ Volume{1, 4}; Delete; }
// Identify the three volumes by their bounding boxes (the fragments may renumber them).
vols[] = Volume{:};
mag[] = {}; cup[] = {}; air[] = {};
eps = 1e-3;
For i In {0 : #vols[] - 1}
  bb[] = BoundingBox Volume{vols[i]};
  If (bb[3] - bb[0] > Rout)
    air[] += vols[i];
  ElseIf (Fabs(bb[3] - R) < eps && Fabs(bb[2] + L / 2) < eps)
    mag[] += vols[i];
  Else
    cup[] += vols[i];
  EndIf
EndFor
If (#mag[] != 1 || #cup[] != 1 || #air[] != 1)
  Error("cup.geo: expected one magnet, one cup and one air volume, got %g, %g, %g", #mag[], #cup[], #air[]);
EndIf
Physical Volume(1) = {mag[]};
Physical Volume(2) = {air[]};
Physical Volume(4) = {cup[]};
outer[] = Boundary{ Volume{air[]}; };
sph[] = {};
For i In {0 : #outer[] - 1}
  bb[] = BoundingBox Surface{Abs(outer[i])};
  If (bb[3] - bb[0] > Rout)
    sph[] += Abs(outer[i]);
  EndIf
EndFor
Physical Surface(3) = {sph[]};
// Sizes: h_zone in the sensing-plane box, h_magnet in the magnet and the cup, growing to h_air.
Field[1] = Box;
Field[1].VIn = h_zone;  Field[1].VOut = h_air;
Field[1].XMin = -zone_half; Field[1].XMax = zone_half;
Field[1].YMin = -zone_half; Field[1].YMax = zone_half;
Field[1].ZMin = zs - zone_half_height; Field[1].ZMax = zs + zone_half_height;
Field[1].Thickness = 4;
Field[2] = Box;
Field[2].VIn = h_magnet; Field[2].VOut = h_air;
Field[2].XMin = -(R + w) * 1.02; Field[2].XMax = (R + w) * 1.02;
Field[2].YMin = -(R + w) * 1.02; Field[2].YMax = (R + w) * 1.02;
Field[2].ZMin = -L / 2 - w * 1.1; Field[2].ZMax = L / 2 + 0.05;
Field[2].Thickness = 4;
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
