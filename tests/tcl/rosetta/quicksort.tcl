proc quicksort {lst} {
    if {[llength $lst] <= 1} { return $lst }
    set pivot [lindex $lst 0]
    set less [lmap x [lrange $lst 1 end] { if {$x < $pivot} {set x} else continue }]
    set more [lmap x [lrange $lst 1 end] { if {$x >= $pivot} {set x} else continue }]
    concat [quicksort $less] [list $pivot] [quicksort $more]
}
proc bubble {lst} {
    set n [llength $lst]
    for {set i 0} {$i < $n} {incr i} {
        for {set j 0} {$j < $n - $i - 1} {incr j} {
            if {[lindex $lst $j] > [lindex $lst $j+1]} {
                set t [lindex $lst $j]; lset lst $j [lindex $lst $j+1]; lset lst $j+1 $t
            }
        }
    }
    return $lst
}
set data {33 4 1 -7 99 12 12 0 5.5 3e2 8}
puts [quicksort $data]
puts [bubble $data]
puts [lsort -real $data]
