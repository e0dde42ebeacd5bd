#include "wall.inc"
sphere { <0,0,0>, 1 pigment { rgbf <1,0.2,0.2,0.9> } finish { ambient 0 diffuse 0 } interior { ior 1.5 } }
sphere { <1.3,1,-1.5>, 0.5 pigment { rgbf <0.3,0.9,0.3,0.8> } finish { ambient 0 diffuse 0 } interior { ior 1.2 } }
