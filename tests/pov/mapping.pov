// POV-Ray's twin of mapping.tsd: image_map map_type 1 and 2.
#version 3.7;
global_settings { assumed_gamma 1.0 ambient_light rgb <1,1,1> }
camera { perspective location <0,0.5,4> look_at <0,0,0> right -x*160/120 up y angle 40 }
background { rgb <0,0,0> }
// rayshell's `rotate 0 A 0`, in right-handed coordinates.
#macro TurnY(A) matrix <cos(radians(A)),0,-sin(radians(A)), 0,1,0, sin(radians(A)),0,cos(radians(A)), 0,0,0> #end
sphere { <0,0,0>, 0.7
  pigment { image_map { ppm "bands.ppm" map_type 1 } }
  finish { ambient 1 diffuse 0 }
  TurnY(60) translate <-0.75,0,0> }
cylinder { <0,0,0>, <0,1,0>, 0.6
  pigment { image_map { ppm "bands.ppm" map_type 2 } }
  finish { ambient 1 diffuse 0 }
  TurnY(-30) translate <0.75,-0.5,0> }
