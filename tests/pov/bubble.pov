#include "wall.inc"
sphere { <0,0,0>, 1 pigment { rgbf <1,1,1,0.9> } finish { ambient 0 diffuse 0 } interior { ior 1.5 } }
sphere { <0,0,0>, 0.6 pigment { rgbf <1,1,1,1> } finish { ambient 0 diffuse 0 } interior { ior 1.0 } }
