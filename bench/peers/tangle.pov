// Goursat's tangle as bench/peers/tangle_whitted.json shows it, for POV-Ray
// 3.7: the same camera (vertical 40 degrees = horizontal 51.78 at 4:3), box
// and point light. POV-Ray is left-handed, so the image is mirrored; the
// work per ray is the same. max_gradient is the true bound over the box:
// |d/dx (x^4 - 5x^2)| = |4x^3 - 10x| <= 37.5 on [-2.5, 2.5], times sqrt(3).
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera {
  location <4.5, 4.0, 6.5>
  look_at <0, 0, 0>
  right x * image_width / image_height
  angle 51.78
}
light_source { <5, 8, 6> color rgb <1, 1, 1> }
isosurface {
  function { x*x*x*x - 5*x*x + y*y*y*y - 5*y*y + z*z*z*z - 5*z*z + 11.8 }
  contained_by { box { <-2.5, -2.5, -2.5>, <2.5, 2.5, 2.5> } }
  threshold 0
  max_gradient 64.96
  accuracy 0.0001
  pigment { color rgb <0.8, 0.45, 0.2> }
  finish { ambient 0 diffuse 1 }
}
