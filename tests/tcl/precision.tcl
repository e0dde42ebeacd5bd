puts [info exists tcl_precision]
set one 1.0; set tenth 0.1; set small 1e-7; set big 2e20; set h 100; set odd 123456.789
foreach p {0 1 3 6 12 17} { set tcl_precision $p; puts "$p: [expr {$one/3}] [expr {$tenth*1}] [expr {$small*1}] [expr {$big/3}] [expr {$h*1.0}] [expr {$odd*1}] [expr {-$small*1e-300}]" }
proc f {} { global tcl_precision; set tcl_precision 4; return [expr {acos(-1)}] }
puts [f]
set tcl_precision 0
puts [catch {set tcl_precision 18} m]; puts $m
puts [catch {set tcl_precision abc} m]; puts $m
puts $tcl_precision
