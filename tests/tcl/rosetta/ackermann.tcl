proc ack {m n} {
    if {$m == 0} { return [expr {$n + 1}] }
    if {$n == 0} { tailcall ack [expr {$m - 1}] 1 }
    tailcall ack [expr {$m - 1}] [ack $m [expr {$n - 1}]]
}
for {set m 0} {$m <= 3} {incr m} { puts [lmap n {0 1 2 3 4} { ack $m $n }] }
