#include "wall.inc"
box { <-0.8,-0.8,-0.8>, <0.8,0.8,0.8>
  pigment { rgbf <1,1,1,0.9> } finish { ambient 0 diffuse 0 } interior { ior 1.5 }
  // rayshell's y then x rotation, in right-handed coordinates.
  matrix <cos(radians(35)),0,-sin(radians(35)), 0,1,0, sin(radians(35)),0,cos(radians(35)), 0,0,0>
  matrix <1,0,0, 0,cos(radians(25)),sin(radians(25)), 0,-sin(radians(25)),cos(radians(25)), 0,0,0> }
