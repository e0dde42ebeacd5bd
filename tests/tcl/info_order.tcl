proc p {a b} { set z 1; set y 2; set x 3; foreach q {1} {}; global tcl_version; puts [info locals]; puts [info vars]; set w 0; upvar 0 z zz; puts [info locals] }
p 1 2
set gz 1; set ga 2; set gm 3
puts [lsort [info globals g*]]
puts [info globals g*]
namespace eval ns { variable v1 1; variable v2 2; variable a 3 }
puts [info vars ns::*]
puts [info procs p]
