set doors [lrepeat 101 0]
for {set pass 1} {$pass <= 100} {incr pass} {
    for {set d $pass} {$d <= 100} {incr d $pass} { lset doors $d [expr {![lindex $doors $d]}] }
}
puts [lmap d [lsearch -all $doors 1] { expr {$d} }]
