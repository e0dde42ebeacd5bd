// POV-Ray's twin of csg.tsd.
#include "wall.inc"
#declare M = finish { ambient 1 diffuse 0.7 }
#macro Pair(X)
  box { <X-0.25,-0.25,-0.25>, <X+0.25,0.25,0.25> pigment { rgb <0.9,0.5,0.2> } finish { M } }
  sphere { <X+0.14,0.14,0.14>, 0.28 pigment { rgb <0.2,0.6,0.9> } finish { M } }
#end
union { Pair(-1.05) }
intersection { Pair(-0.35) }
difference { Pair(0.35) }
merge { Pair(1.05) }
