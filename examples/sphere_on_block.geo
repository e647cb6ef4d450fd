// The lower quarter of an elastic hemisphere of radius R = 10 mm resting on the plane z = 0 at the origin
// (quarter model x, y >= 0): the sphere of examples/sphere_on_block.toml. Mesh size 0.25 mm (4 elements
// per contact radius a = 1 mm) within 1.5 mm of the origin, growing by 0.15 mm per mm to 2.5 mm.
SetFactory("OpenCASCADE");
R = 10;
Sphere(1) = {0, 0, R, R};
Box(2) = {0, 0, 0, R, R, R};
BooleanIntersection(3) = {Volume{1}; Delete;}{Volume{2}; Delete;};
e = 1e-6;
left() = Surface In BoundingBox{-e, -e, -e, e, R + e, R + e};
front() = Surface In BoundingBox{-e, -e, -e, R + e, e, R + e};
top() = Surface In BoundingBox{-e, -e, R - e, R + e, R + e, R + e};
bottom() = Abs(Boundary{Volume{3};});
bottom() -= left();
bottom() -= front();
bottom() -= top();
Physical Surface("left") = left();
Physical Surface("front") = front();
Physical Surface("top") = top();
Physical Surface("bottom") = bottom();
Physical Volume("sphere") = {3};
Field[1] = MathEval;
Field[1].F = "Min(Max(0.25, 0.25 + 0.15 * (Sqrt(x^2 + y^2 + z^2) - 1.5)), 2.5)";
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
