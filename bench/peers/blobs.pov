// Five Wyvill soft objects as bench/peers/blobs_whitted.json shows them, for
// POV-Ray 3.7 (an isosurface: POV-Ray's own blob uses another falloff).
// Kernel k(a) = 1 - 22/9 a^2 + 17/9 a^4 - 4/9 a^6 for a < 1, whose slope
// peaks at 1.5834; max_gradient is the sum of 1.5834 / R over the blobs,
// the field's true bound. POV-Ray is left-handed: the image is mirrored.
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera {
  location <0, 1, 6>
  look_at <0.2, 0.4, 0>
  right x * image_width / image_height
  angle 51.78
}
light_source { <4, 6, 5> color rgb <1, 1, 1> }
#declare Soft = function(a2) { select(a2 - 1, 1 + a2 * (-22/9 + a2 * (17/9 - a2 * 4/9)), 0) }
isosurface {
  function {
    0.3 - Soft((x*x + y*y + z*z) / (1.3*1.3))
        - Soft(((x-0.9)*(x-0.9) + (y-0.2)*(y-0.2) + (z-0.2)*(z-0.2)) / (1.1*1.1))
        - Soft(((x+0.6)*(x+0.6) + (y-0.9)*(y-0.9) + z*z) / (1.0*1.0))
        - Soft(((x-0.3)*(x-0.3) + (y-1.2)*(y-1.2) + (z+0.4)*(z+0.4)) / (0.9*0.9))
        - Soft(((x-0.2)*(x-0.2) + (y+0.6)*(y+0.6) + (z-0.7)*(z-0.7)) / (0.9*0.9))
  }
  contained_by { box { <-1.6, -1.5, -1.3>, <2.0, 2.1, 1.6> } }
  threshold 0
  max_gradient 7.759
  accuracy 0.0001
  pigment { color rgb <0.85, 0.75, 0.55> }
  finish { ambient 0 diffuse 1 }
}
