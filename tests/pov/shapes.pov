// POV-Ray's twin of shapes.tsd: the same shapes, matte, on the backdrop.
#include "wall.inc"
#declare M = finish { ambient 1 diffuse 0.7 }
plane { y, -1 pigment { rgb <0.5,0.5,0.55> } finish { M } }
box { <-1.35,-1,-0.6>, <-0.85,-0.4,-0.1> pigment { rgb <0.9,0.3,0.2> } finish { M } }
cylinder { <-0.55,-1,-0.5>, <-0.55,0,-0.5>, 0.2 pigment { rgb <0.2,0.8,0.3> } finish { M } }
cone { <0,-1,-0.6>, 0.3, <0,0.2,-0.6>, 0 pigment { rgb <0.2,0.4,0.9> } finish { M } }
disc { <0.5,-0.3,0.3>, <0,0.6,0.8>, 0.25, 0.08 pigment { rgb <0.9,0.8,0.2> } finish { M } }
torus { 0.28, 0.09 pigment { rgb <0.8,0.3,0.8> } finish { M }
  matrix <1,0,0, 0,cos(radians(60)),sin(radians(60)), 0,-sin(radians(60)),cos(radians(60)), 0,0,0>
  translate <1.05,-0.5,-0.3> }
blob { threshold 0.5
  sphere { <0.9,-0.7,-1.4>, 0.45, 1 }
  sphere { <0.9,-0.2,-1.4>, 0.35, 1 }
  pigment { rgb <0.3,0.8,0.8> } finish { M } }
