// The CSG scene of bench/peers/csg_whitted.json for POV-Ray 3.7, with its
// own analytic primitives (POV-Ray intersects spheres, tori and boxes in
// closed form; isotrace sphere traces them): a sphere minus a torus, a
// sphere intersected with a rounded box, a mirror sphere, one point light,
// two bounces. POV-Ray is left-handed: the image is mirrored.
#version 3.7;
#include "shapes.inc"
global_settings { assumed_gamma 1.0 max_trace_level 2 }
camera {
  location <0, 2.5, 7>
  look_at <0, 0, -0.5>
  right x * image_width / image_height
  angle 51.78
}
light_source { <3, 6, 5> color rgb <1, 1, 1> }
#declare Clay = texture { pigment { color rgb <0.8, 0.5, 0.4> } finish { ambient 0 diffuse 1 } }
difference {
  sphere { <-1.6, 0, 0>, 1 }
  torus { 1, 0.35 translate <-1.6, 0, 0> }
  texture { Clay }
}
intersection {
  sphere { <1.6, 0, 0>, 1.15 }
  object { Round_Box(<0.8, -0.8, -0.8>, <2.4, 0.8, 0.8>, 0.2, 0) }
  texture { Clay }
}
sphere {
  <0, 0.2, -2.2>, 0.9
  texture { pigment { color rgb <0, 0, 0> } finish { ambient 0 diffuse 0 reflection 1 } }
}
