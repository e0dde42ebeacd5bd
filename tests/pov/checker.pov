// POV-Ray's twin of checker.tsd.
#include "wall.inc"
plane { y, -1.02 pigment { checker rgb <0.9,0.8,0.2> rgb <0.2,0.3,0.8> scale 0.5 } finish { ambient 1 diffuse 0.7 } }
box { <-1.13,-0.97,-0.71>, <0.07,0.33,0.49>
  pigment { checker rgb <0.2,0.8,0.3> rgb <0.9,0.9,0.9> scale 0.3 } finish { ambient 1 diffuse 0.7 } }
